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
The node's tick loop on its own clock: the timer, the due ticks, one tick's step and publish.

``TickGrid`` says which ticks are due on the node's clock, ``TickBudget`` which of them one
callback runs, ``PublishTicks`` which of them publish; ``StatePublishers`` sends the state. With
``publish_clock`` the simulator controls pace the ticks instead and call the same ``_tick``.
"""

from typing import Optional

from ..inputs.input_timeouts import wrench_removal_text
from ..inputs.wrench_gate import NO_WRENCH
from ..timing.publish_ticks import PublishTicks, ticks_per_callback
from ..timing.tick_grid import (CATCH_UP_CAUSE, clock_change_text, clock_jump_text, drop_text,
                                scheduled_origin, TickGrid)
from ..wire.messages import set_stamp


class TickLoop:
    """The tick timer and the tick of ``MouseConstraintNode``."""

    def _start_timer(self) -> None:
        if self._timer is not None:
            self.destroy_timer(self._timer)
        rate = self._config.rate_hz
        self._grid = TickGrid.for_rate(rate)
        self._publish_ticks = PublishTicks(rate, self._config.publish_rate_hz)
        self._dt = 1.0 / rate
        if self._config.publish_clock:
            self._timer = self._start_clock_timer()
        else:
            batch = ticks_per_callback(rate, self._config.publish_rate_hz)
            self._timer = self.create_timer(batch * self._dt, self._on_timer)

    def _on_timer(self) -> None:
        if self._paused:
            return
        clock = self.get_clock()
        now = clock.now().nanoseconds
        if clock.ros_time_is_active != self._grid_sim_time:
            # use_sim_time flipped: a new clock, not lost time. Restart the grid on it.
            self._grid_sim_time = clock.ros_time_is_active
            self._grid.restart(now)
            self.clock_restarts += 1
            self.get_logger().info(clock_change_text(self._grid_sim_time, now))
        elif not self._grid.started:
            self._grid.restart(scheduled_origin(now, self._timer.time_until_next_call(),
                                                self._timer.timer_period_ns))
        due = self._grid.due(now)
        if due.restarted:
            self.clock_restarts += 1
            self.get_logger().warning(clock_jump_text(now))
        first, count = due.first, due.count
        if due.dropped:
            self._drop(due.dropped, CATCH_UP_CAUSE)
        self._release_if_timed_out(now)
        if count:
            budget = self._budget
            ran = budget.run(self._tick, self._grid.stamp, first, count)
            if ran < count:
                self._drop(count - ran, budget.cause(self._config.settings.substeps))
            if ran > 1:
                self.late_ticks += ran - 1
            self.ticks_run += ran

    def _drop(self, count: int, cause: str) -> None:
        self.dropped_ticks += count
        self.drop_cause = cause
        self._warn('rate', lambda: drop_text(self._config.rate_hz, count, self.dropped_ticks,
                                             cause))

    def _tick(self, stamp: int, tick: Optional[int] = None) -> None:
        """
        Step once; publish /clock (if published) and, on a publishing tick, the state.

        :param stamp: the tick's time (ns): the stamp of /clock and of the state.
        :param tick: the tick's number on its grid, for ``PublishTicks``; None publishes (a
            single step asked for by ``~/step``).
        """
        held = self._held_wrench
        if held.advance(stamp):
            self._simulation.wrench = held.wrench
        if held.applied is not None and held.expired(stamp, self._config.wrench_timeout):
            self._simulation.wrench = NO_WRENCH
            self.get_logger().info(wrench_removal_text(self._config.wrench_timeout))
        state = self._simulation.step(self._dt)
        if self._clock_publisher is not None:
            set_stamp(self._clock_message.clock, stamp)
            self._clock_publisher.publish(self._clock_message)
        self._stamp_ns = stamp
        publish_ticks = self._publish_ticks
        if tick is None or publish_ticks.every_tick or publish_ticks.due(tick):
            self._state_publishers.publish(stamp, state)

    def waiting_for_clock(self) -> Optional[str]:
        """
        Return ``'/clock on <topic>'`` while use_sim_time is on and no clock message came.

        The node's clock reads zero until then and no timer on it fires: no tick, no pose.
        """
        clock = self.get_clock()
        if self._clock_publisher is None and clock.ros_time_is_active and \
                clock.now().nanoseconds == 0:
            return f'/clock on {self.resolve_topic_name("/clock")}'
        return None

    def _watch_clock(self) -> None:
        waiting = self.waiting_for_clock()
        if waiting is not None:
            self._warn('clock', lambda: (
                f'waiting for {waiting}: use_sim_time is true and no clock message has come; '
                'no tick runs until one does'))
