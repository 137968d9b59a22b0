"""The body's kinematic state in the world frame (SI units, REP 103)."""

import math
from typing import NamedTuple

from .rotation import IDENTITY_QUATERNION, Quaternion, Vector3
from .validation import finite_vector

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

    def validated(self) -> 'BodyState':
        """Return this state with floats and an exactly unit quaternion, or raise ValueError."""
        orientation = finite_vector('orientation', self.orientation, 4)
        norm = math.sqrt(sum(c * c for c in orientation))
        if abs(norm - 1.0) > UNIT_QUATERNION_TOLERANCE:
            raise ValueError(
                f'orientation must be a unit quaternion (x, y, z, w), got {orientation!r} '
                f'with norm {norm!r}')
        return BodyState(
            finite_vector('position', self.position),
            tuple(c / norm for c in orientation),
            finite_vector('linear_velocity', self.linear_velocity),
            finite_vector('angular_velocity', self.angular_velocity),
        )
