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
The floor: the plane z = ``height`` of the world frame, its settings, and where the body meets it.

The body's collision shape is ``shape`` (``collision.CollisionShape``: boxes, meshes' convex
hulls, spheres, cylinders, in the body frame from the COM), or else a box of ``box_size`` (m)
centered on its COM, axes along the body frame. Its contact points are those within ``margin``
of the plane (at, below or speculatively above it); ``floor_contact.solve`` resolves them in the
same substep as the mouse constraint. docs/contact.md gives the model and why each choice.
"""

from dataclasses import dataclass
import sys
from typing import Optional, Tuple

from .algebra import Quaternion, rotation_matrix, Vector3
from .collision import CollisionShape
from .limits import MAX_CONTACT_ITERATIONS, MAX_DISTANCE, MAX_FRICTION
from .validation import finite_vector, scalar, shown


@dataclass(frozen=True)
class Floor:
    """
    The floor and how contact with it is solved; ``enabled`` False (the default): no floor.

    :param enabled: whether there is a floor.
    :param height: its height z in the world frame (m).
    :param box_size: the body's collision box, full edge lengths along its axes (m), centered
        on the COM (each > 0 when enabled), when ``shape`` is None.
    :param shape: the body's collision shape, from the COM; None: the box of ``box_size``.
    :param friction: Coulomb coefficient mu >= 0: the tangential impulse stays within mu times
        the normal one (a cone).
    :param restitution: e in [0, 1]: a corner that hits faster than ``restitution_threshold``
        leaves at e times its speed of approach.
    :param iterations: the most sequential-impulse sweeps over the contacts per substep (the
        sweeps stop once no impulse changes a contact's velocity by more than 1e-9 m/s).
    :param margin: corners up to this far above the plane are contacts (m): speculative ones,
        which let the corner reach the plane within the substep but not pass it, so that a
        falling box lands without penetrating and a resting one keeps its contacts.
    :param slop: penetration left alone (m); deeper, the position is corrected by split
        impulses, which change no velocity.
    :param restitution_threshold: the speed of approach (m/s) below which a contact does not
        bounce, so that a resting box does not jitter.
    """

    enabled: bool = False
    height: float = 0.0
    box_size: Vector3 = (1.0, 1.0, 1.0)
    friction: float = 0.5
    restitution: float = 0.0
    iterations: int = 10
    margin: float = 0.02
    slop: float = 0.0005
    restitution_threshold: float = 0.5
    shape: Optional[CollisionShape] = None

    def __post_init__(self) -> None:
        """Validate every field; raise ValueError naming the first invalid one."""
        if not isinstance(self.enabled, bool):
            raise ValueError(f'floor must be true or false, got {shown(self.enabled)}')
        height = scalar('floor_height', self.height)
        if abs(height) > MAX_DISTANCE:
            raise ValueError(f'floor_height must be within {MAX_DISTANCE:g} m of the origin, '
                             f'got {height!r}: positions are not resolved beyond')
        object.__setattr__(self, 'height', height)
        size = finite_vector('box_size', self.box_size)
        if not min(size) > 0.0 or max(size) > MAX_DISTANCE:
            raise ValueError(f'box_size must be > 0 and at most {MAX_DISTANCE:g} m per edge, '
                             f'got {shown(self.box_size)}')
        object.__setattr__(self, 'box_size', size)
        if self.shape is None:
            object.__setattr__(self, 'shape', CollisionShape.box(size))
        elif not isinstance(self.shape, CollisionShape):
            raise ValueError(f'shape must be a CollisionShape, got {shown(self.shape)}')
        object.__setattr__(self, 'friction', scalar(
            'friction', self.friction, at_least=0.0, at_most=MAX_FRICTION))
        object.__setattr__(self, 'restitution', scalar(
            'restitution', self.restitution, at_least=0.0, at_most=1.0))
        if isinstance(self.iterations, bool) or not isinstance(self.iterations, int) \
                or not 1 <= self.iterations <= MAX_CONTACT_ITERATIONS:
            raise ValueError(f'contact_iterations must be an integer in [1, '
                             f'{MAX_CONTACT_ITERATIONS}], got {shown(self.iterations)}')
        margin = scalar('contact_margin', self.margin, above=0.0, at_most=MAX_DISTANCE)
        object.__setattr__(self, 'margin', margin)
        slop = scalar('contact_slop', self.slop, at_least=0.0)
        if not slop < margin:
            raise ValueError(f'contact_slop must be below contact_margin {margin!r} m, got '
                             f'{slop!r}')
        object.__setattr__(self, 'slop', slop)
        object.__setattr__(self, 'restitution_threshold', scalar(
            'restitution_threshold', self.restitution_threshold, at_least=0.0))

    def depth(self, position: Vector3, orientation: Quaternion) -> float:
        """Return how far the body's lowest point is below the plane (m; < 0: above it)."""
        return self.height - (position[2] - self.shape.reach(rotation_matrix(orientation)))

    def check_state(self, position: Vector3, orientation: Quaternion, *,
                    prefix: str = 'initial_') -> None:
        """
        Raise ValueError if the body at this pose starts below the floor by more than ``slop``.

        :param prefix: put before ``position`` in the message (the parameter's name).
        """
        if not self.enabled:
            return
        depth = self.depth(position, orientation)
        # Up to the rounding of the subtraction: a corner placed exactly ``slop`` deep comes
        # out a few 1e-19 m deeper (0.0495 - 0.05 is not -0.0005 in binary).
        rounding = 8.0 * sys.float_info.epsilon * (
            abs(self.height) + abs(position[2]) + self.shape.bound)
        if depth > self.slop + rounding:
            raise ValueError(
                f'{prefix}position {shown(tuple(position))} puts the body {depth:.6g} m below '
                f'floor_height {self.height!r} m (its lowest point): start it at or above '
                'the floor')


def coefficients(floor: Floor) -> Optional[Tuple]:
    """Return what the contact solve needs from ``floor`` per substep, or None without one."""
    if not floor.enabled:
        return None
    return (floor.height, floor.shape, floor.friction, floor.restitution, floor.iterations,
            floor.margin, floor.slop, floor.restitution_threshold)
