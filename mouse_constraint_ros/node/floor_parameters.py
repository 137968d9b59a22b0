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
The floor's parameters: their table rows and the core ``Floor`` they make (no ROS here).

``parameters.PARAMETERS`` takes ``FLOOR_PARAMETERS`` into the node's one table; ``floor_from``
builds and validates the floor for ``parameters.node_config``, the collision geometry being
the URDF link's pieces or else the node's ``box_size``. The defaults are the core's
(``physics.floor.Floor``): no floor.
"""

from typing import Any, Mapping, Optional, Tuple

from .timer_limits import FINITE_MAX
from ..physics.algebra import Vector3
from ..physics.collision import CollisionShape
from ..physics.floor import Floor
from ..physics.limits import MAX_CONTACT_ITERATIONS, MAX_DISTANCE, MAX_FRICTION
from ..physics.validation import shown

CORE = Floor()

# (name, default, description, bounds), as ``parameters.ParameterSpec`` takes them.
FLOOR_PARAMETERS: Tuple[tuple, ...] = (
    ('floor', False,
     'A floor: the plane z = floor_height of frame_id, on which the body (its URDF collision '
     'pieces, or the box_size box) rests, slides and bounces (config/params.yaml turns it on); '
     'false: none, the body falls for ever.', None),
    ('floor_height', 0.0, f'Height of the floor in frame_id (m), within {MAX_DISTANCE:g}.',
     (-MAX_DISTANCE, MAX_DISTANCE)),
    ('friction', CORE.friction,
     'Coulomb friction coefficient of the floor, >= 0: a sliding box decelerates by friction '
     'times |gravity|.', (0.0, MAX_FRICTION)),
    ('restitution', CORE.restitution,
     'Restitution of the floor in [0, 1]: a contact point (a corner of a box, a vertex of a '
     'hull) hitting faster than restitution_threshold leaves at this times its speed; '
     '0 = no bounce.', (0.0, 1.0)),
    ('restitution_threshold', CORE.restitution_threshold,
     'Speed of approach (m/s) below which a contact does not bounce, so a resting box is '
     'still.', (0.0, FINITE_MAX)),
    ('contact_iterations', CORE.iterations,
     'Most sequential-impulse sweeps over the floor contacts per substep (they stop once '
     'converged).', (1, MAX_CONTACT_ITERATIONS)),
    ('contact_margin', CORE.margin,
     "The body's points (a box's corners, a hull's vertices) this close above the floor are "
     'contacts (m): the body lands without passing it at up to contact_margin / substep m/s.',
     (0.0, MAX_DISTANCE)),
    ('contact_slop', CORE.slop,
     'Penetration left alone (m), below contact_margin; deeper is pushed out without adding '
     'velocity.', (0.0, MAX_DISTANCE)),
)


def floor_from(values: Mapping[str, Any], box_size: Vector3,
               shape: Optional[CollisionShape] = None) -> Floor:
    """
    Return the floor of parameter ``values``; raise ValueError naming the parameter.

    :param box_size: the box body's edges, its collision box where ``shape`` is None.
    :param shape: a URDF link's collision pieces, from the COM.
    """
    enabled = values['floor']
    if not isinstance(enabled, bool):
        raise ValueError(f'floor must be true or false, got {shown(enabled)}')
    return Floor(enabled=enabled, height=values['floor_height'], box_size=box_size,
                 friction=values['friction'], restitution=values['restitution'],
                 iterations=values['contact_iterations'], margin=values['contact_margin'],
                 slop=values['contact_slop'],
                 restitution_threshold=values['restitution_threshold'], shape=shape)
