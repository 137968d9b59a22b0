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
Which external wrenches the node takes, and how long it applies one: the ``wrench`` policy.

A wrench (frame, force, torque) is taken when its frame is the node's ``frame_id`` (an empty
frame counts as it: no tf lookup is made), its six components are finite, |force| <=
``max_wrench_force`` and |torque| <= ``max_wrench_torque``. A wrench beyond a bound is refused
whole, not clamped: a clamped wrench would be one nobody sent, in a direction that is only
right by luck when one component overflowed. A refused wrench changes nothing: the one
applied before goes on until its own timeout. Each refusal has a key ('wrench frame',
'wrench finite', 'wrench force', 'wrench torque') to throttle repeated ones under.

``HeldWrench`` applies the latest wrench taken until ``wrench_timeout`` passes without
another (0 = hold it until one replaces it). A wrench takes effect from the tick stamped at or
after its own stamp (``effective_time``): a push and the zero wrench that ends it, stamped
with the push's start and end, then last their duration within a tick, whatever the latency
and however late the node runs its ticks, save the ticks that ran before a message arrived. A
stamp far from the node's time (another clock, or none) counts as the time it arrived. Plain
floats and strings only, so that the node and the command line tool apply the same policy.
"""

from collections import deque
from dataclasses import dataclass
import math
from typing import NamedTuple, Optional, Sequence, Tuple

from .target_gate import apart, Refusal

Vector3 = Tuple[float, float, float]
ZERO: Vector3 = (0.0, 0.0, 0.0)
# No wrench: what the simulation applies without one.
NO_WRENCH: Tuple[Vector3, Vector3] = (ZERO, ZERO)
# How far (ns) before the node's time a wrench's stamp may lie and still say when it applies:
# farther, it is on another clock (or 0, unset) and the wrench applies from its arrival.
STAMP_WINDOW_NS = 1_000_000_000


def effective_time(stamp_ns: int, now_ns: int) -> int:
    """
    Return the node's time (ns) from which a wrench stamped ``stamp_ns`` applies.

    Its stamp when that lies within ``STAMP_WINDOW_NS`` before ``now_ns`` (its arrival) or at
    most as far after it; else ``now_ns``. A zero stamp is none (``ros2 topic pub`` leaves it
    so), even on a simulated clock that starts at zero: it applies from its arrival.
    """
    if stamp_ns == 0 or abs(now_ns - stamp_ns) > STAMP_WINDOW_NS:
        return now_ns
    return stamp_ns


@dataclass(frozen=True)
class WrenchGate:
    """
    The node's wrench policy for its ``frame_id`` and bounds (N, N m).

    ``reason`` texts read after 'ignoring wrench ' (the node) or 'wrench refused: ' (a CLI).
    """

    frame_id: str
    max_force: float
    max_torque: float

    def refusal(self, frame: str, force: Sequence[float],
                torque: Sequence[float]) -> Optional[Refusal]:
        """
        Return None when the node takes the wrench, else why not.

        :param frame: the wrench's frame_id; '' is the node's frame.
        :param force: force through the COM (N), world frame.
        :param torque: torque (N m), world frame.
        """
        if frame and frame != self.frame_id:
            return Refusal('wrench frame', f'in frame {frame!r}: this node works in '
                                           f'{self.frame_id!r} (no tf lookup is made)')
        values = tuple(map(float, force)) + tuple(map(float, torque))
        if not all(math.isfinite(v) for v in values):
            return Refusal('wrench finite', f'force {values[:3]} torque {values[3:]}: not finite')
        magnitude = math.hypot(*values[:3])
        if magnitude > self.max_force:
            value, bound = apart(magnitude, self.max_force)
            return Refusal('wrench force', f'force {values[:3]}: |force| {value} N exceeds '
                                           f'max_wrench_force {bound} N')
        magnitude = math.hypot(*values[3:])
        if magnitude > self.max_torque:
            value, bound = apart(magnitude, self.max_torque)
            return Refusal('wrench torque', f'torque {values[3:]}: |torque| {value} N m '
                                            f'exceeds max_wrench_torque {bound} N m')
        return None


class AppliedWrench(NamedTuple):
    """A wrench taken at ``since_ns`` (the node's time): force (N) and torque (N m)."""

    force: Vector3
    torque: Vector3
    since_ns: int


class HeldWrench:
    """The latest wrench taken, until ``timeout`` seconds pass without another (0 = never)."""

    def __init__(self) -> None:
        """Hold no wrench, none scheduled."""
        self.applied: Optional[AppliedWrench] = None
        # Wrenches taken and not yet in effect: (from when, force, torque), in arrival order.
        self._scheduled = deque()

    def schedule(self, force: Sequence[float], torque: Sequence[float], at_ns: int) -> None:
        """Apply ``force`` and ``torque`` from the tick stamped ``at_ns`` or later; zero ends."""
        self._scheduled.append((at_ns, tuple(map(float, force)), tuple(map(float, torque))))

    def advance(self, stamp_ns: int) -> bool:
        """
        Put in effect the wrenches scheduled up to ``stamp_ns`` (the tick's); return if any was.

        A zero wrench clears the one held: nothing is left to time out.
        """
        scheduled, changed = self._scheduled, False
        while scheduled and scheduled[0][0] <= stamp_ns:
            at_ns, force, torque = scheduled.popleft()
            if force == torque == ZERO:
                self.applied = None
            else:
                self.applied = AppliedWrench(force, torque, at_ns)
            changed = True
        return changed

    def take(self, force: Sequence[float], torque: Sequence[float], now_ns: int) -> None:
        """Apply ``force`` and ``torque`` from now on, replacing the wrench held."""
        self.applied = AppliedWrench(tuple(map(float, force)), tuple(map(float, torque)),
                                     now_ns)

    def clear(self) -> None:
        """Hold no wrench, and drop the scheduled ones."""
        self.applied = None
        self._scheduled.clear()

    def expired(self, now_ns: int, timeout: float) -> bool:
        """Drop the wrench when it is older than ``timeout`` (s, > 0); return whether it was."""
        applied = self.applied
        if applied is None or timeout <= 0.0 or now_ns - applied.since_ns <= timeout * 1e9:
            return False
        self.applied = None
        return True

    @property
    def wrench(self) -> Tuple[Vector3, Vector3]:
        """Return (force, torque) to apply: zero without a wrench."""
        applied = self.applied
        return NO_WRENCH if applied is None else (applied.force, applied.torque)
