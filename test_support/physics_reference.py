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
Reference forms of the physics that only the tests and benchmarks use.

The 3x6 Jacobian of the mouse constraint, Box2D's soft-step gains and a direct effective-mass
solve.
They check the core against independent formulas; the core itself never needs them.
"""

import math
from typing import Tuple

import numpy as np

from mouse_constraint_ros.physics.algebra import (cholesky, solve_cholesky,
                                                  Symmetric3, Vector3)


def box2d_soft_gains(frequency_hz: float, damping_ratio: float, h: float) -> Tuple[float, float]:
    """Return Box2D v3's b2MakeSoft gains (mass scale, mass scale * bias rate), for comparison."""
    omega = 2.0 * math.pi * frequency_hz
    a1 = 2.0 * damping_ratio + h * omega
    a2 = h * omega * a1
    a3 = 1.0 / (1.0 + a2)
    return a2 * a3, a2 * a3 * omega / a1


def jacobian(r: Vector3) -> np.ndarray:
    """Return the 3x6 Jacobian J = [I3, -[r]x] of eq. 1.2 (eq. 1.3 with its sign corrected)."""
    rx, ry, rz = r
    return np.array([
        [1.0, 0.0, 0.0, 0.0, rz, -ry],
        [0.0, 1.0, 0.0, -rz, 0.0, rx],
        [0.0, 0.0, 1.0, ry, -rx, 0.0],
    ])


def solve_effective_mass(k: Symmetric3, b: Vector3) -> Vector3:
    """Return x with K x = b for a symmetric positive definite K, by a closed-form Cholesky."""
    return solve_cholesky(cholesky(k), b)
