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

"""Which target stamps time the drag (inputs.target_stamps) and how they map to the core's time."""

import pytest

from mouse_constraint_ros.inputs.target_stamps import (core_time, CoreClock, REASONS,
                                                       stamp_refusal, TargetStamps,
                                                       TargetTiming)
from mouse_constraint_ros.physics.target_stream import STREAM_GAP

NOW = 1_796_000_000_123_456_789  # a system clock reading (ns)
TICK = 1_000_000  # 1 kHz
WINDOW = round(STREAM_GAP * 1e9)


def refusal(stamp: int, now: int = NOW, previous=None):
    return stamp_refusal(stamp, now_ns=now, tick_ns=TICK, window_ns=WINDOW, previous_ns=previous)


def test_a_stamp_a_little_before_now_is_usable():
    """An event 20 ms ago (a browser's delay) times its target."""
    assert refusal(NOW - 20_000_000) is None


def test_a_zero_stamp_is_arrival_time():
    """Zero: the sender did not stamp."""
    assert refusal(0) == 'zero'
    assert refusal(0, now=0) == 'zero'


@pytest.mark.parametrize('ahead, reason', [(0, None), (TICK, None), (TICK + 1, 'future'),
                                           (10**9, 'future')])
def test_a_stamp_may_be_ahead_of_the_node_by_one_tick_at_most(ahead, reason):
    """The edge is inclusive: one tick ahead is the latest tick's own time on a late clock."""
    assert refusal(NOW + ahead) == reason


@pytest.mark.parametrize('age, reason', [(WINDOW, None), (WINDOW + 1, 'old'), (10**10, 'old')])
def test_a_stamp_older_than_the_stream_window_is_arrival_time(age, reason):
    """Older than the stream's gap, a point could not continue a stream anyway."""
    assert refusal(NOW - age) == reason


def test_a_stamp_of_another_clock_source_is_arrival_time():
    """Wall time on a node on simulated time is far ahead; simulated time on wall time, old."""
    simulated_now = 12_500_000_000  # 12.5 s into a /clock or publish_clock run
    assert refusal(NOW, now=simulated_now) == 'future'
    assert refusal(simulated_now - 5_000_000) == 'old'


def test_a_stamp_not_after_the_last_one_used_is_arrival_time():
    """Equal or earlier than the previous usable stamp: out of order, not a new event."""
    previous = NOW - 10_000_000
    assert refusal(previous, previous=previous) == 'order'
    assert refusal(previous - 1, previous=previous) == 'order'
    assert refusal(previous + 1, previous=previous) is None


def test_a_previous_stamp_from_a_clock_that_went_back_does_not_block_the_new_clock():
    """A last stamp far ahead of now belongs to a clock that is gone (a replay restarted)."""
    assert refusal(NOW - 1_000, previous=NOW + 10 * TICK) is None


def test_the_checks_run_in_the_order_of_reasons():
    """Every key is one of REASONS; a zero stamp is 'zero' whatever else holds."""
    assert REASONS == ('zero', 'future', 'old', 'order')
    assert refusal(0, previous=NOW) == 'zero'


def test_target_stamps_remembers_only_the_stamps_it_used():
    """A refused stamp does not become the previous one; a used one does."""
    stamps = TargetStamps(STREAM_GAP)
    first = NOW - 40_000_000
    assert stamps.refusal(first, now_ns=NOW, tick_s=1e-3) is None
    assert stamps.refusal(first, now_ns=NOW, tick_s=1e-3) == 'order'
    assert stamps.refusal(NOW + 10**9, now_ns=NOW, tick_s=1e-3) == 'future'
    assert stamps.previous_ns == first
    assert stamps.refusal(first + 1, now_ns=NOW, tick_s=1e-3) is None
    assert stamps.previous_ns == first + 1


def test_core_time_is_the_latest_ticks_core_time_plus_the_distance_from_its_stamp():
    """A stamp 3.5 ms before the latest tick's stamp is 3.5 ms before its core time."""
    assert core_time(NOW - 3_500_000, tick_stamp_ns=NOW, tick_core_time=12.0) == \
        pytest.approx(12.0 - 3.5e-3, abs=1e-12)
    assert core_time(NOW, tick_stamp_ns=NOW, tick_core_time=12.0) == 12.0


def test_the_core_clock_says_how_far_the_offset_moved():
    """Ticks on time keep the offset; 50 ms of dropped ticks move it, once, by 50 ms."""
    clock = CoreClock()
    tick_ns = 1_000_000
    for n in range(1, 5):
        tick_stamp = NOW + n * tick_ns
        time, shift = clock.time_of(tick_stamp - 2 * tick_ns, tick_stamp_ns=tick_stamp,
                                    tick_core_time=n * 1e-3, tick_s=1e-3)
        assert shift == 0.0
        assert time == pytest.approx((n - 2) * 1e-3, abs=1e-12)
    # 50 ticks dropped: the clock ran 51 ms, the core 1 ms; the times mapped so far are 50 ms
    # earlier on the new offset.
    time, shift = clock.time_of(NOW + 54 * tick_ns, tick_stamp_ns=NOW + 55 * tick_ns,
                                tick_core_time=5e-3, tick_s=1e-3)
    assert shift == pytest.approx(-0.05, abs=1e-12)
    assert time == pytest.approx(4e-3, abs=1e-12)
    assert clock.time_of(NOW + 55 * tick_ns, tick_stamp_ns=NOW + 56 * tick_ns,
                         tick_core_time=6e-3, tick_s=1e-3)[1] == 0.0


def test_after_dropped_ticks_the_stream_goes_on_on_the_new_offset():
    """
    A 1 m/s line with 30 ms of ticks dropped: the stream keeps its velocity, shifted.

    Timed through ``TargetTiming``, as the node times it: the stream's times move by the
    offset's change, so the velocity after the drop is still the line's, where a new stream
    would have started at rest.
    """
    from mouse_constraint_ros.physics import BodyState, MouseSimulation, RigidBody, Settings
    from mouse_constraint_ros.physics.target_motion import TargetMotion
    simulation = MouseSimulation(Settings(
        RigidBody.solid_box(2.0, (0.4, 0.2, 0.1)), gravity=(0.0, 0.0, 0.0),
        target_motion=TargetMotion(feed_forward=True)), BodyState())
    timing = TargetTiming(STREAM_GAP)
    tick_s, tick_ns = 1e-3, 1_000_000
    tick_stamp = NOW
    for n in range(1, 200):
        now = NOW + n * tick_ns
        dropped = 100 <= n < 130
        if n % 10 == 0:
            timing.take(simulation, (1e-9 * (now - NOW), 0.0, 0.0), stamp_ns=now, now_ns=now,
                        tick_stamp_ns=tick_stamp, tick_s=tick_s, ticked=True)
            if n > 20:
                assert simulation.target_velocity == pytest.approx((1.0, 0.0, 0.0), abs=1e-9)
        if not dropped:
            simulation.step(tick_s)
            tick_stamp = now
