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
The fixed-rate tick grid: which physics steps are due at a clock reading, and their stamps.

Tick n is due at t0 + n dt with dt = 1 / rate_hz exactly: the period is kept as an integer
fraction of nanoseconds, so stamps never drift however long the node runs. When the caller comes
late it is told to run every missed tick (catch-up), up to a bound; beyond the bound the missed
ticks are dropped, so simulated time falls behind the clock instead of the node falling further
behind. A clock that jumps backwards (a /clock replay restarting) restarts the grid at the new
time rather than waiting for the old one to come back. On a clock that can also jump forwards
(simulated time: a seek in a replay, a simulator that skips), the caller names how far a
reading may lie past the latest tick before it is a jump (``due``'s ``max_jump``): beyond it
the grid restarts there too, and the time skipped is no tick the node dropped.

The node keeps one grid on its clock (``for_rate``, catching up on at most
``MAX_CATCH_UP_SECONDS``); the first timer call puts t0 where the timer scheduled it
(``scheduled_origin``), and a change of clock source (``use_sim_time`` flipped) restarts it on
the new clock. The texts of these events and of the drops are here too.

The grid is where the node's clock meets the core's time: the state published with a tick's
stamp is the core's state after that tick's step (``inputs.target_stamps.core_time`` maps a
target's stamp onto the core's time through the latest tick).
"""

from fractions import Fraction
import math
from typing import NamedTuple, Optional

NANOSECONDS_PER_SECOND = 1_000_000_000
# Catch up on at most this much missed time in one timer callback (s); older ticks are dropped.
MAX_CATCH_UP_SECONDS = 0.1
# Why ticks beyond the catch-up bound were dropped.
CATCH_UP_CAUSE = f'more than the {MAX_CATCH_UP_SECONDS:g} s catch-up bound was missed'
# On simulated time, a reading this far (s) past the latest tick is a jump of the clock (a seek,
# a skip), not ticks missed: the grid restarts at it. Missed ticks within it are dropped.
MAX_CLOCK_STEP_SECONDS = 1.0


class DueTicks(NamedTuple):
    """
    The ticks to run now: ``first`` to ``first + count - 1``, after ``dropped`` skipped ones.

    ``restarted``: the clock jumped and the grid restarts at the reading, ``jump_ns`` (< 0:
    backwards) from the latest tick's stamp.
    """

    first: int
    count: int
    dropped: int
    restarted: bool
    jump_ns: int = 0


class TickGrid:
    """
    The grid t0 + n / rate_hz in integer nanoseconds, started at the first clock reading.

    :param rate_hz: ticks per second (> 0).
    :param max_catch_up: the most ticks one call may ask for; older ones are dropped.
    """

    @classmethod
    def for_rate(cls, rate_hz: float) -> 'TickGrid':
        """Return the node's grid at ``rate_hz``: catching up on ``MAX_CATCH_UP_SECONDS``."""
        return cls(rate_hz, math.ceil(MAX_CATCH_UP_SECONDS * rate_hz))

    def __init__(self, rate_hz: float, max_catch_up: int) -> None:
        """Create a grid that starts at the first ``due`` call."""
        period = Fraction(NANOSECONDS_PER_SECOND) / Fraction(rate_hz)
        self._numerator, self._denominator = period.numerator, period.denominator
        self.rate_hz = float(rate_hz)
        self.max_catch_up = max(1, int(max_catch_up))
        self._origin: Optional[int] = None
        self._next = 0

    @property
    def started(self) -> bool:
        """Return whether the grid has its origin t0."""
        return self._origin is not None

    @property
    def origin(self) -> Optional[int]:
        """Return t0 in nanoseconds, or None before the first reading."""
        return self._origin

    def stamp(self, tick: int) -> int:
        """Return the time of ``tick`` in nanoseconds, t0 + floor(tick dt)."""
        return self._origin + tick * self._numerator // self._denominator

    def tick_at(self, now: int) -> int:
        """Return the latest tick due at ``now`` (ns): the last whose stamp is not after it."""
        return self.tick_after(now) - 1

    def tick_after(self, stamp: int) -> int:
        """Return the first tick whose stamp is after ``stamp`` (ns)."""
        return -(-(stamp - self._origin + 1) * self._denominator // self._numerator)

    def restart(self, now: int) -> None:
        """Put tick 0 at ``now``; it is due at once."""
        self._origin = now
        self._next = 0

    def due(self, now: int, max_jump: Optional[int] = None) -> DueTicks:
        """
        Return the ticks due at clock reading ``now`` (ns) and mark them as run.

        :param max_jump: how far (ns) ``now`` may lie past the latest tick's stamp; beyond it
            the clock jumped forwards and the grid restarts at ``now``. None: never.
        """
        jump, restarted = 0, False
        if self._origin is not None:
            jump = now - self.stamp(max(0, self._next - 1))
            restarted = jump < 0 or (max_jump is not None and jump > max_jump)
        if self._origin is None or restarted:
            self.restart(now)
        last_due = (now - self._origin) * self._denominator // self._numerator
        count = last_due - self._next + 1
        jump = jump if restarted else 0
        if count <= 0:
            return DueTicks(self._next, 0, 0, restarted, jump)
        dropped = max(0, count - self.max_catch_up)
        first = self._next + dropped
        self._next = last_due + 1
        return DueTicks(first, count - dropped, dropped, restarted, jump)


def scheduled_origin(now: int, until_next: Optional[int], period: int) -> int:
    """
    Return t0 for the first timer call: where the timer scheduled it, not where it ran (ns).

    Each later call then finds exactly its own tick due, however late (up to a period) it runs,
    instead of only when its jitter beats the first call's.

    :param now: the clock reading of the first call.
    :param until_next: the timer's time until its next call (None if it cannot say).
    :param period: the timer's period.
    """
    if until_next is not None and 0 <= until_next <= period:
        return now + until_next - period
    return now


def clock_change_text(sim_time: bool, now: int) -> str:
    """Return what the node logs when use_sim_time flips and the grid restarts at ``now``."""
    return (f'clock changed to {"simulated" if sim_time else "system"} time: restarting the '
            f'tick grid at {now * 1e-9:.9f} s without catching up')


def clock_jump_text(now: int, jump_ns: int = -1) -> str:
    """
    Return what the node warns when its clock jumped and the grid restarts at ``now``.

    :param jump_ns: the jump from the latest tick's stamp (< 0: backwards).
    """
    if jump_ns < 0:
        return f'clock jumped backwards: restarting the tick grid at {now * 1e-9:.9f} s ' \
            'without catching up'
    return (f'clock jumped forwards by {jump_ns * 1e-9:.9f} s: restarting the tick grid at '
            f'{now * 1e-9:.9f} s; the time skipped is no dropped tick')


def drop_text(rate_hz: float, count: int, total: int, cause: str) -> str:
    """Return the warning of ``count`` dropped ticks (``total`` since start) and why."""
    return (f'cannot keep {rate_hz:g} Hz: dropped {count} ticks ({total} in all): {cause}; '
            'simulated time falls behind')
