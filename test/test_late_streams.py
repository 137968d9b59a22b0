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
A pointer as a network delivers it, through the node in lockstep: never flung, never amplified.

Each row of docs/dragging.md's latency table is a test here, with the shipped parameters, the
node stepped on simulated time (``test_support.late_streams``): a stop overshoots by at most
a stream gap of travel (+5 mm), a slowing drag by at most 10 mm, late or not, sent evenly or
as a browser sends it; a still pointer's jitter is not amplified; a stream mixing stamped and
unstamped points, or late, is followed smoothly; a corner pressed into the floor is not flung;
a flat elastic drop stays where it fell. ``python -m bench.late_streams`` prints every row.
"""

import numpy as np
import pytest

from mouse_constraint_ros.physics.polynomial import around, evaluate, polynomial
from mouse_constraint_ros.physics.stream_lag import Lag
from mouse_constraint_ros.physics.target_stream import TargetStream
from test_support import floor_scenarios, late_streams, lockstep_runs
from test_support.floor_press import floor_press


def _line(latencies, count: int = 20) -> TargetStream:
    """Return a stream of a 1 m/s line, stamps 50 ms apart, the latencies taken in turn."""
    stream = TargetStream()
    for k in range(count):
        t = 0.05 * k
        stream.add((t, 0.0, 0.0), t, 2.0, t + latencies[k % len(latencies)])
    return stream


def test_a_late_stream_is_presented_later_by_its_spread_and_extrapolated_one_interval():
    """
    Latencies of 100 and 120 ms in turn: presented 120 ms late, extrapolated 50 ms.

    The horizon a stream on time needs, an interval and the 20 ms spread, is 70 ms; the late
    stream takes the spread into its delay (its lag, within a quarter of 100 ms) and is
    extrapolated one interval past its newest stamp, then eased back.
    """
    stream = _line([0.1, 0.12])
    assert stream.delay == pytest.approx(0.12, abs=1e-12)
    assert stream.horizon == pytest.approx(0.05, abs=1e-12)
    arrived = 0.95 + 0.12
    position, velocity = stream.predict(arrived)
    assert position == pytest.approx((0.95, 0.0, 0.0), abs=1e-12)
    assert velocity == pytest.approx((1.0, 0.0, 0.0), abs=1e-12)
    assert stream.predict(arrived + 0.05)[0] == pytest.approx((1.0, 0.0, 0.0), abs=1e-12)
    assert stream.predict(arrived + 0.051)[1][0] < 0.0
    # 40 and 60 ms: a quarter of the least latency, 10 ms of the spread's 20, is taken.
    stream = _line([0.04, 0.06])
    assert stream.delay == pytest.approx(0.05, abs=1e-12)
    assert stream.horizon == pytest.approx(0.06, abs=1e-12)


def test_a_stream_on_time_keeps_no_lag():
    """Latencies of 0 and 20 ms: presented at once, extrapolated an interval and the spread."""
    stream = _line([0.0, 0.02])
    assert stream.delay == 0.0
    assert stream.horizon == pytest.approx(0.07, abs=1e-12)


def test_the_lag_moves_at_five_percent_and_never_past_a_quarter_of_the_latency():
    """Aimed at 100 ms of a 200 ms stream: 50 ms at once; aimed back at 0, 5 % of the time."""
    lag = Lag()
    lag.aim(0.0, delay=0.2, need=0.1, continues=False)
    assert lag.at(0.0) == 0.05
    lag.aim(1.0, delay=0.2, need=0.0, continues=True)
    assert lag.at(1.0) == 0.05
    assert lag.at(1.5) == pytest.approx(0.025, abs=1e-15)
    assert lag.at(2.0) == 0.0 and lag.at(9.0) == 0.0


def test_a_fit_is_evaluated_before_its_anchoring_time_as_the_polynomial_it_is():
    """A late stream is presented before its newest stamp: the curve there, not its anchor."""
    curve = polynomial(1.0, (1.0, 2.0, 3.0), ((1.0, 0.0, 0.0), (0.5, 0.0, 0.0),
                                              (0.1, 0.0, 0.0), (0.01, 0.0, 0.0)))
    position, velocity = around(curve, 0.8)
    assert position == pytest.approx((1 - 0.2 + 0.02 - 0.0008 + 0.000016, 2.0, 3.0), abs=1e-15)
    assert velocity == pytest.approx((1 - 0.2 + 0.012 - 0.00032, 0.0, 0.0), abs=1e-15)
    assert around(curve, 1.3) == evaluate(curve, 1.3)


@pytest.mark.parametrize('rate', [20.0, 60.0])
@pytest.mark.parametrize('delay', [0.0, 0.2])
def test_a_drag_that_slows_to_rest_stops_where_it_was_left(rate, delay):
    """Overshoot <= 10 mm past the last point; the anchor no faster than 1.2 x the drag."""
    [row] = late_streams.stop_rows([rate], [delay], slow_down=True)
    assert row['overshoot_mm'] <= 10.0
    assert row['speed_ratio'] <= 1.2


@pytest.mark.parametrize('rate', [20.0, 60.0])
@pytest.mark.parametrize('delay', [0.0, 0.2])
def test_a_drag_that_stops_at_once_overshoots_one_gap_at_most(rate, delay):
    """Overshoot <= one stream gap of travel + 5 mm; the anchor no faster than 2 x the drag."""
    [row] = late_streams.stop_rows([rate], [delay], slow_down=False)
    assert row['overshoot_mm'] <= row['gap_mm'] + 5.0
    assert row['speed_ratio'] <= 2.0


@pytest.mark.parametrize('seed', [1, 2])
def test_a_late_browser_drag_that_stops_at_once_overshoots_one_gap_at_most(seed):
    """
    A browser's 20 Hz drag, stamped at its events, delivered 200 ms late, that stops at once.

    Its points come irregularly (``stream_timing.schedule``): the horizon a stream on time
    needs holds the latencies' spread and the intervals' jitter, 45 mm of travel here. The
    late stream is presented later by as much, and extrapolated one interval: overshoot
    <= one gap of travel + 5 mm, the anchor no faster than 2 x the drag.
    """
    [row] = late_streams.browser_stop_rows(20.0, 0.2, [seed])
    assert row['overshoot_mm'] <= row['gap_mm'] + 5.0
    assert row['speed_ratio'] <= 2.0


def test_the_undrained_ticks_are_the_node_s_ticks_drained():
    """
    The scenarios' fast path is the node's own: the same anchor at every tick, to the bit.

    A browser's late drag, every other point unstamped, 0.6 s: stepped with the executor
    drained after every tick and every state published, and as the scenarios step it.
    """
    events = [event._replace(stamped=k % 2 == 0) for k, event in
              enumerate(late_streams.browser_line_events(20.0, 0.1, 3, seconds=0.5))]
    fast = lockstep_runs.run(events, 0.6)
    drained = lockstep_runs.run(events, 0.6, drained=True)
    assert np.array_equal(fast.times, drained.times)
    assert np.array_equal(fast.anchors, drained.anchors)
    assert np.ptp(fast.anchors[:, 0]) > 0.1  # the drag moved the anchor


@pytest.mark.parametrize('delay', [0.0, 0.24])
def test_a_still_pointer_s_jitter_is_not_amplified(delay):
    """+-2 mm at 60 Hz, on time or 240 ms late: the anchor wanders <= 3 mm RMS."""
    [row] = late_streams.still_rows(60.0, [delay])
    assert row['wander_mm'] <= 3.0


def test_a_circle_of_stamped_and_unstamped_points_is_followed():
    """Every other point of a 60 Hz circle unstamped: <= 3 mm RMS from the pointer."""
    row = late_streams.circle_row(60.0, 0.0, mixed=True)
    assert row['error_mm'] <= 3.0


@pytest.mark.parametrize('rate, error_mm, wobble_pct', [(20.0, 3.0, 3.0), (60.0, 1.0, 2.0)])
def test_a_circle_on_time_is_followed_without_lag(rate, error_mm, wobble_pct):
    """A browser's 1 m/s circle on time: as close and as steady as docs/dragging.md says."""
    row = late_streams.circle_row(rate, 0.0)
    assert row['error_mm'] <= error_mm and row['wobble_pct'] <= wobble_pct


@pytest.mark.parametrize('rate, delay', [(60.0, 0.1), (20.0, 0.2)])
def test_a_late_circle_is_followed_smoothly_behind_its_received_path(rate, delay):
    """
    100 ms late at 60 Hz, 200 ms at 20 Hz: <= 3 mm RMS from the path at the delay that fits.

    Wobble <= 3 %; followed at its least latency and its lag, a quarter of that latency at
    most: 100 to 125 ms behind, 200 to 250 ms.
    """
    row = late_streams.circle_row(rate, delay, behind=None)
    assert row['error_mm'] <= 3.0 and row['wobble_pct'] <= 3.0
    assert 1e3 * delay <= row['behind_ms'] <= 1.25e3 * delay


def test_a_corner_pressed_into_the_floor_and_lifted_is_not_flung():
    """A resting box's corner pushed 0.5 m in, 0.3 m aside, then lifted: <= 2.5 m/s, 15 rad/s."""
    peaks = floor_press()
    assert peaks.speed <= 2.5 and peaks.spin <= 15.0


def test_a_corner_pressed_for_long_and_lifted_back_is_not_flung():
    """
    Pressed 0.5 m in and 0.3 m aside for 3 s, then lifted 0.5 m above where it started.

    The box tips onto its side and the anchor is held back the whole time; as the box leaves
    the floor it closes on the guide at the guide's own bounds: <= 2.5 m/s, 15 rad/s.
    """
    peaks = floor_press(press=3.0, back=True)
    assert peaks.speed <= 2.5 and peaks.spin <= 15.0


def test_a_flat_elastic_drop_stays_where_it_fell():
    """Restitution 1, threshold 0, dropped flat from 0.5 m for 30 s: lateral drift <= 1 mm."""
    world = floor_scenarios.world()
    drift, simulation = floor_scenarios.elastic_drift(world, height=0.5, seconds=30.0)
    assert drift <= 1e-3
    # And it still bounces: a perfect bounce, the discrete step's energy kept within bounds.
    assert simulation.state.position[2] > world.half_height or np.linalg.norm(
        simulation.state.linear_velocity) > 1.0
