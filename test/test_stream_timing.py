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
A browser's drag timed by its stamps: the stream follows the curve (core and through ROS).

The scenario and metrics are ``test_support.stream_timing``'s (docs/dragging.md); the figures
through ROS are ``python -m bench.stream_timing``'s, not asserted here.
"""

import math

from hypothesis import given, settings, strategies as st
import numpy as np
import pytest

from mouse_constraint_ros.physics.target_stream import BLEND_INTERVALS, STAMPED_WINDOW
from mouse_constraint_ros.physics.target_stream import TargetStream
from test_support.mouse_feel import shipped_parameters
from test_support.stream_timing import circle, replay, SPEED


def exactly(value: float):
    """Return ``value`` to compare to rounding."""
    return pytest.approx(value, abs=1e-9)


def _circle_points(rate_hz: float, count: int):
    path = circle((0.0, 0.0, 1.0))
    return [(k / rate_hz, tuple(path(k / rate_hz))) for k in range(count)]


def test_a_stamped_circle_is_not_flattened():
    """20 Hz stamps of a circle: the velocity is the tangent at 1 m/s, within 1 %."""
    stamped, arrival = TargetStream(), TargetStream()
    errors = {id(stamped): [], id(arrival): []}
    path = circle((0.0, 0.0, 1.0))
    for t, point in _circle_points(20.0, 40):
        stamped.add(point, t, 2.0, t + 0.03)
        arrival.add(point, t, 2.0)
        if t >= STAMPED_WINDOW:
            truth = (path(t + 1e-6) - path(t - 1e-6)) / 2e-6
            for stream in (stamped, arrival):
                errors[id(stream)].append(np.linalg.norm(np.subtract(stream.velocity, truth)))
    assert max(errors[id(stamped)]) <= 0.01 * SPEED
    # The arrival-timed parabola over as many points takes the circle for a flatter curve.
    assert min(errors[id(arrival)]) >= 5.0 * max(errors[id(stamped)])


def test_a_late_stream_is_presented_at_its_latency_and_extrapolated_one_gap_at_most():
    """
    A line at 1 m/s, points 50 ms apart, each arriving 30 ms after its stamp.

    The stream is presented 30 ms late (its latency): the target is where the line was 30 ms
    ago, up to one interval past the latest point (50 ms, the latencies all alike); then it
    eases back to the latest point over as long, and rests there.
    """
    stream = TargetStream()
    for k in range(10):
        t = 0.05 * k
        stream.add((t, 0.0, 0.0), t, 2.0, t + 0.03)
    assert stream.delay == exactly(0.03) and stream.horizon == exactly(0.05)
    arrived = 0.45 + 0.03
    position, velocity = stream.predict(arrived + 0.02)
    assert position == (exactly(0.45 + 0.02), 0.0, 0.0)
    assert velocity[0] == exactly(1.0)
    # The horizon: 50 ms past the latest point at most, however late the next one is.
    cap = 0.45 + 0.03 + 0.05
    assert stream.predict(cap)[0][0] == exactly(0.5)
    position, velocity = stream.predict(cap + 0.025)
    assert 0.45 < position[0] < 0.5 and velocity[0] < 0.0
    # Eased back at 1.5 times the speed it had, at most; then at rest on the latest point.
    assert min(stream.predict(cap + 0.05 * f)[1][0] for f in np.linspace(0.0, 1.0, 51)) == \
        pytest.approx(-1.5, abs=1e-9)
    assert stream.predict(cap + 0.05 + 1e-6) == ((0.45, 0.0, 0.0), (0.0, 0.0, 0.0))


def test_a_jittering_still_pointer_is_not_extrapolated():
    """Still points jittering by 2 mm: the fit takes degree 0 (the data bear no curve)."""
    random = np.random.default_rng(4)
    stream = TargetStream()
    for k in range(40):
        t = k / 60.0
        stream.add((*random.uniform(-0.002, 0.002, 2), 1.0), t, 2.0, t + 0.1)
    assert stream.velocity == (0.0, 0.0, 0.0)
    assert stream.predict(40 / 60.0 + 0.1)[0] == stream._latest[1]


def test_a_new_stamped_fit_is_blended_in_without_a_jump():
    """At a point's arrival the target goes on from where it was; an interval on, the new fit."""
    stream = TargetStream()
    points = _circle_points(20.0, 12)
    for t, point in points[:-1]:
        stream.add(point, t, 2.0, t + 0.02)
    t_new, new = points[-1]
    arrival = t_new + 0.02
    before = stream.predict(arrival)
    stream.add(new, t_new, 2.0, arrival)
    after = stream.predict(arrival)
    assert np.allclose(after[0], before[0], atol=1e-12)
    assert np.allclose(after[1], before[1], atol=1e-9)
    # The old fit's extrapolation over 70 ms is off the new point's fit; a blend has ended.
    done = arrival + BLEND_INTERVALS * 0.05
    settled = stream.predict(done + 1e-6)
    fresh = TargetStream()
    for t, point in points:
        fresh.add(point, t, 2.0, t + 0.02)
    assert np.allclose(settled[0], fresh.predict(done + 1e-6)[0], atol=1e-12)


def test_stamps_after_arrival_times_or_a_jump_in_latency_start_a_new_stream():
    """
    Times on two clocks are not one fit: the velocity starts from zero again.

    An unstamped point in a stamped stream is put on the stamps' base instead (its arrival less
    the stream's median latency): the stream goes on.
    """
    stream = TargetStream()
    for k in range(5):
        stream.add((0.02 * k, 0.0, 0.0), 0.02 * k, 2.0)
    assert stream.velocity[0] == exactly(1.0)
    assert not stream.add((0.1, 0.0, 0.0), 0.1, 2.0, 0.11)
    assert stream.velocity == (0.0, 0.0, 0.0)
    for k in range(6, 10):
        assert stream.add((0.02 * k, 0.0, 0.0), 0.02 * k, 2.0, 0.02 * k + 0.01)
    # Unstamped, arriving 10 ms after its event like the others: on the same base.
    assert stream.add((0.2, 0.0, 0.0), 0.21, 2.0)
    assert stream.velocity[0] == exactly(1.0)
    # A latency 100 ms longer than the stream's: another path.
    assert not stream.add((0.22, 0.0, 0.0), 0.22, 2.0, 0.33)
    assert stream.velocity == (0.0, 0.0, 0.0) and stream.delay == exactly(0.11)


def test_stamps_through_the_nodes_timing_path_follow_a_20_hz_circle():
    """The drag replayed on the core as the node times it: the targets of docs/dragging.md."""
    stamped = replay(20.0, True, 4.0)
    arrival = replay(20.0, False, 4.0)
    assert stamped.error <= 0.003 and stamped.speed_deviation <= 0.03
    assert stamped.error * 5.0 <= arrival.error
    fast = replay(60.0, True, 3.0)
    assert fast.error <= 0.001 and fast.speed_deviation <= 0.02


def test_with_dropped_ticks_a_stamped_drag_still_beats_one_timed_by_arrival():
    """Spells of 30-100 ms without ticks (a loaded machine): the stamped stream starts again."""
    drops = [(1.5, 0.03), (2.5, 0.06), (3.5, 0.1)]
    stamped = replay(20.0, True, 4.5, drops=drops)
    arrival = replay(20.0, False, 4.5, drops=drops)
    assert stamped.error < arrival.error
    assert stamped.speed_deviation < arrival.speed_deviation


def test_the_node_times_targets_by_their_stamps(simulated_body_factory):
    """
    Arrivals delayed by 0-40 ms, stamps exact: the node's velocity estimate is the line's.

    A line at 1 m/s, one point every 50 ms, each sent a random 0-40 ms (in 5 ms ticks) after
    the time it is stamped with and placed at. Timed by arrival the estimate would wander by
    tens of percent (the same arrivals fed to an arrival-timed stream say how much); timed by
    the stamps it is the line's velocity (to rounding; 0.1 % allowed).
    """
    parameters = shipped_parameters()
    for name in ('publish_clock', 'real_time_factor'):
        parameters.pop(name, None)
    body = simulated_body_factory(**dict(parameters, rate_hz=200.0))
    body.step(20)
    start = np.array(body.node.simulation.anchor_position())
    random = np.random.default_rng(5)
    by_arrival = TargetStream()
    estimates, arrival_estimates = [], []
    began = body.time + 0.005
    for k in range(16):
        event = began + k * 0.05
        send = event + 0.005 * int(random.integers(0, 9))
        body.step_until(lambda: body.time >= send - 1e-9, max_ticks=100)
        point = tuple(start + ((event - began) * SPEED, 0.0, 0.0))
        body.target(point, stamp=event, frame_id=parameters['frame_id'])
        assert body.node.simulation.target == point
        by_arrival.add(point, body.time, math.inf)
        if k >= 3:
            estimates.append(body.node.simulation.target_velocity)
            arrival_estimates.append(by_arrival.velocity)
    stamped_error = max(abs(v[0] - SPEED) + abs(v[1]) + abs(v[2]) for v in estimates)
    arrival_error = max(abs(v[0] - SPEED) for v in arrival_estimates)
    # The delays were irregular enough to tell the two apart: timed by arrival, off by > 2 %.
    assert arrival_error > 0.02
    assert stamped_error < 1e-3


@pytest.mark.parametrize('degree', [1, 2, 3, 4])
def test_stamped_motion_of_degree_up_to_four_is_extrapolated_exactly(degree):
    """
    Points on a polynomial of degree <= 4 in time: position and velocity ahead, exact.

    Each arrives 10 ms after its stamp: the motion is presented 10 ms late.
    """
    def motion(t: float):
        return (0.3 * t ** degree + 0.1 * t, -0.2 * t ** degree, 1.0)

    def rate(t: float):
        return (0.3 * degree * t ** (degree - 1) + 0.1, -0.2 * degree * t ** (degree - 1), 0.0)

    stream = TargetStream()
    for k in range(12):
        t = 0.5 + 0.03 * k
        stream.add(motion(t), t, math.inf, t + 0.01)
    later = 0.5 + 0.03 * 11 + 0.025  # within the horizon: one interval past the latest
    position, velocity = stream.predict(later + 0.01)
    assert position == pytest.approx(motion(later), abs=1e-9)
    assert velocity == pytest.approx(rate(later), abs=1e-7)


def test_a_stamped_stream_that_goes_on_unstamped_past_its_window_holds():
    """Stamped points, then 0.6 s of unstamped ones only: the fit anchors on what it has."""
    stream = TargetStream()
    for k in range(10):
        stream.add((0.02 * k, 0.0, 0.0), 0.02 * k, 2.0, 0.02 * k + 0.01)
    for k in range(10, 40):
        assert stream.add((0.02 * k, 0.0, 0.0), 0.02 * k + 0.01, 2.0)
    assert stream.velocity[0] == pytest.approx(1.0, abs=1e-6)


def test_points_of_one_arrival_time_end_the_stream_at_the_last_one():
    """
    A burst of unstamped points in a stamped stream, all placed at one time: the newest wins.

    The flood of a script that stamps every point alike: after the first, its stamps are not
    later than the last used, so the points come timed by their arrival, many in one tick; the
    stream stopped, the target rests at the last point sent, not at the first of its tick.
    """
    stream = TargetStream()
    stream.add((0.0, 0.0, 0.0), 0.0, 2.0, 0.001)
    for k in range(1, 21):
        stream.add((0.0005 * k, 0.0, 0.0), 0.002, 2.0)  # one tick's arrival, 20 points
    position, velocity = stream.predict(10.0)
    assert position == (0.01, 0.0, 0.0) and velocity == (0.0, 0.0, 0.0)


@settings(max_examples=300, deadline=None)
@given(st.lists(st.tuples(
    st.floats(-1.0, 1.0), st.floats(0.0, 0.3), st.one_of(st.none(), st.floats(-0.01, 0.3)),
    st.booleans()), min_size=1, max_size=60))
def test_any_sequence_of_points_gives_a_finite_target(steps):
    """Stamped, unstamped, untimed and out-of-order points in any mix: never a failure."""
    stream, time = TargetStream(), 0.0
    for x, gap, latency, timed in steps:
        time += gap
        arrival = None if latency is None else time + latency
        stream.add((x, 0.0, 1.0), time if timed else None, 2.0, arrival if timed else None)
        if stream.has_points():
            for later in (0.0, 0.01, 0.1, 1.0):
                position, velocity = stream.predict(time + later)
                assert all(math.isfinite(c) for c in (*position, *velocity))
