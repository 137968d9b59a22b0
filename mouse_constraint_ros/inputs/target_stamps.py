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

Anything else times the target by its arrival, as an unstamped one.

A usable stamp becomes the core's time through the latest tick: the state published with a
tick's stamp is the core's state after that tick's step, so a time on the node's clock is the
core's time of the latest tick plus the clock's distance from that tick's stamp
(``core_time``). Dropped ticks, a pause or a new grid shift the two apart; ``CoreClock`` says
by how much the offset moved since the last stamp it mapped, and the stream's times already
mapped are shifted by as much (``MouseSimulation.shift_target_times``): the stream goes on,
on the new offset, instead of losing its motion. ``TargetTiming`` does all of that for one
target, for the node and for the replays that stand in for it without ROS.

Plain integers (nanoseconds) and floats, no rclpy.
"""

from typing import Optional, Sequence, Tuple

NANOSECONDS_PER_SECOND = 1_000_000_000

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


def core_time(stamp_ns: int, *, tick_stamp_ns: int, tick_core_time: float) -> float:
    """
    Return the core's time (s) at ``stamp_ns`` on the node's clock.

    :param tick_stamp_ns: the stamp of the latest tick run (ns, node's clock).
    :param tick_core_time: the core's time after that tick's step (s).
    """
    return tick_core_time + (stamp_ns - tick_stamp_ns) * 1e-9


class CoreClock:
    """``core_time`` for a stream of stamps, and how far the offset moved since the last one."""

    def __init__(self) -> None:
        """Start with no stamp mapped."""
        # The node's clock minus the core's time at the latest tick (ns), at the last stamp.
        self.offset_ns: Optional[int] = None

    def time_of(self, stamp_ns: int, *, tick_stamp_ns: int, tick_core_time: float,
                tick_s: float) -> Tuple[float, float]:
        """
        Return the core's time of ``stamp_ns``, and by how much (s) the times mapped before move.

        The shift is minus the offset's change since the last stamp when that is half a tick
        or more (dropped ticks: the core fell behind the clock), else 0.

        :param tick_stamp_ns: the stamp of the latest tick run (ns, node's clock).
        :param tick_core_time: the core's time after that tick's step (s).
        :param tick_s: the node's tick (s).
        """
        offset = tick_stamp_ns - round(tick_core_time * NANOSECONDS_PER_SECOND)
        previous, self.offset_ns = self.offset_ns, offset
        moved = previous is not None and abs(offset - previous) >= 0.5e9 * tick_s
        return (core_time(stamp_ns, tick_stamp_ns=tick_stamp_ns, tick_core_time=tick_core_time),
                (previous - offset) * 1e-9 if moved else 0.0)


class TargetTiming:
    """
    How a target is timed and handed to the simulation: by its stamp where usable, else arrival.

    :param window_s: the stream window (s): ``physics.target_stream.STREAM_GAP``.
    """

    def __init__(self, window_s: float) -> None:
        """Start with no stamp used or mapped."""
        self.stamps = TargetStamps(window_s)
        self.clock = CoreClock()

    def take(self, simulation, point: Sequence[float], *, stamp_ns: int, now_ns: int,
             tick_stamp_ns: int, tick_s: float, ticked: bool) -> None:
        """
        Set ``point`` as ``simulation``'s target, timed.

        :param simulation: a ``physics.MouseSimulation`` (its ``time`` is the arrival).
        :param stamp_ns: the target's header stamp (ns).
        :param now_ns: the node's time at its arrival (ns).
        :param tick_stamp_ns: the stamp of the latest tick run (ns).
        :param tick_s: the node's tick (s).
        :param ticked: whether a tick ran: before the first, no stamp can be mapped.
        """
        arrival = simulation.time
        if ticked and self.stamps.refusal(stamp_ns, now_ns=now_ns, tick_s=tick_s) is None:
            time, shift = self.clock.time_of(stamp_ns, tick_stamp_ns=tick_stamp_ns,
                                             tick_core_time=arrival, tick_s=tick_s)
            if shift:
                simulation.shift_target_times(shift)
            simulation.set_target(point, time=time, stamped=True)
        else:
            simulation.set_target(point, time=arrival)
