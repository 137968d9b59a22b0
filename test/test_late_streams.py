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

from test_support import floor_scenarios, late_streams


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
    fast = late_streams.run(events, 0.6)
    drained = late_streams.run(events, 0.6, drained=True)
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


def test_a_late_circle_is_followed_smoothly_behind_its_received_path():
    """
    100 ms late at 60 Hz: <= 3 mm RMS from the path at the delay that fits, wobble <= 3 %.

    Followed at its least latency and its lag, a quarter of that latency at most: 100 to 125 ms
    behind.
    """
    row = late_streams.circle_row(60.0, 0.1, behind=None)
    assert row['error_mm'] <= 3.0 and row['wobble_pct'] <= 3.0
    assert 100.0 <= row['behind_ms'] <= 125.0


def test_a_corner_pressed_into_the_floor_and_lifted_is_not_flung():
    """A resting box's corner pushed 0.5 m in, 0.3 m aside, then lifted: <= 2.5 m/s, 15 rad/s."""
    peaks = late_streams.floor_press()
    assert peaks.speed <= 2.5 and peaks.spin <= 15.0


def test_a_corner_pressed_for_long_and_lifted_back_is_not_flung():
    """
    Pressed 0.5 m in and 0.3 m aside for 3 s, then lifted 0.5 m above where it started.

    The box tips onto its side and the anchor is held back the whole time; as the box leaves
    the floor it closes on the guide at the guide's own bounds: <= 2.5 m/s, 15 rad/s.
    """
    peaks = late_streams.floor_press(press=3.0, back=True)
    assert peaks.speed <= 2.5 and peaks.spin <= 15.0


def test_a_flat_elastic_drop_stays_where_it_fell():
    """Restitution 1, threshold 0, dropped flat from 0.5 m for 30 s: lateral drift <= 1 mm."""
    world = floor_scenarios.world()
    drift, simulation = floor_scenarios.elastic_drift(world, height=0.5, seconds=30.0)
    assert drift <= 1e-3
    # And it still bounces: a perfect bounce, the discrete step's energy kept within bounds.
    assert simulation.state.position[2] > world.half_height or np.linalg.norm(
        simulation.state.linear_velocity) > 1.0
