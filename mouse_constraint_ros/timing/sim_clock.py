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
The simulated time of a node that is its own clock (``publish_clock``), paced by a wall clock.

Simulated time is what the ticks have run: tick n (n = 1, 2, ...) of a grid is the state at
origin + n / rate_hz, kept in integer nanoseconds as ``TickGrid`` keeps it, so stamps never
drift. The clock reads the time of the last tick run (the origin before the first): it never
runs ahead of the published state and never jumps.

Pacing maps a steady wall clock onto it: from an anchor (wall w0, simulated s0) the ticks with
time <= s0 + real_time_factor (w - w0) are due at wall time w. A factor of 0 means no pacing:
every call may run as many ticks as it likes. The anchor moves to (now, the clock's reading)
whenever the pacing changes (a new factor, a resume, a new rate), so the simulated time goes on
from where it stands, without a jump and without catching up on wall time that passed paused.
When the machine cannot keep the factor (more than ``max_lag`` wall seconds of ticks are
due), the anchor moves up as well: simulated time then runs slower than asked, and ``slipped``
adds up the simulated time given up, instead of ticks being skipped.

Paused, no tick is due and the clock stands still; ``step`` is the one way to advance it then,
one tick at a time.

``ClockPacer`` runs the due ticks in the node's tick timer, a steady-clock timer of a period at
least ``MIN_CLOCK_PERIOD``: each call runs ticks for at most ``CLOCK_BUDGET_SHARE`` of the
period. The EventsExecutor queues a timer event every period whatever the callback takes: a
call that ends within the period leaves no backlog, so services and parameters answer within
about a period. Nothing is dropped at the budget; the simulated clock just runs slower. A call
that outlasts its period (one tick of many substeps) is followed by a rest of twice its length,
in which calls return at once and so clear the events queued meanwhile.

``PacingMeter`` says what the pacing achieved between two samples (the node's diagnostics).

Plain integers and floats only (no rclpy), so the pacing is tested alone.
"""

from fractions import Fraction
import math
import time
from typing import Callable, Optional, Tuple

NANOSECONDS_PER_SECOND = 1_000_000_000
# The shortest period (s, steady clock) of the tick timer; each call runs the ticks due (at
# real_time_factor 0, as many as fit in CLOCK_BUDGET_SHARE of the period).
MIN_CLOCK_PERIOD = 0.001
# The share of the tick timer's period one call may run ticks for.
CLOCK_BUDGET_SHARE = 0.8


class SimulatedClock:
    """
    Simulated time on the tick grid of ``rate_hz`` from ``origin_ns``, paced by a wall clock.

    :param rate_hz: ticks per simulated second (> 0).
    :param real_time_factor: simulated seconds per wall second (>= 0); 0 = as fast as the
        caller runs ticks.
    :param max_lag: wall seconds of due ticks (> 0) beyond which the pacing slips rather than
        catching up.
    :param origin_ns: the simulated time before the first tick (ns).
    """

    def __init__(self, rate_hz: float, real_time_factor: float, *, max_lag: float,
                 origin_ns: int = 0) -> None:
        """Create a running clock at ``origin_ns`` whose pacing starts at the first ``due``."""
        self.max_lag = float(max_lag)
        self.real_time_factor = float(real_time_factor)
        self.paused = False
        self.slipped_ns = 0
        self._anchor: Optional[tuple] = None
        self._set_grid(rate_hz, origin_ns)

    def _set_grid(self, rate_hz: float, origin_ns: int) -> None:
        period = Fraction(NANOSECONDS_PER_SECOND) / Fraction(rate_hz)
        self._numerator, self._denominator = period.numerator, period.denominator
        self.rate_hz = float(rate_hz)
        self._origin = int(origin_ns)
        self._ticks = 0

    @property
    def now_ns(self) -> int:
        """Return the simulated time: that of the last tick run, or the origin (ns)."""
        return self.stamp(self._ticks)

    @property
    def ticks(self) -> int:
        """Return how many ticks of the current grid have run."""
        return self._ticks

    def stamp(self, tick: int) -> int:
        """Return the simulated time of ``tick`` of the current grid (ns)."""
        return self._origin + tick * self._numerator // self._denominator

    def due(self, wall_ns: int) -> Optional[int]:
        """
        Return how many ticks are due at wall time ``wall_ns``; None: any number (factor 0).

        The first call after a change of pacing anchors it there and finds none due.
        """
        if self.paused:
            return 0
        if self.real_time_factor == 0.0:
            return None
        if self._anchor is None:
            self._anchor = (wall_ns, self.now_ns)
            return 0
        wall0, sim0 = self._anchor
        target = sim0 + math.floor((wall_ns - wall0) * self.real_time_factor)
        last_due = (target - self._origin) * self._denominator // self._numerator
        count = max(0, last_due - self._ticks)
        most = max(1, math.ceil(self.max_lag * self.real_time_factor * self.rate_hz))
        if count > most:
            # Behind by more than max_lag: give up the rest of the lag, keep the due ticks.
            kept = self.stamp(self._ticks + most)
            self.slipped_ns += target - kept
            self._anchor = (wall_ns, kept)
            count = most
        return count

    def advance(self) -> int:
        """Count one tick as run; return its simulated time (ns), the clock's new reading."""
        self._ticks += 1
        return self.now_ns

    def set_real_time_factor(self, factor: float) -> None:
        """Pace by ``factor`` from the next ``due`` on, from the time the clock reads."""
        self.real_time_factor = float(factor)
        self._anchor = None

    def set_rate(self, rate_hz: float) -> None:
        """Start a grid of ``rate_hz`` at the clock's reading; its tick 1 is 1 / rate_hz on."""
        self._set_grid(rate_hz, self.now_ns)
        self._anchor = None

    def pause(self) -> None:
        """Stop the clock: no tick is due until ``resume``; ``advance`` still steps it."""
        self.paused = True

    def resume(self) -> None:
        """Run again, paced from the next ``due`` on: paused wall time is not caught up."""
        self.paused = False
        self._anchor = None


class ClockPacer:
    """
    How one call of the tick timer runs the ticks a ``SimulatedClock`` says are due.

    :param rate_hz: the tick rate (> 0).
    :param real_time_factor: simulated seconds per wall second (>= 0); 0 = as fast as it runs.
    :param clock: returns wall time in seconds (``time.perf_counter``).
    """

    def __init__(self, rate_hz: float, real_time_factor: float, *,
                 clock: Callable[[], float] = time.perf_counter) -> None:
        """Take the timer period of the ticks due in wall time, at least MIN_CLOCK_PERIOD."""
        self.period = (MIN_CLOCK_PERIOD if real_time_factor == 0.0 else
                       max(MIN_CLOCK_PERIOD, 1.0 / (rate_hz * real_time_factor)))
        self.budget = CLOCK_BUDGET_SHARE * self.period
        self._clock = clock
        # Time of ``clock`` until which calls return at once, after one that overran its period.
        self.rest_until = -math.inf

    def start(self) -> Optional[float]:
        """Return the time a call starts at, or None while resting (the call returns)."""
        started = self._clock()
        return None if started < self.rest_until else started

    def run(self, sim_clock: SimulatedClock, tick: Callable[[int, int], object],
            due: Optional[int], started: float) -> int:
        """
        Advance ``sim_clock`` and ``tick(stamp, n)`` until ``due`` ran or the budget is spent.

        The ticks left stay due: the clock's pacing slips if the lag grows beyond its bound.

        :param due: what ``sim_clock.due`` returned (> 0, or None: any number).
        :param started: what ``start`` returned for this call.
        :returns: how many ran (at least one).
        """
        clock, budget = self._clock, self.budget
        advance = sim_clock.advance
        ran = 0
        while due is None or ran < due:
            tick(advance(), sim_clock.ticks)
            ran += 1
            if clock() - started > budget:
                break
        spent = clock() - started
        if spent > self.period:
            self.rest_until = started + 2.0 * spent
        return ran


class PacingMeter:
    """The simulated seconds per wall second, and the time slipped, between two samples."""

    def __init__(self) -> None:
        """Start with no sample: the first one measures nothing."""
        # (wall ns, simulated ns, slipped ns) at the last sample.
        self._last: Optional[Tuple[int, int, int]] = None

    def sample(self, wall_ns: int, clock: SimulatedClock) -> Tuple[Optional[float], float]:
        """
        Return (achieved factor or None, simulated seconds slipped) since the last sample.

        None before a second sample, or when the wall clock has not moved since the last one.
        """
        now = (wall_ns, clock.now_ns, clock.slipped_ns)
        last, self._last = self._last, now
        if last is None or wall_ns <= last[0]:
            return None, 0.0
        return (now[1] - last[1]) / (wall_ns - last[0]), (now[2] - last[2]) * 1e-9
