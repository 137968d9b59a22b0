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
Which ticks of the node's grid a recording lacks: their count and the longest gap.

The node stamps pose and twist with its tick grid, t0 + floor(n / ``rate_hz``) in nanoseconds,
and publishes every tick, or with ``publish_rate_hz`` p the ticks that ``publish_ticks`` picks
(p / r of them, evenly spread). A row of the recording is a tick with both pose and twist, so
consecutive rows whose stamps lie k ticks apart lack round(k p / r) - 1 published ticks (k - 1
at every tick): the node dropped them, was paused, or the recorder did not keep them. A stamp
that goes back, or a step off the grid, is a restart of the grid (a clock jump, a new
``rate_hz``): nothing is counted across it; a stamp repeated (a reset while paused publishes
its state at the paused tick's stamp) is neither. Without the node's rates, the grid is taken
as the smallest step between rows. Plain integers; no ROS here.
"""

from fractions import Fraction
from typing import Dict, List, NamedTuple, Optional, Sequence


class Grid(NamedTuple):
    """The node's rates (Hz): ``publish_rate_hz`` 0 publishes every tick."""

    rate_hz: float
    publish_rate_hz: float = 0.0


class MissingTicks(NamedTuple):
    """What a recording of ``recorded`` rows lacks on the grid between its first and last row."""

    expected: int
    recorded: int
    missing: int
    longest_gap: float
    gap_at: float
    restarts: int
    grid: str

    def lines(self) -> list:
        """Return the report as ``key: value`` lines, for the CSV's last lines."""
        return [f'grid: {self.grid}', f'ticks_expected: {self.expected}',
                f'ticks_recorded: {self.recorded}', f'ticks_missing: {self.missing}',
                f'longest_gap_s: {self.longest_gap:.9g}', f'longest_gap_at_s: {self.gap_at:.9g}',
                f'grid_restarts: {self.restarts}']


class TickCounter:
    """
    ``missing_ticks`` counted as the rows come, in memory that does not grow with them.

    With the node's rates each step between rows is judged as it comes; without them, the
    distinct steps are counted (a handful on a grid: one tick, a nanosecond more or less, the
    gaps) and judged at the end against the smallest.

    :param grid: the node's rates, or None to take the smallest step between rows as the grid.
    """

    def __init__(self, grid: Optional[Grid]) -> None:
        """Count no row yet."""
        self._grid = grid
        if grid is None:
            self._period, self._share, self._exact = None, Fraction(1), False
        else:
            self._period = Fraction(1_000_000_000) / Fraction(grid.rate_hz)
            self._share = (Fraction(1) if grid.publish_rate_hz == 0.0
                           else Fraction(grid.publish_rate_hz) / Fraction(grid.rate_hz))
            self._exact = True
        self._first: Optional[int] = None
        self._previous: Optional[int] = None
        self.recorded = 0
        self._missing, self._restarts, self._longest, self._at = 0, 0, 0, 0
        # Without the grid: each positive step, its count and where it first came.
        self._steps: Dict[int, List[int]] = {}
        # With it: the ticks missing across the steps seen lately (None: a restart).
        self._judged: Dict[int, Optional[int]] = {}

    def add(self, stamp: int) -> None:
        """Take the next row's stamp (ns)."""
        self.recorded += 1
        previous, self._previous = self._previous, stamp
        if previous is None:
            self._first = stamp
            return
        step = stamp - previous
        if step == 0:
            return  # the same tick again: a reset while paused publishes the state it leaves
        if self._period is None:
            if step < 0:
                self._restarts += 1
            elif step in self._steps:
                self._steps[step][0] += 1
            else:
                self._steps[step] = [1, previous - self._first]
            return
        self._judge(step, 1, previous - self._first)

    def _judge(self, step: int, count: int, at: int) -> None:
        lacking = self._judged.get(step, -1)
        if lacking == -1:
            ticks = round(step / self._period) if step > 0 else 0
            # Stamps are t0 + floor(n P): two of them lie within 1 ns of k P apart.
            lacking = (None if ticks < 1 or (self._exact and abs(step - ticks * self._period) >= 1)
                       else max(0, round(ticks * self._share) - 1))
            if len(self._judged) >= 256:
                self._judged.clear()
            self._judged[step] = lacking
        if lacking is None:
            self._restarts += count
            return
        self._missing += count * lacking
        if step > self._longest:
            self._longest, self._at = step, at

    def result(self) -> MissingTicks:
        """Return what the rows so far lack."""
        if self._grid is not None:
            described = f'{self._grid.rate_hz:g} Hz' + (
                ', every tick published' if self._share == 1 else
                f', published at {self._grid.publish_rate_hz:g} Hz')
            missing, restarts, longest, at = (self._missing, self._restarts, self._longest,
                                              self._at)
        else:
            period = Fraction(min(self._steps)) if self._steps else Fraction(1)
            described = (f'{1e9 / float(period):.6g} Hz, the smallest step between rows (the '
                         "node's rate_hz was not read)")
            judged = TickCounter(Grid(1e9 / float(period)))
            judged._period, judged._exact = period, False
            for step, (count, first_at) in sorted(self._steps.items(), key=lambda s: s[1][1]):
                judged._judge(step, count, first_at)
            missing, longest, at = judged._missing, judged._longest, judged._at
            restarts = self._restarts + judged._restarts
        return MissingTicks(expected=self.recorded + missing, recorded=self.recorded,
                            missing=missing, longest_gap=longest * 1e-9, gap_at=at * 1e-9,
                            restarts=restarts, grid=described)


def missing_ticks(stamps: Sequence[int], grid: Optional[Grid]) -> MissingTicks:
    """
    Count the ticks missing between consecutive ``stamps`` (ns, in the order of the rows).

    :param grid: the node's rates, or None to take the smallest step between rows as the grid
        (every tick of it published).
    """
    counter = TickCounter(grid)
    for stamp in stamps:
        counter.add(stamp)
    return counter.result()
