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
A periodic call on the steady clock that the spin loop makes itself, not the executor.

An rclpy timer under the EventsExecutor costs a thread of its own: it waits for the timer,
then posts the call to the executor's queue, which wakes the spinning thread. At 1 kHz that
thread alone takes a good share of a bare timer node's CPU (``python -m bench.node_cost`` reads
it per thread, docs/benchmarks.md). ``LoopTimer`` keeps the timer's schedule instead, and the
spin loop that serves the node (``spin.spin_until`` with a ``pace``) waits in ``spin_once`` only
until the next call is due, then makes the call in the same thread: one thread, one wake per
call. A call the loop takes late (it was busy, not
waiting) is made at once too, before the next message the loop takes
(``tick_loop.NodeClockTicks``): the tick comes first.

Its schedule is an rclpy timer's: calls at ``start + k * period``; a call that runs late is
still made once, and the periods it overran are skipped, not caught up (the caller's grid
catches up on its own terms). ``timer_period_ns`` and ``time_until_next_call`` read as an rclpy
timer's do.
"""

import time
from typing import Callable, Optional


class LoopTimer:
    """
    The schedule of a periodic call made by the spin loop.

    :param period_ns: the period (ns), > 0.
    :param now_ns: the steady clock (``time.monotonic_ns`` by default).
    """

    def __init__(self, period_ns: int, *,
                 now_ns: Callable[[], int] = time.monotonic_ns) -> None:
        """Schedule the first call one period from now."""
        if period_ns <= 0:
            raise ValueError(f'period_ns must be > 0, not {period_ns}')
        self.timer_period_ns = period_ns
        self._now_ns = now_ns
        self._next = now_ns() + period_ns
        self.late_ns = 0

    def time_until_next_call(self) -> Optional[int]:
        """Return the time (ns) until the next call is due; <= 0 when it is due."""
        return self._next - self._now_ns()

    def take(self) -> bool:
        """
        Return whether a call is due now; if so, schedule the next one.

        The next call is the first of the schedule after now: the periods overrun are skipped.
        ``late_ns`` is then how long after its time (ns) the call was taken.
        """
        now = self._now_ns()
        late = now - self._next
        if late < 0:
            return False
        period = self.timer_period_ns
        self._next += period * (late // period + 1)
        self.late_ns = late
        return True
