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
The driver of the tick on the node's own clock: a timer, the due ticks, the budget.

``TickGrid`` says which ticks are due on the node's clock (system time, or ``/clock`` with
``use_sim_time``), ``TickBudget`` which of them one callback runs, and ``ticks_per_callback``
how many ticks one timer period holds at the publish rate; each runs ``Tick.run``.
``ticker.Ticker`` owns this driver and says when it runs; with ``publish_clock`` the node is the
clock and ``clock_ticks.ClockTicks`` drives instead.

The timer is an rclpy timer, or, for a node served by its own spin loop (``loop_ticks``, as the
executable serves it) on system time, a ``LoopTimer`` whose calls that loop makes
(``run_due``): the same schedule without the executor's timer thread. The loop makes a due
call before it takes the next message, on time or late: the tick comes first, whatever waits
in the executor's queue (a flood of targets), which is taken after it, between ticks. On
simulated time (use_sim_time) the timer is rclpy's, which /clock drives; a loop timer's call
that finds the clock switched to simulated time hands over to one.
"""

from typing import Callable, Optional

from rclpy.node import Node

from .tick import Tick
from .tick_record import TickRecord
from ..timing.loop_timer import LoopTimer
from ..timing.publish_ticks import ticks_per_callback
from ..timing.tick_budget import TickBudget
from ..timing.tick_grid import (CATCH_UP_CAUSE, clock_change_text, clock_jump_text, drop_text,
                                MAX_CLOCK_STEP_SECONDS, scheduled_origin, TickGrid)

# A /clock reading this far past the latest tick is a jump, not missed ticks (``TickGrid.due``).
MAX_CLOCK_STEP_NS = round(MAX_CLOCK_STEP_SECONDS * 1e9)


class NodeClockTicks:
    """
    Runs a tick on the grid of the node's clock, from a timer of the node.

    :param node: the node whose clock and timers are used.
    :param ticker: the owner of time: the rate, the pause, the substeps of a tick.
    :param record: the ticks' record: late and dropped ticks and clock restarts are counted.
    :param warn: ``warn(key, message())``, throttled per key.
    :param loop: on system time, the calls are the spin loop's (``run_due``), not a timer's.
    """

    def __init__(self, node: Node, ticker, record: TickRecord, *,
                 warn: Callable[[str, Callable[[], str]], None], loop: bool = False) -> None:
        """Create no timer until ``start``."""
        self._node = node
        self._loop = loop
        self._ticker = ticker
        self._record = record
        self._warn = warn
        self._budget = TickBudget()
        self._tick: Optional[Tick] = None
        self._timer = None
        self.grid: Optional[TickGrid] = None
        # The node's clock, read through its handle: ``Clock.now`` builds a ``Time`` per call,
        # five times the cost of the reading itself, on the path of every tick.
        self._clock = node.get_clock()
        self._clock_now = self._clock.handle.get_now
        # Which clock the grid runs on: simulated (True) or system time.
        self._grid_sim_time = self._clock.ros_time_is_active

    @property
    def timer(self):
        """Return the tick timer, or None while stopped."""
        return self._timer

    def start(self, tick: Tick, rate_hz: float, publish_rate_hz: float) -> None:
        """Run ``tick`` on a new grid at ``rate_hz``, from a timer of one batch of ticks."""
        self._tick = tick
        self.grid = TickGrid.for_rate(rate_hz)
        self.retime(rate_hz, publish_rate_hz)

    def retime(self, rate_hz: float, publish_rate_hz: float) -> None:
        """Go on with the same grid on a timer of the batch ``publish_rate_hz`` gives."""
        self._destroy_timer()
        batch = ticks_per_callback(rate_hz, publish_rate_hz)
        if self._loop and not self._clock.ros_time_is_active:
            self._timer = LoopTimer(round(batch / rate_hz * 1e9))
        else:
            self._timer = self._node.create_timer(batch / rate_hz, self._on_timer)

    def run_due(self) -> Optional[float]:
        """
        Make the loop timer's call if it is due; return the time (s) until the next one.

        The call runs at once, late or not: the loop asks before each message it takes, so a
        due tick never waits behind the messages queued meanwhile. Were a late call posted to
        the back of the executor's queue (where an rclpy timer's call goes), a flood that the
        node takes more slowly than it comes would keep every later call late behind it, past
        the catch-up bound, and the ticks would be dropped. The services do not starve: the
        ticks of one call take at most ``TickBudget``'s share of the time, and the queue's
        messages and requests run between calls. The periods a late call overran are skipped.
        None when no loop timer runs (stopped, or an rclpy timer makes the calls).
        """
        timer = self._timer
        if type(timer) is not LoopTimer:
            return None
        if timer.take():
            self._on_timer()
            if self._clock.ros_time_is_active:
                # use_sim_time came on: /clock drives the calls from now on, through rclpy.
                self.retime(self._ticker.rate_hz, self._ticker.publish_rate_hz)
                return None
            if timer is not self._timer:
                return None  # retimed or stopped by the call
        return timer.time_until_next_call() * 1e-9

    def now_ns(self) -> int:
        """Return the node's clock's reading (ns)."""
        return self._clock_now().nanoseconds

    def stop(self) -> None:
        """Destroy the timer: no tick runs until ``start``."""
        self._destroy_timer()

    def resume(self) -> None:
        """Run again from a new grid at the next timer call: the paused time is not caught up."""
        if self.grid is not None:
            self.grid = TickGrid.for_rate(self._ticker.rate_hz)

    def waiting_for_clock(self) -> Optional[str]:
        """
        Return ``'/clock on <topic>'`` while use_sim_time is on and no clock message came.

        The node's clock reads zero until then and no timer on it fires: no tick, no pose.
        """
        clock = self._node.get_clock()
        if clock.ros_time_is_active and clock.now().nanoseconds == 0:
            return f'/clock on {self._node.resolve_topic_name("/clock")}'
        return None

    def _destroy_timer(self) -> None:
        if self._timer is not None and type(self._timer) is not LoopTimer:
            self._node.destroy_timer(self._timer)
        self._timer = None

    def _on_timer(self) -> None:
        if self._ticker.paused:
            return
        node, record, grid = self._node, self._record, self.grid
        clock = self._clock
        now = self._clock_now().nanoseconds
        if clock.ros_time_is_active != self._grid_sim_time:
            # use_sim_time flipped: a new clock, not lost time. Restart the grid on it.
            self._grid_sim_time = clock.ros_time_is_active
            grid.restart(now)
            record.clock_restarts += 1
            node.get_logger().info(clock_change_text(self._grid_sim_time, now))
        elif not grid.started:
            grid.restart(scheduled_origin(now, self._timer.time_until_next_call(),
                                          self._timer.timer_period_ns))
        due = grid.due(now, MAX_CLOCK_STEP_NS if self._grid_sim_time else None)
        if due.restarted:
            record.clock_restarts += 1
            node.get_logger().warning(clock_jump_text(now, due.jump_ns))
        first, count = due.first, due.count
        if due.dropped:
            self._drop(due.dropped, CATCH_UP_CAUSE)
        if count:
            budget = self._budget
            ran = budget.run(self._tick.run, grid.stamp, first, count)
            if ran < count:
                self._drop(count - ran, budget.cause(self._ticker.substeps))
            if ran > 1:
                record.late_ticks += ran - 1

    def _drop(self, count: int, cause: str) -> None:
        record = self._record
        record.drop(count, cause)
        self._warn('rate', lambda: drop_text(self._ticker.rate_hz, count, record.dropped_ticks,
                                             cause))
