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

"""The fixed-rate tick grid, without ROS: exact stamps, catch-up, dropping, restarts."""

from fractions import Fraction
import math

import pytest

from mouse_constraint_ros.timing.tick_grid import (CATCH_UP_CAUSE, clock_change_text,
                                                   clock_jump_text, drop_text,
                                                   MAX_CATCH_UP_SECONDS, scheduled_origin,
                                                   TickGrid)


def test_stamps_lie_on_the_exact_grid_for_any_rate():
    """Tick n is at t0 + floor(n * 1e9 / rate) ns, with no drift after millions of ticks."""
    for rate in (300.0, 1000.0, 240.0, 7.0, 2999.5):
        grid = TickGrid(rate, 10)
        grid.restart(123_456_789)
        period = Fraction(10**9) / Fraction(rate)
        for n in (0, 1, 2, 3, 1000, 10**7 + 3):
            assert grid.stamp(n) == 123_456_789 + int(n * period)


def test_ticks_due_are_run_once_each_with_bounded_catch_up():
    """Each tick is due once; a late call runs the missed ones, up to the bound."""
    grid = TickGrid(1000.0, 5)
    assert grid.due(10_000_000).count == 1  # tick 0 at the first reading
    assert grid.due(10_500_000).count == 0  # not yet
    due = grid.due(11_000_000)
    assert (due.first, due.count, due.dropped) == (1, 1, 0)
    due = grid.due(14_000_000)
    assert (due.first, due.count, due.dropped) == (2, 3, 0)
    due = grid.due(22_000_000)
    # Ticks 5 to 12 are due; the oldest 3 are dropped.
    assert (due.first, due.count, due.dropped) == (8, 5, 3)
    assert grid.stamp(due.first + due.count - 1) == 22_000_000


def test_a_clock_going_backwards_restarts_the_grid():
    """A reading before the last tick puts tick 0 there, with no catch-up burst."""
    grid = TickGrid(100.0, 100)
    grid.due(5_000_000_000)
    grid.due(5_500_000_000)
    due = grid.due(1_000_000_000)
    assert due.restarted and (due.first, due.count, due.dropped) == (0, 1, 0)
    assert grid.origin == 1_000_000_000
    assert not grid.due(1_010_000_000).restarted


def test_a_clock_jumping_forwards_past_max_jump_restarts_the_grid_without_drops():
    """
    Beyond ``max_jump`` past the latest tick: tick 0 at the reading, nothing dropped.

    Within it the missed ticks are missed: caught up on to the bound, the rest dropped.
    """
    grid = TickGrid(100.0, 10)
    grid.due(5_000_000_000)
    grid.due(5_010_000_000)
    due = grid.due(65_010_000_001, max_jump=1_000_000_000)
    assert due.restarted and (due.first, due.count, due.dropped) == (0, 1, 0)
    assert due.jump_ns == 60_000_000_001 and grid.origin == 65_010_000_001
    due = grid.due(66_010_000_001, max_jump=1_000_000_000)  # 1 s: within it
    assert not due.restarted and (due.first, due.count, due.dropped) == (91, 10, 90)
    assert grid.due(80_000_000_000).count == 10  # no max_jump: never a jump forwards


@pytest.mark.parametrize('rate', [1.0, 7.0, 1000.0, 2999.5])
def test_the_nodes_grid_catches_up_on_its_bound_of_time(rate):
    grid = TickGrid.for_rate(rate)
    assert grid.rate_hz == rate
    assert grid.max_catch_up == max(1, math.ceil(MAX_CATCH_UP_SECONDS * rate))
    assert str(MAX_CATCH_UP_SECONDS) in CATCH_UP_CAUSE


def test_the_first_call_puts_t0_where_the_timer_scheduled_it():
    """A first call that ran late by 0.3 periods: t0 goes back by those; later calls on time."""
    period = 1_000_000
    late = 300_000
    now = 50_000_000
    origin = scheduled_origin(now, period - late, period)
    assert origin == now - late
    grid = TickGrid(1000.0, 5)
    grid.restart(origin)
    assert grid.due(now).count == 1
    # The next call, on time but with less jitter than the first: its own tick is due.
    assert grid.due(origin + period + late // 2).count == 1


@pytest.mark.parametrize('until_next', [None, -1, 1_000_001])
def test_without_a_plain_schedule_t0_is_the_reading(until_next):
    assert scheduled_origin(7, until_next, 1_000_000) == 7


def test_the_clock_and_drop_texts_say_what_happened_and_when():
    assert clock_change_text(True, 1_500_000_000).startswith(
        'clock changed to simulated time: restarting the tick grid at 1.500000000 s')
    assert clock_change_text(False, 0).startswith('clock changed to system time')
    assert clock_jump_text(2_000_000_001) == (
        'clock jumped backwards: restarting the tick grid at 2.000000001 s without catching up')
    assert clock_jump_text(2_000_000_001, 1_500_000_000) == (
        'clock jumped forwards by 1.500000000 s: restarting the tick grid at 2.000000001 s; the '
        'time skipped is no dropped tick')
    assert drop_text(1000.0, 3, 40, 'why') == (
        'cannot keep 1000 Hz: dropped 3 ticks (40 in all): why; simulated time falls behind')


@pytest.mark.parametrize('rate', [1000.0, 300.0, 7.0, 1234.5])
def test_the_tick_at_a_reading_and_after_a_stamp_are_those_of_the_grid(rate):
    grid = TickGrid.for_rate(rate)
    grid.restart(123_456_789)
    for tick in range(-3, 2000):
        stamp = grid.stamp(tick)
        assert grid.tick_at(stamp) == tick and grid.tick_at(stamp - 1) == tick - 1
        assert grid.tick_after(stamp) == tick + 1 and grid.tick_after(stamp - 1) == tick
