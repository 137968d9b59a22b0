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
from typing import NamedTuple, Optional, Sequence


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


def missing_ticks(stamps: Sequence[int], grid: Optional[Grid]) -> MissingTicks:
    """
    Count the ticks missing between consecutive ``stamps`` (ns, in the order of the rows).

    :param grid: the node's rates, or None to take the smallest step between rows as the grid
        (every tick of it published).
    """
    steps = [b - a for a, b in zip(stamps, stamps[1:])]
    if grid is None:
        positive = [step for step in steps if step > 0]
        period = Fraction(min(positive)) if positive else Fraction(1)
        share, exact = Fraction(1), False
        described = (f'{1e9 / float(period):.6g} Hz, the smallest step between rows (the '
                     "node's rate_hz was not read)")
    else:
        period = Fraction(1_000_000_000) / Fraction(grid.rate_hz)
        share = (Fraction(1) if grid.publish_rate_hz == 0.0
                 else Fraction(grid.publish_rate_hz) / Fraction(grid.rate_hz))
        exact = True
        described = f'{grid.rate_hz:g} Hz' + (
            ', every tick published' if share == 1 else
            f', published at {grid.publish_rate_hz:g} Hz')
    missing, restarts, longest, at = 0, 0, 0, 0
    for index, step in enumerate(steps):
        if step == 0:
            continue  # the same tick again: a reset while paused publishes the state it leaves
        ticks = round(step / period) if step > 0 else 0
        # Stamps are t0 + floor(n P): two of them lie within 1 ns of k P apart.
        if ticks < 1 or (exact and abs(step - ticks * period) >= 1):
            restarts += 1
            continue
        missing += max(0, round(ticks * share) - 1)
        if step > longest:
            longest, at = step, stamps[index] - stamps[0]
    return MissingTicks(expected=len(stamps) + missing, recorded=len(stamps), missing=missing,
                        longest_gap=longest * 1e-9, gap_at=at * 1e-9, restarts=restarts,
                        grid=described)
