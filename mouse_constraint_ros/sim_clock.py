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
one tick at a time. Plain integers and floats only (no rclpy), so the pacing is tested alone.
"""

from fractions import Fraction
import math
from typing import Optional

NANOSECONDS_PER_SECOND = 1_000_000_000


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
