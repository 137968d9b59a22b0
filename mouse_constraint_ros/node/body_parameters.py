# Copyright 2026 The mouse_constraint_ros Authors
#
# Licensed under the Apache License, Version 2.0 (the "License");
# you may not use this file except in compliance with the License.
# You may obtain a copy of the License at
#
#     http://www.apache.org/licenses/LICENSE-2.0
#
# Unless required by applicable law or agreed to in writing, software
# distributed under the License is distributed on an "AS IS" BASIS,
# WITHOUT WARRANTIES OR CONDITIONS OF ANY KIND, either express or implied.
# See the License for the specific language governing permissions and
# limitations under the License.

"""
The body's parameters: a URDF link (``robot_description``) or a box; no ROS here.

``body_from`` gives the physics' body and the link's geometry. With ``robot_description`` the
body is ``body_link`` of the URDF (``description.urdf_link``): the published pose, TF and the
``anchor`` and ``initial_position`` parameters are of the link frame, which the physics moves to
the COM (``physics.body_frame``). Without it, the body is the box of ``box_size``, ``mass`` and
``inertia``, whose frame is at its COM.
"""

from typing import Any, Callable, Mapping, NamedTuple, Optional, Tuple

from ..description import BodyGeometry
from ..physics import RigidBody
from ..physics.body_frame import BodyFrame
from ..physics.validation import finite_vector, scalar, shown

# The densest material a body is made of (kg/m^3): osmium's is 22 590.
MAX_DENSITY = 25000.0

# (name, default, description, bounds), as ``parameters.ParameterSpec`` takes them.
BODY_PARAMETERS: Tuple[tuple, ...] = (
    ('robot_description', '',
     'URDF of the body (XML text; the launch file reads urdf:=path into it). Mass, inertia and '
     "COM from the link's <inertial>, grab and floor by its <collision> pieces, drawn by its "
     '<visual> ones; pose, TF, anchor and initial_position are of the link frame. Empty: the '
     'box of box_size, mass and inertia.', None),
    ('robot_description_file', '',
     'The file robot_description was read from (urdf:= and make run URDF= set it): mesh paths '
     'relative to it resolve against its directory; with robot_description empty, the node '
     'reads it. Read at start.', None),
    ('body_link', '',
     "The URDF link that is the body; empty: the URDF's only link.", None),
    ('density', 0.0,
     f'kg/m^3, up to {MAX_DENSITY:g}: a link without <inertial> gets mass and inertia from its '
     'collision pieces at this density; 0 = such a link is refused.', (0.0, MAX_DENSITY)),
)


class Body(NamedTuple):
    """What the body parameters make: the physics' body, its geometry, what messages call it."""

    body: RigidBody
    geometry: BodyGeometry
    frame: BodyFrame
    name: str


# Loads the body of (robot_description, body_link, density): ``description.body_model``'s.
BodyLoader = Callable[[str, str, float], Any]


def load_body(description: str, link: str, density: float):
    """Return ``description.body_model`` of the URDF text, its link and density."""
    # The parser and trimesh load with the first URDF: the box body runs without them.
    from ..description import urdf_link
    return urdf_link.body_model(description, link, density=density)


def body_from(values: Mapping[str, Any], load: Optional[BodyLoader] = None) -> Body:
    """
    Return the body of parameter ``values``; raise ValueError naming the parameter.

    :param load: loads the URDF link's body (``load_body`` when None; the node keeps the one it
        loaded, see ``body_loads``).
    """
    description = values['robot_description']
    if not isinstance(description, str):
        raise ValueError(f'robot_description must be a string, got {shown(description)}')
    link = values['body_link']
    if not isinstance(link, str):
        raise ValueError(f'body_link must be a string, got {shown(link)}')
    density = scalar('density', values['density'], at_least=0.0, at_most=MAX_DENSITY)
    if not description:
        if link:
            raise ValueError(f'body_link {link!r} needs robot_description (a URDF) to name')
        return _box(values)
    model = (load or load_body)(description, link, density)
    geometry = model.geometry
    return Body(model.rigid_body(), geometry, BodyFrame(geometry.com),
                f'link {geometry.link!r} of mass')


# What a process beside the node reads of its parameters to know the body's shape.
GEOMETRY_PARAMETERS = ('robot_description', 'body_link', 'density', 'box_size')


def geometry_from(values: Mapping[str, Any]) -> BodyGeometry:
    """
    Return the body's shape of the node's parameter ``values`` (``GEOMETRY_PARAMETERS``).

    What the view, the marker, the recorder and ``mouse_target`` draw and grab by: the URDF
    link's geometry, or the box of ``box_size``. Raise ValueError as the node would.
    """
    if not values['robot_description']:
        return BodyGeometry.box(finite_vector('box_size', values['box_size']))
    from ..description.urdf_link import body_model
    return body_model(values['robot_description'], values['body_link'],
                      density=values['density']).geometry


def _box(values: Mapping[str, Any]) -> Body:
    """Return the box body of ``box_size``, ``mass`` and ``inertia``."""
    box_size = finite_vector('box_size', values['box_size'])
    inertia = finite_vector('inertia', values['inertia'], 6)
    if any(inertia):
        body = RigidBody(values['mass'], inertia)
        name = f'body of inertia {shown(inertia)} and mass'
    else:
        body = RigidBody.solid_box(values['mass'], box_size, name='box_size')
        name = f'solid box of box_size {shown(box_size)} and mass'
    return Body(body, BodyGeometry.box(box_size), BodyFrame(), name)
