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
The map between a haptic device's frame and the world, and its force back (stdlib only).

A device reports its handle at p_d in its own frame, in metres; the world point is

    p = offset + s R p_d,

with R the rotation of the device frame into the world frame (a unit quaternion x, y, z, w),
s the position scale and ``offset`` the device origin's world point. The force F the world
computes at p goes back to the device as

    f_d = f R^T F,

with f the force scale: the transpose rotation (R is orthogonal) and, for a rendering that
keeps power, f = s (the power the hand puts in, f_d . v_d = f R^T F . v_d, is then the power
F . v the body takes, v = s R v_d). A coupling of stiffness k in the world is a stiffness
s f k at the handle: a displacement dp_d moves the world point s dp_d, which the spring
answers with k s dp_d, scaled by f on the way back.
"""

import math
from typing import NamedTuple, Sequence

from .algebra import (IDENTITY_QUATERNION, Matrix3, multiply, multiply_transposed,
                      Quaternion, rotation_matrix, Vector3)
from .validation import finite_vector, scalar

# The rotation's norm may be off by this much (a quaternion written with few digits); the map
# uses it normalised.
QUATERNION_TOLERANCE = 1e-3
# The scales' range: a millionth to a million keeps every product of the map well within a
# double for the distances and forces the node takes.
SCALE_RANGE = (1e-6, 1e6)


class DeviceMap(NamedTuple):
    """
    ``p = offset + scale R p_d`` into the world; ``f_d = force_scale R^T F`` back.

    :param scale: the position scale s (world metres per device metre), > 0.
    :param offset: the world point of the device frame's origin (m).
    :param rotation: R, the device frame's orientation in the world (x, y, z, w), unit.
    :param force_scale: the force scale f (device newtons per world newton), > 0.
    """

    scale: float = 1.0
    offset: Vector3 = (0.0, 0.0, 0.0)
    rotation: Quaternion = IDENTITY_QUATERNION
    force_scale: float = 1.0

    @property
    def matrix(self) -> Matrix3:
        """Return R, row-major."""
        return rotation_matrix(self.rotation)

    def to_world(self, point: Vector3) -> Vector3:
        """Return the world point of the device point ``point``."""
        s = self.scale
        x, y, z = multiply(point, self.matrix)
        ox, oy, oz = self.offset
        return (ox + s * x, oy + s * y, oz + s * z)

    def from_world(self, point: Vector3) -> Vector3:
        """Return the device point of the world point ``point``: R^T (p - offset) / s."""
        s = self.scale
        ox, oy, oz = self.offset
        x, y, z = multiply_transposed((point[0] - ox, point[1] - oy, point[2] - oz),
                                      self.matrix)
        return (x / s, y / s, z / s)

    def to_device(self, force: Vector3) -> Vector3:
        """Return the force the device renders for the world force ``force``."""
        f = self.force_scale
        x, y, z = multiply_transposed(force, self.matrix)
        return (f * x, f * y, f * z)

    def felt_stiffness(self, stiffness: float) -> float:
        """Return the stiffness s f k the handle feels of a world coupling ``stiffness`` k."""
        return self.scale * self.force_scale * stiffness


def device_map(scale: float, pose: Sequence[float], force_scale: float) -> DeviceMap:
    """
    Return the checked map of a scale, a pose (x, y, z, qx, qy, qz, qw) and a force scale.

    :raises ValueError: naming ``device_scale``, ``device_pose`` or ``device_force_scale``.
    """
    low, high = SCALE_RANGE
    s = scalar('device_scale', scale, at_least=low, at_most=high)
    f = scalar('device_force_scale', force_scale, at_least=low, at_most=high)
    values = finite_vector('device_pose', pose, size=7)
    quaternion = values[3:]
    length = math.sqrt(sum(c * c for c in quaternion))
    if abs(length - 1.0) > QUATERNION_TOLERANCE:
        raise ValueError(f"device_pose's rotation (the last four, x y z w) must be a unit "
                         f'quaternion, got norm {length:g}')
    return DeviceMap(s, values[:3], tuple(c / length for c in quaternion), f)
