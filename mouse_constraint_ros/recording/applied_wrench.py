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
The wrench the recorded node applies at each tick, as the wrenches received on ``wrench`` make it.

The node's own policy (``inputs.wrench_gate``) decides, with the node's frame (the poses') and
its ``max_wrench_force``, ``max_wrench_torque`` and ``wrench_timeout`` as the recording knows
them: a wrench the node refuses changes nothing; one it takes applies from the tick stamped at
its stamp when that lies on the poses' clock (within ``STAMP_WINDOW_NS`` of the latest pose
received), else from the tick after it came; it holds until the next one (a zero wrench ends
it: ``mouse_wrench`` sends one at the push's end), until ``wrench_timeout`` passes without
another, or until a ``~/reset``. Without the node's bounds every finite wrench is taken, and
without its timeout a wrench holds until the next.

``push_spans`` reads the pushes back from rows: the runs of ticks with a wrench applied.
"""

import math
from typing import Callable, List, Mapping, NamedTuple, Optional, Sequence, Tuple

from ..inputs.wrench_gate import effective_time, HeldWrench, NO_WRENCH, WrenchGate
from ..physics.algebra import Vector3
from ..wire.cdr.stamped import StampedFields

# The doubles after a WrenchStamped's header: force x, y, z and torque x, y, z.
WRENCH_DOUBLES = 6


class ReceivedWrench(NamedTuple):
    """A wrench received: its frame, from when the node applies it (ns), force and torque."""

    frame_id: str
    at_ns: int
    force: Vector3
    torque: Vector3


def received_wrench(fields: StampedFields, latest_pose_ns: Optional[int]) -> ReceivedWrench:
    """
    Return a raw-read wrench with the time the node applies it from (``effective_time``).

    :param latest_pose_ns: the stamp of the latest pose received before it (its arrival on the
        poses' clock); None before the first, when it applies from the first tick.
    """
    values = fields.values
    at = 0 if latest_pose_ns is None else effective_time(fields.stamp_ns, latest_pose_ns)
    return ReceivedWrench(fields.frame_id, at, tuple(values[:3]), tuple(values[3:]))


class WrenchView:
    """
    The wrench the recorded node applies, tick by tick (see the module).

    :param parameters: the node's parameters as the recording follows them (``NodeView``): the
        bounds and the timeout are read from it when a wrench is taken and a tick made.
    :param frame: the node's frame (the latest pose's; '' before the first), read when a
        wrench is taken.
    """

    def __init__(self, parameters: Mapping[str, object], frame: Callable[[], str]) -> None:
        """Hold no wrench."""
        self._parameters, self._frame = parameters, frame
        self._held = HeldWrench()

    def take(self, wrench: ReceivedWrench) -> None:
        """Schedule a wrench the node takes; a refused one changes nothing."""
        p = self._parameters
        # Before the first pose the node's frame is not known: the wrench's own is taken.
        gate = WrenchGate(self._frame() or wrench.frame_id, p.get('max_wrench_force', math.inf),
                          p.get('max_wrench_torque', math.inf))
        if gate.refusal(wrench.frame_id, wrench.force, wrench.torque) is None:
            self._held.schedule(wrench.force, wrench.torque, wrench.at_ns)

    def clear(self) -> None:
        """Drop the wrench held and the scheduled ones (a ``~/reset``)."""
        self._held.clear()

    def at(self, stamp_ns: int) -> Tuple[Vector3, Vector3]:
        """Return the force (N) and torque (N m) applied at the tick stamped ``stamp_ns``."""
        held = self._held
        held.advance(stamp_ns)
        held.expired(stamp_ns, self._parameters.get('wrench_timeout', 0.0))
        return held.wrench


class PushSpan(NamedTuple):
    """A push: the time of its first tick and of the tick after its last (s), its peak |F| (N)."""

    start: float
    end: float
    peak_force: float


def push_spans(rows: Sequence) -> List[PushSpan]:
    """
    Return the pushes of ``rows`` (``rows.Row``, in order): each run of rows with a wrench.

    A push ends at the first row without one, or at the last row when the recording ends first.
    """
    spans: List[PushSpan] = []
    start: Optional[float] = None
    peak = 0.0
    for row in rows:
        applied = (row.wrench_force, row.wrench_torque) != NO_WRENCH
        if applied:
            if start is None:
                start, peak = row.time, 0.0
            peak = max(peak, math.hypot(*row.wrench_force))
        elif start is not None:
            spans.append(PushSpan(start, row.time, peak))
            start = None
    if start is not None:
        spans.append(PushSpan(start, rows[-1].time, peak))
    return spans
