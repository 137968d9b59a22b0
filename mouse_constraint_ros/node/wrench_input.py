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
The node's external wrench input: what it takes, from which tick it applies, when it expires.

``WrenchGate`` judges a wrench (frame, finite, bounds); a taken one is scheduled in
``HeldWrench`` from the node's time its stamp gives (``effective_time``), and each tick puts in
effect what is due at its stamp and removes a wrench older than ``wrench_timeout`` (``apply``).
"""

from typing import Callable

from geometry_msgs.msg import WrenchStamped

from .parameters import NodeConfig
from ..inputs.input_timeouts import input_age, wrench_removal_text
from ..inputs.throttle import RefusalLog
from ..inputs.wrench_gate import effective_time, HeldWrench, NO_WRENCH, WrenchGate
from ..physics import MouseSimulation
from ..wire.messages import stamp_nanoseconds


class WrenchInput:
    """
    The ``wrench`` callback and the wrench each tick applies to the body.

    :param simulation: the body the wrench acts on.
    :param config: the node's configuration (``configure`` replaces it).
    :param now_ns: the node's time (ns).
    :param refuse: counts and warns about a refused wrench.
    :param log: logs a line at INFO.
    """

    def __init__(self, *, simulation: MouseSimulation, config: NodeConfig,
                 now_ns: Callable[[], int], refuse: RefusalLog,
                 log: Callable[[str], None]) -> None:
        """Hold no wrench."""
        self._simulation = simulation
        self._now_ns = now_ns
        self._refuse = refuse
        self._log = log
        self.held = HeldWrench()
        self.configure(config)

    def configure(self, config: NodeConfig) -> None:
        """Take the bounds, the frame and the timeout of a new configuration."""
        self._gate = WrenchGate(config.frame_id, config.max_wrench_force,
                                config.max_wrench_torque)
        self._timeout = config.wrench_timeout

    def on_wrench(self, message: WrenchStamped) -> None:
        """Schedule a wrench the gate takes, from the tick its stamp gives; ignore any other."""
        f, t = message.wrench.force, message.wrench.torque
        force, torque = (f.x, f.y, f.z), (t.x, t.y, t.z)
        refusal = self._gate.refusal(message.header.frame_id, force, torque)
        if refusal is not None:
            self._refuse(refusal, f'ignoring wrench {refusal.reason}')
            return
        # In effect from the tick stamped at its stamp (its end, for the zero wrench of a push).
        self.held.schedule(force, torque, effective_time(
            stamp_nanoseconds(message.header.stamp), self._now_ns()))

    def apply(self, stamp: int) -> None:
        """Put in effect what is due at the tick stamped ``stamp``; remove an expired wrench."""
        held = self.held
        if held.advance(stamp):
            self._simulation.wrench = held.wrench
        if held.applied is not None and held.expired(stamp, self._timeout):
            self._simulation.wrench = NO_WRENCH
            self._log(wrench_removal_text(self._timeout))

    def clear(self) -> None:
        """Drop the wrench held and the scheduled ones (``~/reset``)."""
        self.held.clear()
        self._simulation.wrench = NO_WRENCH

    def age(self, now_ns: int):
        """Return how old the applied wrench is (s), or None without one."""
        applied = self.held.applied
        return None if applied is None else input_age(applied.since_ns, now_ns)

    def restart_age(self, now_ns: int) -> None:
        """Count the applied wrench's age from ``now_ns`` (the node's time changed base)."""
        applied = self.held.applied
        if applied is not None:
            self.held.applied = applied._replace(since_ns=now_ns)
