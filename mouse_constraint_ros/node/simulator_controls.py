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
The node's simulator controls: the node as the clock, pause, step, reset, release, the wrench.

The pacing is ``SimulatedClock``'s and ``ClockPacer``'s, the wrench policy ``WrenchGate``'s and
``HeldWrench``'s, the replies ``service_replies``'; here is the wiring.
"""

import time

from geometry_msgs.msg import WrenchStamped
from rosgraph_msgs.msg import Clock as ClockMessage
from std_srvs.srv import SetBool, Trigger

from .service_replies import (pause_reply, release_reply, reset_refusal, reset_reply, step_refusal,
                              step_reply)
from ..inputs.wrench_gate import effective_time, HeldWrench, NO_WRENCH, WrenchGate
from ..monitoring.diagnostics import TickWindow
from ..timing.sim_clock import ClockPacer, PacingMeter, SimulatedClock
from ..timing.tick_grid import MAX_CATCH_UP_SECONDS, TickGrid
from ..wire.interface import (CLOCK_QOS, CLOCK_TOPIC, PAUSE_SERVICE, STEP_SERVICE, WRENCH_QOS,
                              WRENCH_TOPIC)
from ..wire.messages import stamp_nanoseconds


class SimulatorControls:
    """The simulator controls of ``MouseConstraintNode``."""

    def _simulator_controls_init(self) -> None:
        """Create the state the tick timers read: pause, wrench, simulated clock."""
        self._paused = False
        self._held_wrench = HeldWrench()
        # Created once: turning publish_clock off and on goes on from the simulated time reached.
        self._sim_clock = SimulatedClock(self._config.rate_hz, self._config.real_time_factor,
                                         max_lag=MAX_CATCH_UP_SECONDS)
        self._clock_message = ClockMessage()
        self._clock_publisher = None
        if self._config.publish_clock:
            self._clock_publisher = self.create_publisher(ClockMessage, CLOCK_TOPIC, CLOCK_QOS)
        # What the pacing achieved between two diagnostics calls.
        self._pacing = PacingMeter()

    def _simulator_controls_setup(self) -> None:
        self.create_subscription(WrenchStamped, WRENCH_TOPIC, self._on_wrench, WRENCH_QOS)
        self.create_service(SetBool, PAUSE_SERVICE, self._on_pause)
        self.create_service(Trigger, STEP_SERVICE, self._on_step)

    def _now_ns(self) -> int:
        """Return the node's time: the simulated clock with publish_clock, else its clock."""
        if self._clock_publisher is not None:
            return self._sim_clock.now_ns
        return self.get_clock().now().nanoseconds

    def _start_clock_timer(self):
        """Return the tick timer of publish_clock, on the steady clock (``ClockPacer``)."""
        self._pacer = ClockPacer(self._config.rate_hz, self._config.real_time_factor)
        return self.create_timer(self._pacer.period, self._on_clock_timer,
                                 clock=self._steady_clock)

    def _on_clock_timer(self) -> None:
        pacer = self._pacer
        started = pacer.start()
        if started is None:
            # Clears the events queued while one tick outlasted the period (many substeps).
            return
        clock = self._sim_clock
        due = clock.due(time.monotonic_ns())
        if due == 0:
            return
        self._release_if_timed_out(clock.now_ns)
        self.ticks_run += pacer.run(clock, self._tick, due, started)

    def _switch_clock(self, previous) -> None:
        """Start the tick timer again for a new rate or clock source, re-basing input ages."""
        config = self._config
        if config.publish_clock and self._clock_publisher is None:
            self._clock_publisher = self.create_publisher(ClockMessage, CLOCK_TOPIC, CLOCK_QOS)
        elif not config.publish_clock and self._clock_publisher is not None:
            self.destroy_publisher(self._clock_publisher)
            self._clock_publisher = None
        self._sim_clock.set_rate(config.rate_hz)
        self._sim_clock.set_real_time_factor(config.real_time_factor)
        self._start_timer()
        if config.publish_clock != previous.publish_clock:
            # Another time base: the ages of target and wrench start again in it.
            now = self._now_ns()
            if self._user_target:
                self._last_target_ns = now
            applied = self._held_wrench.applied
            if applied is not None:
                self._held_wrench.applied = applied._replace(since_ns=now)

    def _retime_clock_timer(self) -> None:
        if self._clock_publisher is not None:
            self.destroy_timer(self._timer)
            self._timer = self._start_clock_timer()

    def _on_pause(self, request: SetBool.Request, response: SetBool.Response):
        """
        Pause (true) or resume (false) the physics.

        Resuming catches nothing up: the simulated clock paces on from where it stood, the
        node-clock grid starts again at the next timer call.
        """
        pause = bool(request.data)
        response.success = True
        response.message = pause_reply(pause, self._paused, self._now_ns())
        if pause == self._paused:
            return response
        self._paused = pause
        if pause:
            self._sim_clock.pause()
            return response
        self._sim_clock.resume()
        self._grid = TickGrid.for_rate(self._config.rate_hz)
        self._tick_window = TickWindow()
        return response

    def _on_step(self, _request: Trigger.Request, response: Trigger.Response):
        """While paused: run exactly one tick and publish it; refused while running."""
        refusal = step_refusal(self._paused, self.waiting_for_clock())
        if refusal is not None:
            response.success = False
            response.message = refusal
            return response
        if self._clock_publisher is not None:
            stamp = self._sim_clock.advance()
        else:
            stamp = self.get_clock().now().nanoseconds
        self._release_if_timed_out(stamp)
        self._tick(stamp)
        self.ticks_run += 1
        response.success = True
        response.message = step_reply(self._dt, stamp)
        return response

    def _on_wrench(self, message: WrenchStamped) -> None:
        f, t = message.wrench.force, message.wrench.torque
        force, torque = (f.x, f.y, f.z), (t.x, t.y, t.z)
        config = self._config
        refusal = WrenchGate(config.frame_id, config.max_wrench_force,
                             config.max_wrench_torque).refusal(
                                 message.header.frame_id, force, torque)
        if refusal is not None:
            self._warn(refusal.key, lambda: f'ignoring wrench {refusal.reason}')
            return
        # In effect from the tick stamped at its stamp (its end, for the zero wrench of a push).
        self._held_wrench.schedule(force, torque, effective_time(
            stamp_nanoseconds(message.header.stamp), self._now_ns()))

    def _on_reset(self, _request: Trigger.Request, response: Trigger.Response):
        configured = self._configured_anchor
        if self._config.settings.constraint.anchor != configured:
            reason = self._set_anchor(configured)
            if reason is not None:
                response.success = False
                response.message = reset_refusal(configured, reason)
                return response
        self._simulation.reset()
        self._hold_initial_anchor()
        self._held_wrench.clear()
        self._simulation.wrench = NO_WRENCH
        response.success = True
        response.message = reset_reply(self._config.hold_initial_anchor)
        return response

    def _on_release(self, _request: Trigger.Request, response: Trigger.Response):
        had_target = self._simulation.target is not None
        self._simulation.target = None
        self._user_target = False
        response.success = True
        response.message = release_reply(had_target)
        return response
