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

"""The core's specialized paths compute what the general ones do, to the bit."""

import math
import random

import pytest

from mouse_constraint_ros.physics import BodyState
from mouse_constraint_ros.physics import MouseConstraint
from mouse_constraint_ros.physics import MouseSimulation
from mouse_constraint_ros.physics import RigidBody
from mouse_constraint_ros.physics import Settings
from mouse_constraint_ros.physics.algebra import integrate_orientation
from mouse_constraint_ros.physics.gyroscopic import gyroscopic_step
from mouse_constraint_ros.physics.gyroscopic import gyroscopic_step_diagonal
from mouse_constraint_ros.physics.limits import MAX_MOMENT, MIN_MOMENT


def random_cases(count: int, seed: int):
    """Yield (moments, w, h): moments over decades, |w| h from 1e-6 to beyond 10."""
    generator = random.Random(seed)
    for _ in range(count):
        scale = 10.0 ** generator.uniform(-6.0, 6.0)
        moments = tuple(scale * generator.uniform(0.1, 1.0) for _ in range(3))
        speed = 10.0 ** generator.uniform(-3.0, 4.0)
        w = tuple(speed * generator.gauss(0.0, 1.0) for _ in range(3))
        yield moments, w, 10.0 ** generator.uniform(-4.0, -1.0)


def diagonal(moments):
    """Return diag(moments) as the symmetric 6-tuple (xx, xy, xz, yy, yz, zz)."""
    return (moments[0], 0.0, 0.0, moments[1], 0.0, moments[2])


def test_the_diagonal_gyroscopic_step_is_the_general_one_to_the_bit():
    """Random spins, slow to far beyond convergence (energy rescaled there), equal as floats."""
    converged = rescaled = 0
    for moments, w, h in random_cases(3000, seed=3):
        general = gyroscopic_step(diagonal(moments), w, h)
        assert gyroscopic_step_diagonal(moments, w, h) == general, (moments, w, h)
        energy = sum(m * c * c for m, c in zip(moments, w))
        if sum(m * c * c for m, c in zip(moments, general)) < energy * (1.0 - 1e-9):
            rescaled += 1
        else:
            converged += 1
    # Both regimes were met, so both branches were compared.
    assert converged > 100 and rescaled > 100


@pytest.mark.parametrize('moments, w, h', [
    # Zero spin, a singular Jacobian (about the intermediate axis), the extreme moments.
    ((1.0, 2.0, 3.0), (0.0, 0.0, 0.0), 0.001),
    ((3.0, 4.0, 6.0), (0.0, 6.0, 0.0), 1.0),
    ((MIN_MOMENT, 2.0 * MIN_MOMENT, 2.5 * MIN_MOMENT), (1e3, -2e3, 5e2), 1e-3),
    ((MAX_MOMENT / 3.0, MAX_MOMENT / 2.0, MAX_MOMENT), (1e100, 3e99, -2e100), 1e-3),
    ((1.0, 2.0, 2.5), (1e118, -1e118, 1e118), 1.0),
])
def test_the_diagonal_gyroscopic_step_matches_at_the_edges(moments, w, h):
    """The degenerate and extreme inputs give the general step's result too."""
    assert gyroscopic_step_diagonal(moments, w, h) == gyroscopic_step(diagonal(moments), w, h)


def test_a_diagonal_body_moves_as_a_body_with_a_vanishing_product_of_inertia():
    """
    The step picks the diagonal path by the inertia; a tiny product of inertia takes the general.

    A product 1e-300 of the moments changes the dynamics by far less than a rounding error, so
    the two trajectories agree to rounding while taking different paths.
    """
    anchor = (0.2, 0.1, 0.05)
    start = BodyState(angular_velocity=(1.5, -2.0, 6.0))
    trajectories = []
    for product in (0.0, 1e-300):
        body = RigidBody(2.0, (0.0083, product, 0.0, 0.0283, 0.0, 0.0333))
        sim = MouseSimulation(Settings(body, MouseConstraint(anchor=anchor)), start)
        sim.target = sim.anchor_position()
        trajectories.append([sim.step(0.001) for _ in range(500)])
    for a, b in zip(*trajectories):
        for field_a, field_b in zip(a, b):
            assert all(math.isclose(x, y, rel_tol=1e-9, abs_tol=1e-12)
                       for x, y in zip(field_a, field_b))


@pytest.mark.parametrize('w', [(1.5, -2.0, 6.0), (1e-3, 2e-3, -1e-3), (40.0, 0.0, -30.0)])
def test_the_step_turns_the_body_as_integrate_orientation_does_to_the_bit(w):
    """
    The step's written-out orientation update is ``algebra.integrate_orientation``, to the bit.

    With one substep the orientation a step returns is ``integrate_orientation`` of the one
    before with the angular velocity it returns, held for the step. The three speeds take both
    branches of the rotation (its series at small angles, sine and cosine beyond). The body is
    held by the joint: a free body turns by its gyroscopic step's own rotation instead
    (``test_physics_torque``).
    """
    dt = 0.004
    half = math.sqrt(0.5)
    start = BodyState(orientation=(0.0, half, 0.0, half), angular_velocity=w)
    body = RigidBody(2.0, (0.0083, 0.0, 0.0, 0.0283, 0.0, 0.0333))
    sim = MouseSimulation(Settings(body), start)
    sim.target = sim.anchor_position()
    q = start.orientation
    for _ in range(200):
        state = sim.step(dt)
        assert state.orientation == integrate_orientation(q, state.angular_velocity, dt)
        q = state.orientation
