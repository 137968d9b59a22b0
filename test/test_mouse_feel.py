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

"""How a click and a drag move the body: bounds, guide, velocity feed-forward, jumps."""

import math

import numpy as np
import pytest

from mouse_constraint_ros.physics import MouseConstraint, MouseSimulation, RigidBody, Settings
from mouse_constraint_ros.physics.settings import friction_torque_bound, weight_scale
from mouse_constraint_ros.physics.target_motion import Guide, TargetMotion
from mouse_constraint_ros.physics.target_stream import TargetStream
from test_support.mouse_feel import circle, click, far_click, seed_joint, SOFT

CORNER = (0.2, 0.1, 0.05)


def test_a_click_with_the_shipped_parameters_carries_the_body_over_gently():
    """A 0.5 m click: peak COM speed <= 5 m/s, spin <= 30 rad/s, anchor on target by 1.5 s."""
    result = click()
    assert result.peak_speed <= 5.0
    assert result.peak_angular_speed <= 30.0
    assert result.error_at_settle <= 0.005
    assert result.error_after_settle <= 0.005
    # Not growing: the last second is no worse than the settle time's bound.
    assert result.error_last_second <= 0.005


@pytest.mark.parametrize('substeps', [1, 2, 16])
def test_a_far_click_on_the_floor_drags_the_resting_box_without_rolling_it(substeps):
    """
    Clicked 4 m away on the floor, the box resting there: the click's bounds hold.

    The corner is dragged along the floor; the box tips over and slides, spin <= 30 rad/s, and
    the COM no faster than 3 m/s (the guide's 2 m/s and the box turning about its corner).
    """
    peak_speed, peak_spin = far_click({'substeps': substeps})
    assert peak_spin <= 30.0
    assert peak_speed <= 3.0


def test_the_seed_joint_flings_the_body_on_the_same_click():
    """Without the bounds the same click flings and spins the body (what the bounds prevent)."""
    result = click(seed_joint())
    assert result.peak_speed > 5.0
    assert result.peak_angular_speed > 30.0


@pytest.mark.parametrize('mass', [0.01, 100.0])
def test_force_and_torque_bounds_hold_at_every_substep(mass):
    """|F| <= k m g and the friction torque <= c m g sqrt(I/m), each substep, light or heavy."""
    body = RigidBody.solid_box(mass, (0.4, 0.2, 0.1))
    constraint = MouseConstraint(anchor=CORNER, max_force_per_weight=5.0, angular_friction=0.25)
    settings = Settings(body, constraint, substeps=1)
    simulation = MouseSimulation(settings)
    simulation.target = (0.5, 0.3, 0.2)
    force_bound = 5.0 * weight_scale(settings)
    torque_bound = friction_torque_bound(settings)
    forces, torques = [], []
    for _ in range(3000):
        simulation.step(1e-3)
        forces.append(math.hypot(*simulation.constraint_force))
        torques.append(simulation.friction_torque)
    assert max(forces) <= force_bound * (1.0 + 1e-12)
    assert max(torques) <= torque_bound * (1.0 + 1e-12)
    # Both bounds bind (the jump asks for more), and scale with the mass.
    assert max(forces) == pytest.approx(force_bound)
    assert max(torques) == pytest.approx(torque_bound)
    assert math.hypot(*simulation.anchor_error()) < 1e-3


def test_zero_gravity_does_not_make_a_dead_joint():
    """With zero gravity the weight bound uses the standard gravity: the joint still pulls."""
    body = RigidBody.solid_box(2.0, (0.4, 0.2, 0.1))
    settings = Settings(body, MouseConstraint(max_force_per_weight=1.0), gravity=(0.0, 0.0, 0.0))
    simulation = MouseSimulation(settings)
    simulation.target = (0.1, 0.0, 0.0)
    simulation.step(1e-3)
    assert math.hypot(*simulation.constraint_force) == pytest.approx(2.0 * 9.80665)


def test_the_guide_stops_on_the_goal_within_its_bounds():
    """Speed and acceleration stay bounded; the guide lands on the goal and rests there."""
    guide = Guide((0.0, 0.0, 0.0))
    h, speed, acceleration = 5e-4, 2.0, 20.0
    positions, velocities = [guide.position], [guide.velocity]
    for _ in range(2000):
        guide.advance((0.5, 0.0, 0.0), (0.0, 0.0, 0.0), h, speed, acceleration)
        positions.append(guide.position)
        velocities.append(guide.velocity)
    v = np.array(velocities)
    assert np.linalg.norm(v, axis=1).max() <= speed * (1.0 + 1e-12)
    assert np.linalg.norm(np.diff(v, axis=0), axis=1).max() <= acceleration * h * (1 + 1e-9)
    assert np.array(positions)[:, 0].max() <= 0.5 + 1e-12  # no overshoot
    assert guide.position == pytest.approx((0.5, 0.0, 0.0), abs=1e-12)
    assert guide.velocity == pytest.approx((0.0, 0.0, 0.0), abs=1e-12)


def test_a_jump_in_a_stream_is_not_taken_for_a_velocity():
    """Points at 1 m/s give 1 m/s; a 0.5 m jump or a point after a pause gives zero."""
    stream = TargetStream()
    for k in range(10):
        assert stream.add((0.02 * k, 0.0, 0.0), 0.02 * k, 2.0) == (k > 0)
    assert stream.velocity == pytest.approx((1.0, 0.0, 0.0))
    assert not stream.add((0.68, 0.0, 0.0), 0.2, 2.0)
    assert stream.velocity == (0.0, 0.0, 0.0)
    stream.add((0.70, 0.0, 0.0), 0.22, 2.0)
    assert not stream.add((0.75, 0.0, 0.0), 1.5, 2.0)
    assert stream.velocity == (0.0, 0.0, 0.0)
    assert not stream.add((0.76, 0.0, 0.0), None, 2.0)
    assert stream.velocity == (0.0, 0.0, 0.0)


def test_a_jump_during_a_drag_moves_the_body_like_a_click():
    """A 0.5 m jump in the middle of a 50 Hz stream: the body is not flung along a velocity."""
    simulation = MouseSimulation(*_shipped())
    simulation.target = simulation.anchor_position()
    start = np.array(simulation.anchor_position())
    peak = 0.0
    for tick in range(3000):
        if tick % 20 == 0 and tick <= 1000:
            point = start + (0.5 * tick / 1000 + (0.5 if tick == 1000 else 0.0), 0.0, 0.0)
            simulation.set_target(tuple(point), time=simulation.time)
            if tick == 1000:
                assert simulation.target_velocity == (0.0, 0.0, 0.0)
        state = simulation.step(1e-3)
        peak = max(peak, math.hypot(*state.linear_velocity))
    assert peak <= 5.0
    assert math.hypot(*simulation.anchor_error()) < 1e-3


def test_the_velocity_estimate_is_robust_to_irregular_arrival_times():
    """Points of a 1 m/s line arriving up to 8 ms late: the fit beats a two-point difference."""
    random = np.random.default_rng(3)
    stream = TargetStream()
    estimates, differences, previous = [], [], None
    for k in range(200):
        point, time = (0.02 * k, 0.0, 0.0), 0.02 * k + random.uniform(0.0, 0.008)
        stream.add(point, time, 2.0)
        if k >= 10:
            estimates.append(stream.velocity[0])
            differences.append((point[0] - previous[1][0]) / (time - previous[0]))
        previous = (time, point)

    def rms(values):
        return float(np.sqrt(np.mean(np.square(np.array(values) - 1.0))))

    assert rms(estimates) < 0.1
    assert rms(estimates) * 2.0 < rms(differences)


@pytest.mark.parametrize('jitter', [0.0, 0.005])
def test_velocity_feed_forward_cuts_the_soft_drag_lag_five_fold(jitter):
    """A target circling at 1 m/s, 50 Hz, soft 7.5 Hz joint: the error falls >= 5-fold."""
    unguided = dict(SOFT, max_target_speed=math.inf, max_target_acceleration=math.inf)
    with_ff = circle(unguided, jitter=jitter)
    without = circle(unguided, jitter=jitter, target_feed_forward=False)
    assert with_ff * 5.0 <= without


def test_gravity_feed_forward_removes_the_soft_spring_sag():
    """A soft spring holding a hanging body sags by about g / omega^2 unless it carries it."""
    body = RigidBody.solid_box(2.0, (0.4, 0.2, 0.1))
    omega = 2.0 * math.pi * 7.5
    sags = []
    for carry in (False, True):
        settings = Settings(body, MouseConstraint(anchor=(0.0, 0.0, 0.05), frequency_hz=7.5,
                                                  gravity_feed_forward=carry),
                            angular_damping=5.0, linear_damping=5.0, substeps=2)
        simulation = MouseSimulation(settings)
        simulation.target = simulation.anchor_position()
        for _ in range(3000):
            simulation.step(1e-3)
        sags.append(-simulation.anchor_error()[2])
    assert sags[0] == pytest.approx(9.80665 / omega ** 2, rel=0.05)
    assert abs(sags[1]) < 0.01 * sags[0]


def test_untimed_targets_and_the_default_motion_keep_the_seed_joint():
    """TargetMotion() hands the target over as given: the same states as no motion at all."""
    body = RigidBody.solid_box(2.0, (0.4, 0.2, 0.1))
    runs = []
    for timed in (False, True):
        simulation = MouseSimulation(Settings(body, MouseConstraint(anchor=CORNER), substeps=2))
        for k in range(200):
            point = (0.01 * k, 0.0, 0.0)
            if timed:
                simulation.set_target(point, time=simulation.time)
            else:
                simulation.target = point
            simulation.step(1e-3)
        runs.append(simulation.state)
    assert runs[0] == runs[1]


def test_target_motion_is_validated():
    """Invalid bounds are refused with the parameter's name."""
    with pytest.raises(ValueError, match='max_target_speed'):
        TargetMotion(max_speed=0.0)
    with pytest.raises(ValueError, match='max_target_acceleration'):
        TargetMotion(max_acceleration=math.nan)
    with pytest.raises(ValueError, match='feed_forward'):
        TargetMotion(feed_forward=1)


def _shipped() -> tuple:
    """Return the settings and initial state of config/params.yaml (above its floor)."""
    from test_support.mouse_feel import configured
    config = configured({})
    return config.settings, config.initial_state


def test_a_drag_that_stops_ends_on_the_last_point():
    """
    Extrapolation runs out 1.5 intervals after the last point: the anchor ends on it.

    The guide rests on the last point exactly; the body swings on from the drag, so the rigid
    joint holds the anchor there to its residual on a swinging body (2 um at 4 rad/s).
    """
    simulation = MouseSimulation(*_shipped())
    simulation.target = simulation.anchor_position()
    start = np.array(simulation.anchor_position())
    for tick in range(2000):
        if tick % 20 == 0 and tick <= 500:
            last = tuple(start + (0.001 * tick, 0.0, 0.0))
            simulation.set_target(last, time=simulation.time)
        simulation.step(1e-3)
        if tick == 505:
            # Still extrapolating the 1 m/s stream.
            assert simulation.joint_target[0] > last[0]
    assert simulation.joint_target == last
    assert math.dist(simulation.anchor_position(), last) < 1e-5
