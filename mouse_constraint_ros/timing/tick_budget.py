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
Which of the due ticks one timer callback runs, within a wall-time budget, and when to rest.

The executor is single-threaded: a callback that runs ticks for long makes every service and
parameter call wait behind the physics. ``TickBudget`` bounds that wait whatever one tick
costs (substeps): a callback runs ticks for at most ``seconds`` of wall time. It keeps a
running estimate of one tick's wall time (an exponential average, the newest callback weighing
``weight``) and runs only as many of the due ticks as fit the budget at that cost, the newest
ones, so that the newest state is the one published; the older ones are dropped, as are the
ones left when the budget runs out early. A callback that drops ticks is followed by as long a
rest, in which every due tick is dropped at once: the physics then has at most half of the
wall time, and the timer events that queued up meanwhile are cleared in microseconds instead
of each running ticks in turn.

Used on the node's clock (``TickGrid``); with ``publish_clock`` nothing is dropped and
``sim_clock.ClockPacer`` paces instead. Plain Python: the wall clock is a parameter.
"""

import math
import time
from typing import Callable

# Run ticks for at most this much wall time in one timer callback (s).
CALLBACK_BUDGET_SECONDS = 0.05
# Weight of the newest callback in the running estimate of one tick's wall time.
TICK_COST_WEIGHT = 0.25


class TickBudget:
    """
    The wall budget of one timer callback and the tick-cost estimate that divides it.

    :param seconds: the longest a callback runs ticks for (s of ``clock``).
    :param weight: the weight of the newest callback in the cost estimate, in (0, 1].
    :param clock: returns wall time in seconds (``time.perf_counter``).
    """

    def __init__(self, *, seconds: float = CALLBACK_BUDGET_SECONDS,
                 weight: float = TICK_COST_WEIGHT,
                 clock: Callable[[], float] = time.perf_counter) -> None:
        """Start with no estimate (the first callback runs all it can) and no rest."""
        self.seconds = seconds
        self.weight = weight
        self._clock = clock
        # Running estimate of one tick's wall time (s), 0 before the first tick.
        self.tick_seconds = 0.0
        # Time of ``clock`` until which due ticks are dropped, after a callback that dropped.
        self.rest_until = -math.inf

    def run(self, tick: Callable[[int, int], object], stamp: Callable[[int], int], first: int,
            count: int) -> int:
        """
        Run what fits of ticks ``first`` .. ``first + count - 1``: ``tick(stamp(n), n)``.

        The ``count`` minus the returned number are dropped (oldest first); then the budget
        rests as long as this call ran.

        :param tick: steps and publishes tick ``n`` at its stamp.
        :param stamp: the stamp of tick ``n`` (ns).
        :param first: the oldest tick due.
        :param count: how many are due (> 0).
        :returns: how many ran: 0 while resting, else at least one.
        """
        clock = self._clock
        started = clock()
        if started < self.rest_until:
            return 0
        budget = self.seconds
        estimate = self.tick_seconds
        last = first + count
        if estimate > 0.0:
            fits = int(budget / estimate) or 1
            if count > fits:
                first = last - fits
        ran = 0
        for n in range(first, last):
            tick(stamp(n), n)
            ran += 1
            if clock() - started > budget:
                break
        finished = clock()
        cost = (finished - started) / ran
        self.tick_seconds = cost if estimate == 0.0 else estimate + self.weight * (
            cost - estimate)
        if ran < count:
            self.rest_until = finished + (finished - started)
        return ran

    def cause(self, substeps: int) -> str:
        """Return why ticks were dropped for the budget, for the warning and /diagnostics."""
        return (f'one tick takes {self.tick_seconds * 1e3:.3g} ms of wall time '
                f'({substeps} substeps) and a timer callback stops after '
                f'{self.seconds * 1e3:g} ms so that services and parameters answer')
