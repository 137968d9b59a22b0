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

"""The simulation against exact dynamics: convergence, pendulum, spin, soft spring, max force."""

import math

import numpy as np
import pytest
from scipy.spatial.transform import Rotation

from mouse_constraint_ros.physics import BodyState
from mouse_constraint_ros.physics import MouseConstraint
from mouse_constraint_ros.physics import MouseSimulation
from mouse_constraint_ros.physics import RigidBody
from mouse_constraint_ros.physics import Settings
from test_support.reference_dynamics import GRAVITY
from test_support.reference_dynamics import hanging_rotation
from test_support.reference_dynamics import pendulum_com_path
from test_support.reference_dynamics import small_oscillation_modes

NO_GRAVITY = (0.0, 0.0, 0.0)
BOX = RigidBody.solid_box(2.0, (0.4, 0.2, 0.1))
CORNER = (0.2, 0.1, 0.05)


def error_norm(sim: MouseSimulation) -> float:
    """Return |C|, the anchor's distance from the target."""
    return float(np.linalg.norm(sim.anchor_error()))


@pytest.mark.parametrize('anchor, offset', [
    ((0.0, 0.0, 0.0), (0.003, -0.002, 0.001)),
    # Off the COM, an error along r pulls through the COM and starts no rotation.
    (CORNER, tuple(0.02 * np.array(CORNER))),
])
@pytest.mark.parametrize('baumgarte', [0.2, 0.5, 1.0])
def test_static_target_error_shrinks_by_one_minus_delta(anchor, offset, baumgarte):
    """
    Test 3: rigid mode, no gravity: |C| shrinks by (1 - delta) per step, to below 1e-9 m.

    An error across r would start the body spinning about the anchor, and a spinning body's
    anchor drifts by O(h^2 |w|^2 |r|) per step, a floor that Baumgarte holds but cannot remove.
    """
    sim = MouseSimulation(Settings(BOX, MouseConstraint(anchor=anchor, baumgarte=baumgarte),
                                   gravity=NO_GRAVITY))
    sim.target = tuple(np.add(sim.anchor_position(), offset))
    errors = [error_norm(sim)]
    for _ in range(200):
        sim.step(0.001)
        errors.append(error_norm(sim))
    errors = np.array(errors)
    resolved = errors[:-1] > 1e-10
    ratios = errors[1:][resolved] / errors[:-1][resolved]
    np.testing.assert_allclose(ratios, 1.0 - baumgarte, atol=1e-6)
    assert errors[-1] < 1e-9


def pendulum(tilt: Rotation, anchor, h: float, duration: float, substeps: int = 1):
    """Return the COM path and largest anchor error of the box hung rigidly by ``anchor``."""
    anchor = np.asarray(anchor)
    orientation = tilt * hanging_rotation(anchor)
    pivot = np.array([0.0, 0.0, 1.0])
    settings = Settings(BOX, MouseConstraint(anchor=tuple(anchor)), gravity=(0.0, 0.0, -GRAVITY),
                        substeps=substeps)
    sim = MouseSimulation(settings, BodyState(tuple(pivot - orientation.apply(anchor)),
                                              tuple(orientation.as_quat())))
    sim.target = tuple(pivot)
    path = [sim.state.position]
    drift = 0.0
    for _ in range(int(round(duration / h))):
        sim.step(h)
        path.append(sim.state.position)
        drift = max(drift, error_norm(sim))
    return np.array(path), drift, orientation, pivot


def test_corner_pendulum_follows_the_exact_motion():
    """Test 4: box hung by a corner, 20 degrees from hanging: COM RMS <= 0.5 mm over 5 s."""
    h, duration = 0.001, 5.0
    path, drift, orientation, pivot = pendulum(
        Rotation.from_rotvec([math.radians(20.0), 0.0, 0.0]), CORNER, h, duration)
    times = h * np.arange(len(path))
    exact = pendulum_com_path(BOX.mass, BOX.inertia, CORNER, pivot, orientation, times)
    rms = np.sqrt(np.mean(np.sum((path - exact) ** 2, axis=1)))
    assert rms <= 0.5e-3
    # It really swings: the COM travels far more than the error.
    assert np.ptp(exact, axis=0).max() > 0.05
    assert drift < 1e-5


def test_corner_pendulum_small_oscillation_periods():
    """Test 4: both small-oscillation periods within 0.5 % of the linearized analytic ones."""
    periods, shapes = small_oscillation_modes(BOX.mass, BOX.inertia, CORNER)
    assert len(periods) == 2 and abs(periods[0] - periods[1]) > 0.01
    hanging_com = -hanging_rotation(np.array(CORNER)).apply(CORNER)
    h = 0.001
    for period, shape in zip(periods, shapes):
        # Released 1 degree along the mode: the swing is a clean sinusoid at that mode's period.
        tilt = Rotation.from_rotvec(math.radians(1.0) * shape / np.linalg.norm(shape))
        path, _, _, pivot = pendulum(tilt, CORNER, h, 6.0 * period)
        direction = np.cross(shape, hanging_com)
        signal = (path - (pivot + hanging_com)) @ (direction / np.linalg.norm(direction))
        crossings = np.nonzero(np.sign(signal[:-1]) * np.sign(signal[1:]) < 0)[0]
        times = h * (crossings - signal[crossings] / (signal[crossings + 1] - signal[crossings]))
        measured = 2.0 * np.mean(np.diff(times))
        assert len(crossings) >= 10
        assert measured == pytest.approx(period, rel=0.005)


def test_free_body_spinning_near_its_intermediate_axis_keeps_energy_and_momentum():
    """Test 5: the tumbling box keeps its kinetic energy and |L| over 10 s at h = 1 ms."""
    body = RigidBody.solid_box(1.0, (0.4, 0.25, 0.1))
    sim = MouseSimulation(Settings(body, gravity=NO_GRAVITY),
                          BodyState(angular_velocity=(0.01, 6.0, 0.01)))
    energy0, momentum0 = sim.kinetic_energy(), np.array(sim.angular_momentum())
    energies, momenta, spin_y = [], [], []
    for _ in range(10000):
        sim.step(0.001)
        energies.append(sim.kinetic_energy())
        momenta.append(sim.angular_momentum())
        rotation = Rotation.from_quat(sim.state.orientation)
        spin_y.append(rotation.inv().apply(sim.state.angular_velocity)[1])
    momenta = np.array(momenta)
    # The intermediate axis is unstable: the body flips over (Dzhanibekov) at least once.
    assert min(spin_y) < -5.0
    assert np.max(np.abs(np.array(energies) / energy0 - 1.0)) < 0.01
    assert np.max(np.abs(np.linalg.norm(momenta, axis=1) / np.linalg.norm(momentum0) - 1.0)) < 0.01
    # Stronger than asked: the implicit midpoint rule keeps both to rounding, and L's direction.
    assert np.max(np.abs(np.array(energies) / energy0 - 1.0)) < 1e-9
    assert np.max(np.linalg.norm(momenta - momentum0, axis=1)) < 0.01 * np.linalg.norm(momentum0)


def test_a_fast_spin_beyond_the_step_never_gains_energy():
    """Even where |w| h ~ 5 the gyroscopic step cannot converge, the energy does not grow."""
    body = RigidBody.solid_box(1.0, (0.4, 0.25, 0.1))
    sim = MouseSimulation(Settings(body, gravity=NO_GRAVITY),
                          BodyState(angular_velocity=(10.0, 5000.0, 10.0)))
    energy = sim.kinetic_energy()
    for _ in range(2000):
        sim.step(0.001)
        assert sim.kinetic_energy() <= energy * (1.0 + 1e-12)
        energy = sim.kinetic_energy()
    assert all(math.isfinite(c) for c in sim.state.angular_velocity)


def test_free_fall_is_exact_at_every_tick():
    """
    No target: a free body. Started half a step back, symplectic Euler is leapfrog: exact.

    The position at every tick is x0 + v0 t + g t^2 / 2 to rounding, and the published velocity
    is the half-step one, v0 + g (t - h / 2): the difference of consecutive positions over h.
    """
    h, steps = 0.002, 500
    sim = MouseSimulation(Settings(BOX), BodyState(linear_velocity=(1.0, 0.0, 2.0)))
    g = sim.settings.gravity[2]
    for n in range(1, steps + 1):
        sim.step(h)
        t = n * h
        assert sim.state.position == pytest.approx((t, 0.0, 2.0 * t + g * t * t / 2.0),
                                                   abs=1e-12)
        assert sim.state.linear_velocity == pytest.approx((1.0, 0.0, 2.0 + g * (t - h / 2.0)),
                                                          abs=1e-12)
    assert sim.constraint_force == (0.0, 0.0, 0.0)


@pytest.mark.parametrize('h, substeps', [(0.001, 1), (1 / 60, 1), (1 / 60, 4)])
def test_soft_mode_rings_at_the_requested_frequency_and_damping(h, substeps):
    """Test 6: anchor at the COM, f = 5 Hz, zeta = 0.1: measured f and zeta within 2 %."""
    frequency, damping_ratio = 5.0, 0.1
    constraint = MouseConstraint(frequency_hz=frequency, damping_ratio=damping_ratio)
    sim = MouseSimulation(Settings(BOX, constraint, gravity=NO_GRAVITY, substeps=substeps))
    direction = np.array([1.0, -2.0, 0.5]) / np.linalg.norm([1.0, -2.0, 0.5])
    sim.target = tuple(0.1 * direction)
    signal = [-0.1]
    for _ in range(int(round(3.0 / h))):
        sim.step(h)
        signal.append(np.dot(sim.anchor_error(), direction))
    signal = np.array(signal)
    crossings = np.nonzero(np.sign(signal[:-1]) * np.sign(signal[1:]) < 0)[0]
    times = h * (crossings - signal[crossings] / (signal[crossings + 1] - signal[crossings]))
    damped = 1.0 / (2.0 * np.mean(np.diff(times)))
    natural = damped / math.sqrt(1.0 - damping_ratio ** 2)
    assert natural == pytest.approx(frequency, rel=0.02)
    # Logarithmic decrement between the first and the last whole period of samples.
    periods = int(3.0 * damped) - 1
    start = int(round(times[0] / h))
    stop = start + int(round(periods / (damped * h)))
    decrement = np.log(np.abs(signal[start - 1: start + 2]).max() /
                       np.abs(signal[stop - 1: stop + 2]).max()) / periods
    measured_zeta = decrement / math.sqrt(4.0 * math.pi ** 2 + decrement ** 2)
    if h == 0.001:
        assert measured_zeta == pytest.approx(damping_ratio, rel=0.02)
    else:
        # At a coarse step the samples miss the peaks; the decay is still the requested one.
        assert measured_zeta == pytest.approx(damping_ratio, rel=0.05)


@pytest.mark.parametrize('frequency_hz', [0.0, 3.0])
@pytest.mark.parametrize('substeps', [1, 4])
def test_max_force_bounds_the_momentum_change(frequency_hz, substeps):
    """
    Test 7: |m dv - m g dt| <= F_max dt every step, and the bound is reached.

    The first step also moves the given velocities back half a substep h (the leapfrog start,
    see ``kernel.stagger``): by gravity's m g h / 2 and the constraint's reaction,
    bounded by F_max h / 2.
    """
    max_force, dt = 15.0, 0.002
    constraint = MouseConstraint(anchor=CORNER, frequency_hz=frequency_hz, damping_ratio=1.0,
                                 max_force=max_force)
    sim = MouseSimulation(Settings(BOX, constraint, substeps=substeps))
    sim.target = (2.0, 0.5, 1.0)
    gravity = np.array(sim.settings.gravity)
    largest = 0.0
    for i in range(1500):
        before = np.array(sim.state.linear_velocity)
        sim.step(dt)
        change = BOX.mass * (np.array(sim.state.linear_velocity) - before - gravity * dt)
        if i == 0:
            half = 0.5 * dt / substeps
            bound = max_force * (dt + half) + BOX.mass * np.linalg.norm(gravity) * half
        else:
            bound = max_force * dt
            largest = max(largest, np.linalg.norm(change))
        assert np.linalg.norm(change) <= bound * (1.0 + 1e-9)
        assert np.linalg.norm(sim.constraint_force) <= max_force * (1.0 + 1e-9)
    assert largest == pytest.approx(max_force * dt, rel=1e-6)


def test_soft_critically_damped_drag_reaches_a_far_target_under_max_force():
    """
    Test 7: a critically damped soft joint with limited force still brings the anchor 2 m.

    Some angular damping lets the spin the drag starts die out; a body that keeps spinning about
    its anchor needs a centripetal force, which a spring only makes by stretching.
    """
    constraint = MouseConstraint(anchor=CORNER, frequency_hz=2.0, damping_ratio=1.0,
                                 max_force=10.0)
    sim = MouseSimulation(Settings(BOX, constraint, gravity=NO_GRAVITY, angular_damping=3.0))
    start = np.array(sim.anchor_position())
    sim.target = tuple(start + np.array([2.0, 0.0, 0.0]))
    saturated = False
    for _ in range(10000):
        sim.step(0.001)
        saturated |= np.linalg.norm(sim.constraint_force) > 10.0 * (1.0 - 1e-9)
    assert saturated
    assert error_norm(sim) < 1e-3


@pytest.mark.parametrize('frequency_hz, damping_ratio, dt', [
    (0.0, 1.0, 1 / 30), (50.0, 3.0, 1 / 30), (50.0, 0.1, 1 / 30), (5.0, 1.0, 0.001)])
def test_the_leapfrog_start_adds_no_energy_at_a_still_target(frequency_hz, damping_ratio, dt):
    """
    A moving, spinning body whose anchor sits on the target: the first step removes energy.

    The constraint can only take the anchor's velocity away here (no error to correct, no
    gravity), and so can the half-substep start (a spring the step cannot resolve is started
    like rigid mode: a first-order kick of it would add energy).
    """
    body = RigidBody.solid_box(1.0, (0.4, 0.2, 0.1))
    constraint = MouseConstraint(anchor=(0.2, 0.0, 0.0), frequency_hz=frequency_hz,
                                 damping_ratio=damping_ratio)
    sim = MouseSimulation(Settings(body, constraint, gravity=NO_GRAVITY),
                          BodyState(linear_velocity=(0.0, 1.0, 0.0),
                                    angular_velocity=(1.0, 2.0, 3.0)))
    sim.target = sim.anchor_position()
    energy = sim.kinetic_energy()
    sim.step(dt)
    assert sim.kinetic_energy() <= energy
