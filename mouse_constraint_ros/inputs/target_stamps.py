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
Which target stamps time the drag: the policy of ``mouse_constraint``'s ``target`` stamps.

A browser or a tool that stamps each target with the time of its pointer event says when the
pointer was there; the time it reaches the node adds a varying delay (the sender's jitter,
transport, the wait for the next tick). A stamp is used as the target's time when it is usable:

- not zero (a zero stamp means "not stamped");
- on the node's clock: not ahead of the node's time by more than one tick, and not older than
  the stream window (a stamp of another clock source, wall time sent to a node on simulated
  time or the reverse, falls outside one or the other);
- later than the last stamp used, unless that one is itself ahead of the node's time by more
  than a tick (the clock went back: a new clock, and the old stamps say nothing about it).

Anything else times the target by its arrival, as an unstamped one. Plain integers
(nanoseconds), no rclpy: the node asks ``TargetStamps.refusal`` for every target, and the
conversion of a usable stamp to the core's time is ``timing.tick_grid.core_time``.
"""

from typing import Optional

# The keys of the refusals, in the order the checks run.
REASONS = ('zero', 'future', 'old', 'order')


def stamp_refusal(stamp_ns: int, *, now_ns: int, tick_ns: int, window_ns: int,
                  previous_ns: Optional[int]) -> Optional[str]:
    """
    Return None if ``stamp_ns`` can time a target, else the key in ``REASONS`` of why not.

    :param stamp_ns: the target's header stamp (ns).
    :param now_ns: the node's time when the target came (ns).
    :param tick_ns: the node's tick (ns): a stamp may be ahead of ``now_ns`` by this much.
    :param window_ns: the stream window (ns): an older stamp cannot continue a stream.
    :param previous_ns: the last stamp used, or None.
    """
    if stamp_ns == 0:
        return 'zero'
    if stamp_ns > now_ns + tick_ns:
        return 'future'
    if stamp_ns < now_ns - window_ns:
        return 'old'
    if previous_ns is not None and stamp_ns <= previous_ns <= now_ns + tick_ns:
        return 'order'
    return None


class TargetStamps:
    """
    ``stamp_refusal`` with the last stamp used kept between targets.

    :param window_s: the stream window (s): ``physics.target_motion.STREAM_GAP``, the longest a
        stream goes between two points.
    """

    def __init__(self, window_s: float) -> None:
        """Start with no stamp used."""
        self.window_ns = round(window_s * 1e9)
        self.previous_ns: Optional[int] = None

    def refusal(self, stamp_ns: int, *, now_ns: int, tick_s: float) -> Optional[str]:
        """Return None and remember ``stamp_ns`` if it times the target, else why not."""
        reason = stamp_refusal(stamp_ns, now_ns=now_ns, tick_ns=round(tick_s * 1e9),
                               window_ns=self.window_ns, previous_ns=self.previous_ns)
        if reason is None:
            self.previous_ns = stamp_ns
        return reason
