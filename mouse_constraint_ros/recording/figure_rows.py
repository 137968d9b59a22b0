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
The rows a recording's figure draws: all of a short recording, evenly thinned in a long one.

A recording of any length keeps at most ``FIGURE_ROWS`` rows for its figure, so that its memory
stays flat however long it runs (the CSV has every row). Up to ``FIGURE_ROWS`` rows, every row
is kept: 20 s at 1 kHz, the figure is drawn from every tick. Past it, every second row is kept,
then every fourth, and so on: row n is kept while n is a multiple of the stride, which doubles
each time the rows kept reach ``FIGURE_ROWS``, so that the kept rows stay evenly spread over
the whole recording (a figure 1500 pixels wide shows no more). The rows that mark a grab are
kept besides, up to a quarter of ``FIGURE_ROWS``, and so are the rows whose applied wrench
differs from the row's before (a push's first tick and the tick after its last), up to another
quarter, and the last row always, so that the figure's end, its grabs, its pushes and its
title's anchor are the recording's own: a push of a few ticks in an hour's recording is drawn
from its first tick to its end.
"""

from typing import List, Optional, Tuple

from .rows import Row

# The most rows a figure is drawn from.
FIGURE_ROWS = 20_000


class FigureRows:
    """
    The rows kept for the figure of a recording, at most ``limit`` (see the module).

    :param limit: the most rows kept, at least 8.
    """

    def __init__(self, limit: int = FIGURE_ROWS) -> None:
        """Keep no row yet."""
        if limit < 8:
            raise ValueError(f'limit must be at least 8, got {limit}')
        self._limit = limit
        self._stride = 1
        # (index, row, whether kept as a grab's or a wrench change's row)
        self._kept: List[Tuple[int, Row, bool]] = []
        self._grabs = 0
        self._wrench_changes = 0
        self._wrench = (Row._field_defaults['wrench_force'], Row._field_defaults['wrench_torque'])
        self._last: Optional[Tuple[int, Row]] = None
        self.count = 0

    def add(self, row: Row) -> None:
        """Take the next row of the recording."""
        index = self.count
        self.count += 1
        self._last = (index, row)
        mark = row.grab is not None and self._grabs < self._limit // 4
        if mark:
            self._grabs += 1
        wrench = (row.wrench_force, row.wrench_torque)
        if wrench != self._wrench and self._wrench_changes < self._limit // 4:
            self._wrench_changes += 1
            mark = True
        self._wrench = wrench
        if not mark and index % self._stride:
            return
        self._kept.append((index, row, mark))
        if len(self._kept) >= self._limit:
            self._thin()

    def _thin(self) -> None:
        """Double the stride and drop the rows off it; the grabs' and the pushes' rows stay."""
        self._stride *= 2
        self._kept = [kept for kept in self._kept if kept[2] or kept[0] % self._stride == 0]

    @property
    def stride(self) -> int:
        """Return how many rows of the recording one kept row stands for (a power of 2)."""
        return self._stride

    def rows(self) -> List[Row]:
        """Return the rows kept, in order, the last row of the recording included."""
        rows = [row for _, row, _ in self._kept]
        if self._last is not None and (not self._kept or self._kept[-1][0] != self._last[0]):
            rows.append(self._last[1])
        return rows

    def __len__(self) -> int:
        """Return how many rows the recording had (not how many are kept)."""
        return self.count
