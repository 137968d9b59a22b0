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
The body's shape as the node has it, and where a pointer's ray meets it (no ROS here).

``BodyShape`` keeps the ``BodyGeometry`` of the node's ``GEOMETRY_PARAMETERS``
(``robot_description``, ``body_link``, ``density``, ``box_size``), made by the node's own
``geometry_from``: the URDF link's collision and visual pieces in the link frame, or the box of
``box_size`` about the COM. It is made again only when one of those changes, not at each grab
(which sets ``anchor``). A description this process cannot read, though the node could (a mesh
file this machine does not have, a ``package://`` outside its ``AMENT_PREFIX_PATH``), leaves the
box of ``box_size`` in its place, and ``error`` says why. For a whole robot (several links and
no ``body_link``) the shape is the tracked link's (``tracked_link``, else the robot's tool),
in its frame, which is the frame of the node's ``pose``: what a client that draws one body
(``mouse_marker``) draws and grabs; ``mouse_view`` draws every link (``robot_shape``).

``ray_body_hit`` is a click's ray on the body at a pose: in the body's frame, the nearest hit on
its collision pieces (``BodyGeometry.ray``: boxes, spheres and cylinders in closed form, meshes
by trimesh's ray test), so a click on a mesh grabs the mesh where the ray meets it, also inside a
concave part that a box or hull would cover. A body whose only collision piece is a box about
its frame's origin, unturned (the box of ``box_size``), is met by ``ray_box_hit``, as it always
was: a ray that starts inside it meets it where it leaves.
"""

import math
from typing import Optional, Sequence, Tuple

from .geometry import local_point, Pose, ray_box_hit
from .node_readouts import ViewParameters
from ..description.body_geometry import BodyGeometry, lone_box
from ..node.body_parameters import geometry_from, GEOMETRY_PARAMETERS
from ..node.robot_parameters import is_robot
from ..physics.algebra import multiply_transposed, rotation_matrix, Vector3


def ray_body_hit(origin: Sequence[float], direction: Sequence[float], *, pose: Pose,
                 geometry: BodyGeometry) -> Optional[Vector3]:
    """
    Return the first point where a ray meets the body's collision pieces, or None.

    :param origin: the ray's origin, world frame (m).
    :param direction: the ray's direction, world frame (any non-zero length).
    :param pose: the pose of the body's frame (the link's; the box's COM).
    :param geometry: the body's shape in that frame.
    :returns: the world point (m), or None for a miss, a ray pointing away, or a zero or
        non-finite direction.
    """
    edges = lone_box(geometry.collisions)
    if edges is not None:
        return ray_box_hit(origin, direction, pose=pose, box_size=edges)
    start = local_point(origin, pose)
    heading = multiply_transposed(tuple(float(c) for c in direction),
                                  rotation_matrix(pose.orientation))
    if not all(math.isfinite(c) for c in (*start, *heading)) or not any(heading):
        return None
    t = geometry.ray(start, heading)
    if t is None:
        return None
    return tuple(float(o) + t * float(d) for o, d in zip(origin, direction))


def tracked_link_geometry(text: str, tracked_link: str) -> BodyGeometry:
    """
    Return a whole robot's tracked link's pieces, in its frame (no Pinocchio).

    :param text: the robot's URDF.
    :param tracked_link: the node's ``tracked_link``; empty: the robot's tool.
    :raises ValueError: the URDF is not a robot served, or has no such link.
    """
    from ..description.robot_links import robot_links
    from ..description.robot_structure import robot_structure
    link = tracked_link or robot_structure(text).tool
    links = robot_links(text, visuals=True)
    if link not in links.pieces:
        raise ValueError(f'tracked_link {link!r} is not a link of the robot')
    return links.geometry(link)


class BodyShape:
    """The body's shape of the node's parameters as last known (the default box at first)."""

    def __init__(self) -> None:
        """Start with the box of the default ``box_size``."""
        self._key: Optional[Tuple] = None
        self.geometry = BodyGeometry.box(ViewParameters().box_size)
        self.error: Optional[str] = None
        self.update(ViewParameters())

    def update(self, parameters: ViewParameters) -> bool:
        """
        Take the shape of ``parameters``; return whether it changed.

        :param parameters: the node's parameters as known (``GEOMETRY_PARAMETERS`` of them).
        """
        values = {name: getattr(parameters, name) for name in GEOMETRY_PARAMETERS}
        robot = is_robot(values)
        key = tuple(values[name] for name in GEOMETRY_PARAMETERS) + (
            (parameters.tracked_link,) if robot else ())
        if key == self._key:
            return False
        self._key = key
        try:
            if robot:
                self.geometry = tracked_link_geometry(values['robot_description'],
                                                      parameters.tracked_link)
            else:
                self.geometry = geometry_from(values)
            self.error = None
        except ValueError as error:
            self.geometry = BodyGeometry.box(parameters.box_size)
            self.error = f'the body is drawn as the box of box_size: {error}'
        return True
