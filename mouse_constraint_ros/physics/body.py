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
The rigid body: mass and inertia about the center of mass, in the body frame.

The inertia is given in URDF order (ixx, ixy, ixz, iyy, iyz, izz). A physical inertia is
symmetric positive definite and its principal moments obey the triangle inequality
I1 + I2 >= I3 (a mass distribution cannot produce anything else; a thin plate is the limit).
The mass and the principal moments must also lie in the ranges of ``limits``, where the step's
float arithmetic with them stays finite and exact enough (MIN_MASS..MAX_MASS,
MIN_MOMENT..MAX_MOMENT, largest over smallest moment at most MAX_CONDITION).
"""

from dataclasses import dataclass, field
from typing import Tuple

import numpy as np

from .algebra import (congruence, Matrix3, multiply, multiply_symmetric, multiply_transposed,
                      Quaternion, rotation_matrix, Symmetric3, Vector3)
from .limits import MAX_CONDITION, MAX_DISTANCE, MAX_MASS, MAX_MOMENT, MIN_MASS, MIN_MOMENT
from .validation import finite_vector, scalar, shown

# The smallest principal moment must exceed this fraction of the largest: a moment that is zero
# but for rounding would pass "> 0" and then divide by zero in the step.
_CONDITION_LIMIT = 1.0 / MAX_CONDITION
# Relative slack on the triangle inequality, so that a thin plate (I3 = I1 + I2) passes.
_TRIANGLE_TOLERANCE = 1e-9


def checked_mass(mass: float, name: str = 'mass') -> float:
    """
    Return ``mass`` as a float in [MIN_MASS, MAX_MASS] kg, or raise ValueError naming ``name``.

    The bounds are the float arithmetic's (see ``limits``): the effective mass K grows like
    1 / m, the impulses, forces and energies of a correction like m.
    """
    mass = scalar(name, mass, above=0.0)
    if not MIN_MASS <= mass <= MAX_MASS:
        raise ValueError(
            f'{name} must be within [{MIN_MASS:g}, {MAX_MASS:g}] kg, got {mass!r}: beyond, the '
            'effective mass (1 / m) or the impulses and energies (m) of the step overflow')
    return mass


@dataclass(frozen=True)
class RigidBody:
    """
    Mass (kg) and inertia tensor about the COM in the body frame (kg m^2, URDF order).

    ``inverse_mass``, ``inverse_inertia`` (the body-frame I_b^-1 as a symmetric 6-tuple) and
    ``principal_moments`` (ascending) are derived once here, so the solver never inverts
    anything per step.
    """

    mass: float
    inertia: Symmetric3
    inverse_mass: float = field(init=False, repr=False)
    inverse_inertia: Symmetric3 = field(init=False, repr=False)
    principal_moments: Tuple[float, float, float] = field(init=False, repr=False)

    def __post_init__(self) -> None:
        """Validate mass and inertia and derive their inverses; raise ValueError if invalid."""
        mass = checked_mass(self.mass)
        inertia = finite_vector('inertia', self.inertia, 6)
        largest = max(abs(c) for c in inertia)
        if largest > MAX_MOMENT:
            raise ValueError(
                f'inertia must have no element beyond {MAX_MOMENT:g} kg m^2, got '
                f'{shown(inertia)}: the gyroscopic step multiplies three moments, which would '
                'overflow')
        matrix = _matrix(inertia)
        moments = np.linalg.eigvalsh(matrix)
        # The principal moments, shown where they differ from the diagonal.
        principal = ('' if not any(inertia[i] for i in (1, 2, 4)) else
                     ' (principal moments ' + ', '.join(f'{m:.6g}' for m in moments) + ')')
        if not moments[0] > _CONDITION_LIMIT * moments[2]:
            raise ValueError(
                f'inertia must be positive definite, got {shown(inertia)}{principal}: the '
                f'smallest principal moment must exceed {_CONDITION_LIMIT:g} of the largest')
        if moments[0] + moments[1] < moments[2] * (1.0 - _TRIANGLE_TOLERANCE):
            raise ValueError(
                f'inertia is not physically realizable, got {shown(inertia)}{principal}: the '
                'principal moments break the triangle inequality I1 + I2 >= I3')
        if not MIN_MOMENT <= moments[0] <= moments[2] <= MAX_MOMENT:
            raise ValueError(
                f'inertia must have principal moments within [{MIN_MOMENT:g}, {MAX_MOMENT:g}] '
                f'kg m^2, got {shown(inertia)}{principal}: the determinant of the Jacobian of '
                'the gyroscopic step, a product of three moments, would leave the float range')
        inverse = np.linalg.inv(matrix)
        object.__setattr__(self, 'mass', mass)
        object.__setattr__(self, 'inertia', inertia)
        object.__setattr__(self, 'inverse_mass', 1.0 / mass)
        object.__setattr__(self, 'inverse_inertia', _symmetric(inverse))
        object.__setattr__(self, 'principal_moments', tuple(float(m) for m in moments))

    @classmethod
    def solid_box(cls, mass: float, extents: Vector3, *, name: str = 'extents',
                  mass_name: str = 'mass') -> 'RigidBody':
        """
        Return a uniform solid box of ``mass`` kg and full edge lengths ``extents`` (m).

        Each edge must be in (0, MAX_DISTANCE]; the inertia the box has must be valid as any
        (see ``RigidBody``), or the ValueError names both ``name`` and ``mass_name``.

        :param name: what messages call the extents (the parameter they came from).
        :param mass_name: what messages call the mass.
        """
        x, y, z = finite_vector(name, extents)
        if not min(x, y, z) > 0.0:
            raise ValueError(f'{name} must be > 0, got {shown(extents)}')
        if max(x, y, z) > MAX_DISTANCE:
            raise ValueError(
                f'{name} must be at most {MAX_DISTANCE:g} m per edge, got {shown(extents)}')
        mass = checked_mass(mass, mass_name)
        k = mass / 12.0
        try:
            return cls(mass, (k * (y * y + z * z), 0.0, 0.0, k * (x * x + z * z), 0.0,
                              k * (x * x + y * y)))
        except ValueError as error:
            raise ValueError(f'{name} {shown((x, y, z))} and {mass_name} {mass!r} give a solid '
                             f'box whose {error}') from None

    def world_inverse_inertia(self, rotation: Matrix3) -> Symmetric3:
        """Return I_w^-1 = R I_b^-1 R^T for the body's rotation matrix R (seed eq. 1.8)."""
        return congruence(rotation, self.inverse_inertia)

    def kinetic_energy(self, linear_velocity: Vector3, angular_velocity_body: Vector3) -> float:
        """Return m v.v / 2 + w_b.I_b w_b / 2, with ``angular_velocity_body`` in the body frame."""
        vx, vy, vz = linear_velocity
        lx, ly, lz = multiply_symmetric(angular_velocity_body, self.inertia)
        wx, wy, wz = angular_velocity_body
        return 0.5 * (self.mass * (vx * vx + vy * vy + vz * vz) + wx * lx + wy * ly + wz * lz)

    def body_rate(self, orientation: Quaternion, angular_velocity: Vector3) -> Vector3:
        """Return the world ``angular_velocity`` in the body frame of ``orientation``."""
        return multiply_transposed(angular_velocity, rotation_matrix(orientation))

    def angular_momentum(self, orientation: Quaternion, angular_velocity: Vector3) -> Vector3:
        """Return L = R I_b R^T w about the COM, world frame, for the world velocity."""
        rotation = rotation_matrix(orientation)
        w_body = multiply_transposed(angular_velocity, rotation)
        return multiply(multiply_symmetric(w_body, self.inertia), rotation)


def _matrix(s: Symmetric3) -> np.ndarray:
    xx, xy, xz, yy, yz, zz = s
    return np.array([[xx, xy, xz], [xy, yy, yz], [xz, yz, zz]])


def _symmetric(m: np.ndarray) -> Symmetric3:
    # Average the off-diagonal pairs so that the stored inverse is exactly symmetric.
    return (float(m[0, 0]), 0.5 * float(m[0, 1] + m[1, 0]), 0.5 * float(m[0, 2] + m[2, 0]),
            float(m[1, 1]), 0.5 * float(m[1, 2] + m[2, 1]), float(m[2, 2]))
