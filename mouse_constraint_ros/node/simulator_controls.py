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

Pause, resume and the single step are the ``Ticker``'s: pausing holds every driver of the tick,
resuming catches nothing up, ``~/step`` runs one tick while paused. ``~/reset`` restores the
configured anchor (through the node's own ``anchor`` parameter), the initial state and the
initial hold, and drops the wrench; while paused it publishes the state it leaves at once, at
a stamp of its own (``Ticker.publish_state``). The replies are ``service_replies``'.
"""

from typing import Callable, Optional

from std_srvs.srv import SetBool, Trigger

from .service_replies import (pause_reply, release_reply, reset_refusal, reset_reply, step_refusal,
                              step_reply)
from .target_input import TargetInput
from .ticker import Ticker
from .wrench_input import WrenchInput
from ..physics import MouseSimulation


class SimulatorControls:
    """
    The four services' callbacks.

    :param ticker: the owner of time: pause, resume and the single step.
    :param simulation: the body that ``~/reset`` returns to its initial state.
    :param target: the target input (released, or holding the initial anchor after a reset).
    :param wrench: the wrench input (dropped on reset).
    :param restore_anchor: restores the configured anchor; returns None, or why it could not and
        what it was as ``(anchor, reason)``.
    :param hold_initial_anchor: returns whether a reset holds the initial anchor.
    """

    def __init__(self, *, ticker: Ticker, simulation: MouseSimulation, target: TargetInput,
                 wrench: WrenchInput, restore_anchor: Callable[[], Optional[tuple]],
                 hold_initial_anchor: Callable[[], bool]) -> None:
        """Answer for ``ticker`` and ``simulation``."""
        self._ticker = ticker
        self._simulation = simulation
        self._target = target
        self._wrench = wrench
        self._restore_anchor = restore_anchor
        self._hold_initial_anchor = hold_initial_anchor

    def on_pause(self, request: SetBool.Request, response: SetBool.Response):
        """Pause (true) or resume (false) the physics; resuming catches nothing up."""
        pause = bool(request.data)
        response.success = True
        response.message = pause_reply(pause, self._ticker.paused, self._simulation.time)
        self._ticker.set_paused(pause)
        return response

    def on_step(self, _request: Trigger.Request, response: Trigger.Response):
        """While paused: run exactly one tick and publish it; refused while running."""
        ticker = self._ticker
        refusal = step_refusal(ticker.paused, ticker.waiting_for_clock(),
                               ticker.stands_still())
        if refusal is not None:
            response.success = False
            response.message = refusal
            return response
        ticker.step_once()
        response.success = True
        response.message = step_reply(ticker.record.dt, self._simulation.time)
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
        if self._ticker.paused:
            # No tick will publish it until the node runs again: every subscriber shows the
            # old pose meanwhile. Published at once, at a stamp of its own.
            self._ticker.publish_state()
        response.success = True
        response.message = reset_reply(self._hold_initial_anchor())
        return response

    def on_release(self, _request: Trigger.Request, response: Trigger.Response):
        """Let go of the target: the body flies free (a grabbed point stays the anchor)."""
        response.success = True
        response.message = release_reply(self._target.release())
        return response
