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
The node's simulator services: ``~/pause``, ``~/step``, ``~/reset`` and ``~/release``.

Pausing holds both drivers of the tick: the node's timer runs no tick while paused, the
simulated clock stands still; resuming catches nothing up (a new grid on the node's clock, the
simulated clock paced from where it stood). ``~/step`` runs one tick while paused. ``~/reset``
restores the configured anchor (through the node's own ``anchor`` parameter), the initial state
and the initial hold, and drops the wrench; while paused it publishes the state it leaves at
once. The replies are ``service_replies``'.
"""

from typing import Callable, Optional

from std_srvs.srv import SetBool, Trigger

from .clock_ticks import ClockTicks
from .service_replies import (pause_reply, release_reply, reset_refusal, reset_reply, step_refusal,
                              step_reply)
from .target_input import TargetInput
from .tick import Tick
from .tick_loop import NodeClockTicks
from .tick_record import TickRecord
from .wrench_input import WrenchInput
from ..physics import MouseSimulation


class SimulatorControls:
    """
    The pause state and the four services' callbacks.

    :param simulation: the body that ``~/reset`` returns to its initial state.
    :param tick: runs the single tick of ``~/step``.
    :param record: the ticks' record (the tick length, for the reply).
    :param node_clock_ticks: the driver on the node's clock.
    :param clock_ticks: the driver on the simulated clock.
    :param target: the target input (released, or holding the initial anchor after a reset).
    :param wrench: the wrench input (dropped on reset).
    :param now_ns: the node's time (ns).
    :param restore_anchor: restores the configured anchor; returns None, or why it could not and
        what it was as ``(anchor, reason)``.
    :param hold_initial_anchor: returns whether a reset holds the initial anchor.
    """

    def __init__(self, *, simulation: MouseSimulation, tick: Tick, record: TickRecord,
                 node_clock_ticks: NodeClockTicks, clock_ticks: ClockTicks,
                 target: TargetInput, wrench: WrenchInput, now_ns: Callable[[], int],
                 restore_anchor: Callable[[], Optional[tuple]],
                 hold_initial_anchor: Callable[[], bool]) -> None:
        """Start running (not paused)."""
        self._simulation = simulation
        self._tick = tick
        self._record = record
        self._node_clock_ticks = node_clock_ticks
        self._clock_ticks = clock_ticks
        self._target = target
        self._wrench = wrench
        self._now_ns = now_ns
        self._restore_anchor = restore_anchor
        self._hold_initial_anchor = hold_initial_anchor
        self.paused = False
        # How many times the physics resumed: a rate window across a pause measures nothing.
        self.resumes = 0

    def on_pause(self, request: SetBool.Request, response: SetBool.Response):
        """
        Pause (true) or resume (false) the physics.

        Resuming catches nothing up: the simulated clock paces on from where it stood, the
        node-clock grid starts again at the next timer call.
        """
        pause = bool(request.data)
        response.success = True
        response.message = pause_reply(pause, self.paused, self._simulation.time)
        if pause == self.paused:
            return response
        self.paused = pause
        sim_clock = self._clock_ticks.sim_clock
        if pause:
            sim_clock.pause()
        else:
            sim_clock.resume()
            self._node_clock_ticks.resume()
            self.resumes += 1
        return response

    def on_step(self, _request: Trigger.Request, response: Trigger.Response):
        """While paused: run exactly one tick and publish it; refused while running."""
        clock_ticks = self._clock_ticks
        waiting = None if clock_ticks.on else self._node_clock_ticks.waiting_for_clock()
        refusal = step_refusal(self.paused, waiting)
        if refusal is not None:
            response.success = False
            response.message = refusal
            return response
        if clock_ticks.on:
            stamp = clock_ticks.step(on_grid=False)
        else:
            stamp = self._node_clock_ticks.step_stamp()
            self._tick.run(stamp)
        response.success = True
        response.message = step_reply(self._record.dt, self._simulation.time)
        return response

    def on_reset(self, _request: Trigger.Request, response: Trigger.Response):
        """Back to the initial state, the configured anchor and the initial hold; no wrench."""
        failure = self._restore_anchor()
        if failure is not None:
            response.success = False
            response.message = reset_refusal(*failure)
            return response
        self._simulation.reset()
        self._target.hold_initial_anchor()
        self._wrench.clear()
        if self.paused:
            # No tick will publish it until the node runs again: every subscriber shows the
            # old pose meanwhile. Published at once, stamped with the latest tick.
            self._tick.publish_state()
        response.success = True
        response.message = reset_reply(self._hold_initial_anchor())
        return response

    def on_release(self, _request: Trigger.Request, response: Trigger.Response):
        """Let go of the target: the body flies free (a grabbed point stays the anchor)."""
        response.success = True
        response.message = release_reply(self._target.release())
        return response
