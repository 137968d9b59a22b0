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

"""The body's kinematic state in the world frame (SI units, REP 103)."""

import math
from typing import NamedTuple

from .algebra import IDENTITY_QUATERNION, multiply, Quaternion, rotation_matrix, Vector3
from .limits import MAX_DISTANCE
from .validation import finite_vector, shown

# How far from 1 the norm of a given orientation may be; it is then normalized exactly.
UNIT_QUATERNION_TOLERANCE = 1e-6


class BodyState(NamedTuple):
    """
    COM position (m), orientation (x, y, z, w), linear (m/s) and angular (rad/s) velocity.

    Both velocities are expressed in the world frame; the body frame's origin is the COM.
    """

    position: Vector3 = (0.0, 0.0, 0.0)
    orientation: Quaternion = IDENTITY_QUATERNION
    linear_velocity: Vector3 = (0.0, 0.0, 0.0)
    angular_velocity: Vector3 = (0.0, 0.0, 0.0)

    def world_point(self, local: Vector3) -> Vector3:
        """
        Return the world position x + R(q) r of the body-frame point ``local`` (m).

        The one place the anchor's world position is computed: the simulation's anchor, the
        initial anchor a node holds, and the recorder's anchor column all come from here.
        """
        x = self.position
        r = multiply(local, rotation_matrix(self.orientation))
        return (x[0] + r[0], x[1] + r[1], x[2] + r[2])

    def moved(self, offset: Vector3) -> 'BodyState':
        """
        Return the state of the frame at body-frame ``offset`` (m) from this one's origin.

        The same orientation and angular velocity; the origin x + R r, and its velocity
        v + w x R r (a point of the rigid body). The link frame of a URDF body and its COM are
        two such frames.
        """
        r = multiply(offset, rotation_matrix(self.orientation))
        x, y, z = self.position
        vx, vy, vz = self.linear_velocity
        wx, wy, wz = self.angular_velocity
        return BodyState((x + r[0], y + r[1], z + r[2]), self.orientation,
                         (vx + wy * r[2] - wz * r[1], vy + wz * r[0] - wx * r[2],
                          vz + wx * r[1] - wy * r[0]), self.angular_velocity)

    def validated(self, *, prefix: str = '') -> 'BodyState':
        """
        Return this state with floats and an exactly unit quaternion, or raise ValueError.

        The position must lie within MAX_DISTANCE of the origin, where positions are resolved
        (see ``limits``).

        :param prefix: put before the field names in messages, e.g. ``initial_`` for the
            parameters ``initial_position`` and ``initial_orientation``.
        """
        orientation = finite_vector(prefix + 'orientation', self.orientation, 4)
        norm = math.sqrt(sum(c * c for c in orientation))
        if abs(norm - 1.0) > UNIT_QUATERNION_TOLERANCE:
            raise ValueError(
                f'{prefix}orientation must be a unit quaternion (x, y, z, w), got '
                f'{shown(orientation)} with norm {math.hypot(*orientation)!r}')
        position = finite_vector(prefix + 'position', self.position)
        if math.hypot(*position) > MAX_DISTANCE:
            raise ValueError(
                f'{prefix}position must be at most {MAX_DISTANCE:g} m from the origin, got '
                f'{shown(position)}: positions are not resolved beyond')
        return BodyState(
            position,
            tuple(c / norm for c in orientation),
            finite_vector(prefix + 'linear_velocity', self.linear_velocity),
            finite_vector(prefix + 'angular_velocity', self.angular_velocity),
        )
