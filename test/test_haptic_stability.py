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
The haptic loop's largest stable stiffness: predicted from its polynomial, measured in lockstep.

A simulated device (test_support.haptic_device) reads the force each tick, moves, and sends its
pose as the target, which acts from the next tick (plus ``delay`` ticks). Bisection between
0.75 and 1.3 times the prediction, five halvings (a bracket of 1.7 %), each trial's growth
measured and set beside the predicted one (``haptic_device.measure_largest_stable``).
"""

import math

import numpy as np
import pytest

from mouse_constraint_ros.physics import (BodyState, MouseConstraint, MouseSimulation, RigidBody,
                                          Settings)
from mouse_constraint_ros.physics.coupling_stability import (
    body_matrices, characteristic_polynomial, colgate_brown_damping, coupling_passivity_damping,
    Device, largest_stable_stiffness, passive_stiffness, passivity_damping, static_stiffness)
from mouse_constraint_ros.physics.mouse_joint import coupling_gains
from mouse_constraint_ros.testing import SimulatedBody
from test_support.haptic_device import (coupling, HAND, loop, LOOP_BODY, MASS,
                                        measure_largest_stable, ORIGIN, PERIOD, SUBSTEPS)

T = PERIOD
# (m_d, b_d, coupling damping, delay) -> each trial's measured growth over 250 ticks, found by
# running them.
CASES = [
    ((0.045, 0.05, 0.5, 0), [0.961032, 1.427069, 1.174694, 1.056142, 1.012957]),
    ((0.2, 0.02, 2.0, 0), [0.981991, 1.228968, 1.089931, 1.030286, 1.00607]),
    ((0.1, 0.5, 0.5, 1), [0.976844, 1.234039, 1.083744, 1.034882, 1.00127]),
]


def test_the_body_s_tick_map_is_the_node_s_step():
    """A (x, v) sequence of the core, stepped with the coupling's gains, is A^k, B exactly."""
    frequency, ratio = coupling_gains(500.0, 0.7, MASS)
    settings = Settings(RigidBody.solid_box(MASS, (0.1, 0.1, 0.1)),
                        MouseConstraint(frequency_hz=frequency, damping_ratio=ratio),
                        gravity=(0.0, 0.0, 0.0), substeps=SUBSTEPS)
    simulation = MouseSimulation(settings, BodyState((0.0, 0.0, 0.0)))
    simulation.target = (0.0, 0.0, 0.0)
    simulation.step(T)
    a, b = body_matrices(stiffness=500.0, damping=0.7, mass=MASS, period=T, substeps=SUBSTEPS)
    state = np.array([simulation.state.position[0], simulation.state.linear_velocity[0]])
    for target in (0.01, 0.012, 0.02, 0.0, -0.01):
        simulation.target = (target, 0.0, 0.0)
        simulation.step(T)
        state = a @ state + b * target
        actual = (simulation.state.position[0], simulation.state.linear_velocity[0])
        np.testing.assert_allclose(actual, state, rtol=1e-13, atol=1e-16)


def test_the_polynomial_is_the_loop_s_state_matrix():
    """p(z) has the eigenvalues of the loop written as one state matrix, delays included."""
    device = Device(0.05, 0.1, **HAND)
    a, b = body_matrices(stiffness=800.0, damping=0.5, mass=MASS, period=T, substeps=SUBSTEPS)
    phi, gamma = device.matrices(T)
    for delay in (0, 1, 3):
        size = 4 + delay
        # State: body (x, v), device (x, v), then the device's last positions, newest first.
        matrix = np.zeros((size, size))
        sent = 2 + 2 if delay == 0 else 4 + delay - 1
        # The target of the next tick: the device's position ``delay`` ticks back.
        source = np.zeros(size)
        source[2 if delay == 0 else sent] = 1.0
        matrix[:2, :] = np.outer(b, source)
        matrix[:2, :2] += a
        # Force of the next tick: -(m / T) (v' - v).
        force = -(MASS / T) * (matrix[1] - np.eye(size)[1])
        matrix[2:4, :] = np.outer(gamma, force)
        matrix[2:4, 2:4] += phi
        if delay:
            matrix[4, 2] = 1.0
            for row in range(5, size):
                matrix[row, row - 1] = 1.0
        expected = np.sort_complex(np.linalg.eigvals(matrix))
        roots = np.sort_complex(np.roots(characteristic_polynomial(
            stiffness=800.0, **loop(device, 0.5, delay))))
        np.testing.assert_allclose(roots, expected, rtol=0.0, atol=1e-9)


@pytest.mark.parametrize('stiffness, damping', [(1000.0, 3.0), (200.0, -0.5), (50.0, 0.0)])
def test_undelayed_the_passivity_condition_is_colgate_and_brown_s(stiffness, damping):
    assert passivity_damping(stiffness, damping, T) == pytest.approx(
        colgate_brown_damping(stiffness, damping, T), rel=1e-6)


@pytest.mark.parametrize('delay', [0, 1, 2, 5])
def test_a_spring_alone_delayed_needs_k_t_2d_plus_1_over_2(delay):
    """B = 0: the condition peaks at w = 0, K T (2 d + 1) / 2 (the Dirichlet kernel)."""
    need = passivity_damping(800.0, 0.0, T, delay, samples=1 << 16)
    assert need == pytest.approx(800.0 * T * (2 * delay + 1) / 2.0, rel=1e-6)


@pytest.mark.parametrize('delay', [0, 1])
def test_a_well_damped_coupling_is_a_spring_to_the_device(delay):
    """300 N/m, 3 N s/m: the body behind it needs the damping of the wall K, B = 0, or less."""
    need = coupling_passivity_damping(stiffness=300.0, **coupling(3.0, delay))
    assert need <= 300.0 * T * (2 * delay + 1) / 2.0 * 1.001
    assert need > 0.9 * 300.0 * T * (2 * delay + 1) / 2.0


def test_a_lightly_damped_coupling_needs_more_at_its_resonance():
    need = coupling_passivity_damping(stiffness=1950.0, **coupling(0.5, 0))
    assert need > 1.1 * 1950.0 * T / 2.0
    assert passive_stiffness(device_damping=need, **coupling(0.5, 0)) == pytest.approx(
        1950.0, rel=1e-5)


@pytest.mark.parametrize('pair', [pair for pair, _ in CASES])
def test_what_the_device_renders_passively_the_loop_holds_stably(pair):
    """Passivity is sufficient: the passive stiffness is below the stable one, every case."""
    mass, damping, coupling_damping, delay = pair
    device = Device(mass, damping, **HAND)
    passive = passive_stiffness(device_damping=damping + device.hand_damping,
                                **coupling(coupling_damping, delay))
    assert passive <= largest_stable_stiffness(**loop(device, coupling_damping, delay))


@pytest.mark.ros
def test_a_constant_force_meets_the_static_stiffness():
    """Held at its COM under its weight, no feed-forward: the sag is m |g| / (m b / h)."""
    with SimulatedBody(**{**LOOP_BODY, 'gravity': [0.0, 0.0, -9.80665]},
                       gravity_feed_forward=False, coupling_stiffness=300.0,
                       coupling_damping=3.0) as body:
        body.step(3000)
        stiffness = static_stiffness(stiffness=300.0, damping=3.0, mass=MASS, period=T,
                                     substeps=SUBSTEPS)
        assert ORIGIN[2] - body.pose.position[2] == pytest.approx(
            MASS * 9.80665 / stiffness, rel=1e-9)
        assert stiffness == pytest.approx(300.0, rel=0.02)


@pytest.mark.ros
@pytest.mark.parametrize('pair, growths', CASES)
def test_the_measured_largest_stable_stiffness_is_the_predicted_one(pair, growths):
    """Within 5 %: the bracket's middle, and each trial's growth is the largest root's."""
    mass, damping, coupling_damping, delay = pair
    device = Device(mass, damping, **HAND)
    predicted = largest_stable_stiffness(**loop(device, coupling_damping, delay))
    low, high, trials = measure_largest_stable(predicted, coupling_damping, device, delay)
    assert high / low < 1.02
    assert abs(math.sqrt(low * high) / predicted - 1.0) < 0.05
    for _, measured, expected in trials:
        assert measured == pytest.approx(expected, abs=0.02)
    assert [round(measured, 6) for _, measured, _ in trials] == growths
