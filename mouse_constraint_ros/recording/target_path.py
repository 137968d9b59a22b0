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
Where a stream of targets is at a tick's time: the line between the two targets around it.

The anchor error of a streamed drag is the anchor's distance to where the pointer was at the
tick's time, not to the latest target received, which is up to one stream gap old (a 50 Hz
circle at 0.5 m/s: 10 mm). Each target has a time on the poses' clock: its stamp when it has
one on that clock (within ``SAME_CLOCK_NS`` of the latest pose's stamp), else the stamp of the
latest pose received before it (the tick after which it came). Targets at most
``STREAM_GAP_NS`` apart with nothing else between them (no grab, parameter change, reset or
release) are a stream; between two of them the path is the straight line, and a tick's time
between them gives the point on it. From a stream's last target on (a lone click is a stream of
one) the path is that target: the pointer stopped there, whether or not the target had reached
the node by that tick (a stream's last point comes a delivery after its stamp). Before a
stream's first target, and across a pause longer than a stream's gap, there is no path, and the
row's target is the one the node holds.
"""

import bisect
from typing import List, NamedTuple, Optional

from ..physics.algebra import Vector3

# Targets at most this far apart (ns) are a stream: a mouse or a script sends 10 to 1000 a
# second; a click follows another after a human's pause.
STREAM_GAP_NS = 250_000_000
# A stamp this close (ns) to the latest pose's stamp is on the poses' clock.
SAME_CLOCK_NS = 1_000_000_000


class _Target(NamedTuple):
    index: int
    time_ns: int
    point: Vector3


class TargetPath:
    """
    The targets received, each with its time on the poses' clock, and the breaks between.

    The targets are kept in the order they came, with their times beside them: a stream whose
    times never go back (every unstamped one, and stamped ones in order) is searched by
    bisection, one row in O(log n) however fast the targets come; one whose times do go back
    somewhere (noted as they come) is sorted first.
    """

    def __init__(self) -> None:
        """Start with no target."""
        self._targets: List[_Target] = []
        self._indices: List[int] = []  # the targets' message indices, increasing
        self._times: List[int] = []  # their times
        self._back: List[int] = []  # the indices of targets earlier than the one before
        self._breaks: List[int] = []

    @staticmethod
    def time_of(stamp_ns: int, latest_pose_ns: Optional[int]) -> Optional[int]:
        """
        Return a target's time on the poses' clock (ns), None before any pose.

        :param stamp_ns: its header stamp (0: none).
        :param latest_pose_ns: the stamp of the latest pose received before it.
        """
        if latest_pose_ns is None:
            return None
        if stamp_ns and abs(stamp_ns - latest_pose_ns) <= SAME_CLOCK_NS:
            return stamp_ns
        return latest_pose_ns

    def add(self, index: int, time_ns: Optional[int], point: Vector3) -> None:
        """
        Add the target received as message ``index`` (increasing), at ``time_ns``.

        A target without a time (before the first pose) breaks the stream.
        """
        if time_ns is None:
            self.add_break(index)
            return
        if self._times and time_ns < self._times[-1]:
            self._back.append(index)
        self._targets.append(_Target(index, time_ns, point))
        self._indices.append(index)
        self._times.append(time_ns)

    def add_break(self, index: int) -> None:
        """Note that message ``index`` (a grab, a change, a reset, a release) ends a stream."""
        self._breaks.append(index)

    def at(self, time_ns: int, held: int) -> Optional[Vector3]:
        """
        Return the stream's point at ``time_ns``: its last target's from that target's time on.

        None before the stream's first target, and within a pause of over ``STREAM_GAP_NS``.

        :param held: the message index of the target the node holds: the stream is the targets
            received between the breaks around it.
        """
        after = bisect.bisect_right(self._breaks, held)
        lo = bisect.bisect_right(self._indices, self._breaks[after - 1]) if after else 0
        hi = (bisect.bisect_left(self._indices, self._breaks[after])
              if after < len(self._breaks) else len(self._indices))
        if lo >= hi:
            return None
        back = bisect.bisect_right(self._back, self._indices[lo])
        if back < len(self._back) and self._back[back] <= self._indices[hi - 1]:
            stream = sorted(self._targets[lo:hi], key=lambda t: (t.time_ns, t.index))
            k = bisect.bisect_left([t.time_ns for t in stream], time_ns)
            if k == 0:
                return None
            if k == len(stream):
                return stream[-1].point
            first, second = stream[k - 1], stream[k]
        else:  # In time order: times[k - 1] < time_ns <= times[k].
            k = bisect.bisect_left(self._times, time_ns, lo, hi)
            if k == lo:
                return None
            if k == hi:
                return self._targets[hi - 1].point
            first, second = self._targets[k - 1], self._targets[k]
        span = second.time_ns - first.time_ns
        if span > STREAM_GAP_NS:
            return None
        share = (time_ns - first.time_ns) / span
        return tuple(a + share * (b - a) for a, b in zip(first.point, second.point))

    def forget_before(self, time_ns: int) -> None:
        """Drop what no tick from ``time_ns`` on can need: targets a stream gap earlier."""
        keep = time_ns - 2 * STREAM_GAP_NS
        first = next((i for i, t in enumerate(self._times) if t >= keep), len(self._times))
        if first > 1:
            oldest = self._indices[first - 1]
            for kept in (self._targets, self._indices, self._times):
                del kept[:first - 1]
            self._breaks = [b for b in self._breaks if b >= oldest]
            self._back = [b for b in self._back if b > oldest]
