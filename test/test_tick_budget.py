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

"""The wall budget of a timer callback and the clock pacer's, on a fake wall clock."""

import math

import pytest

from mouse_constraint_ros.timing.sim_clock import (CLOCK_BUDGET_SHARE, ClockPacer,
                                                   MIN_CLOCK_PERIOD, SimulatedClock)
from mouse_constraint_ros.timing.tick_budget import TickBudget


class FakeWall:
    """A wall clock that only moves when a tick runs, by ``cost`` seconds."""

    def __init__(self, cost: float) -> None:
        self.now = 100.0
        self.cost = cost
        self.ran = []

    def __call__(self) -> float:
        return self.now

    def tick(self, stamp: int, n: int) -> None:
        self.ran.append((stamp, n))
        self.now += self.cost


def stamp(n: int) -> int:
    """Stamp of tick n on a 1 kHz grid from 0."""
    return n * 1_000_000


def ticks_within(budget: float, cost: float) -> int:
    """How many ticks of ``cost`` run until the time exceeds ``budget`` (not a multiple)."""
    return math.floor(budget / cost) + 1


def test_what_fits_runs_and_nothing_rests():
    wall = FakeWall(0.001)
    budget = TickBudget(seconds=0.05, clock=wall)
    assert budget.run(wall.tick, stamp, 10, 3) == 3
    assert wall.ran == [(stamp(n), n) for n in (10, 11, 12)]
    assert budget.tick_seconds == pytest.approx(wall.cost)
    assert budget.rest_until == -math.inf


def test_without_an_estimate_ticks_run_until_the_budget_is_spent_then_it_rests():
    wall = FakeWall(0.02)
    budget = TickBudget(seconds=0.05, clock=wall)
    started = wall.now
    ran = budget.run(wall.tick, stamp, 0, 10)
    assert ran == ticks_within(budget.seconds, wall.cost)
    spent = wall.now - started
    assert budget.rest_until == pytest.approx(wall.now + spent)
    # Resting: due ticks run not at all, until the rest is over.
    wall.now = budget.rest_until - 1e-6
    assert budget.run(wall.tick, stamp, 10, 5) == 0 and len(wall.ran) == ran
    wall.now = budget.rest_until
    assert budget.run(wall.tick, stamp, 10, 1) == 1


def test_with_an_estimate_only_the_newest_ticks_that_fit_run():
    wall = FakeWall(0.02)
    budget = TickBudget(seconds=0.05, clock=wall)
    budget.run(wall.tick, stamp, 0, 1)
    fits = int(budget.seconds / budget.tick_seconds)
    wall.ran.clear()
    assert budget.run(wall.tick, stamp, 1, 10) == fits
    assert [n for _, n in wall.ran] == list(range(11 - fits, 11))
    assert budget.rest_until > wall.now


def test_a_tick_over_the_whole_budget_still_runs_one():
    wall = FakeWall(1.0)
    budget = TickBudget(seconds=0.05, clock=wall)
    budget.run(wall.tick, stamp, 0, 1)
    wall.now = budget.rest_until
    assert budget.run(wall.tick, stamp, 1, 4) == 1 and wall.ran[-1][1] == 4


def test_the_cost_estimate_is_a_running_average_weighted_to_the_newest():
    wall = FakeWall(0.001)
    budget = TickBudget(seconds=0.05, weight=0.25, clock=wall)
    budget.run(wall.tick, stamp, 0, 1)
    first = budget.tick_seconds
    wall.cost = 0.003
    budget.run(wall.tick, stamp, 1, 1)
    assert budget.tick_seconds == pytest.approx(first + budget.weight * (wall.cost - first))


def test_the_cause_says_the_cost_the_substeps_and_the_budget():
    wall = FakeWall(0.004)
    budget = TickBudget(seconds=0.05, clock=wall)
    budget.run(wall.tick, stamp, 0, 1)
    cause = budget.cause(7)
    assert cause.startswith(f'one tick takes {wall.cost * 1e3:.3g} ms of wall time (7 substeps)')
    assert f'stops after {budget.seconds * 1e3:g} ms' in cause


@pytest.mark.parametrize('rate_hz, factor, period', [
    (1000.0, 0.0, MIN_CLOCK_PERIOD), (100.0, 1.0, 1.0 / 100.0), (100.0, 0.5, 1.0 / 50.0),
    (1000.0, 2.0, MIN_CLOCK_PERIOD),
])
def test_the_pacer_period_is_that_of_the_ticks_due_at_least_the_minimum(
        rate_hz, factor, period):
    pacer = ClockPacer(rate_hz, factor)
    assert pacer.period == pytest.approx(period)
    assert pacer.budget == pytest.approx(CLOCK_BUDGET_SHARE * period)


def test_the_pacer_runs_the_due_ticks_on_the_clock():
    wall = FakeWall(1e-5)
    pacer = ClockPacer(100.0, 1.0, clock=wall)
    clock = SimulatedClock(100.0, 1.0, max_lag=0.1)
    started = pacer.start()
    assert pacer.run(clock, wall.tick, 3, started) == 3
    assert wall.ran == [(clock.stamp(n), n) for n in (1, 2, 3)] and clock.ticks == 3
    assert pacer.start() is not None


def test_as_fast_as_it_runs_the_pacer_stops_at_its_budget_without_rest():
    wall = FakeWall(1.5e-4)
    pacer = ClockPacer(1000.0, 0.0, clock=wall)
    clock = SimulatedClock(1000.0, 0.0, max_lag=0.1)
    ran = pacer.run(clock, wall.tick, None, pacer.start())
    assert ran == ticks_within(pacer.budget, wall.cost) == clock.ticks
    assert pacer.start() is not None


def test_a_call_that_outlasts_its_period_rests_twice_as_long():
    wall = FakeWall(0.005)
    pacer = ClockPacer(1000.0, 1.0, clock=wall)
    clock = SimulatedClock(1000.0, 1.0, max_lag=0.1)
    started = pacer.start()
    assert pacer.run(clock, wall.tick, 4, started) == 1
    assert pacer.rest_until == pytest.approx(started + 2.0 * wall.cost)
    assert pacer.start() is None
    wall.now = pacer.rest_until
    assert pacer.start() == wall.now
