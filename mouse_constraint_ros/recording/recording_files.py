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
A recording's files, written while it records: the CSV row by row, the MCAP chunk by chunk.

``RecordingFiles`` takes each message as the recorder receives it. Until ``start`` (the first
pose came and the recorded node's parameters are known) it keeps them; then it writes what it
kept and, from there on, each message to the MCAP file and each row to the CSV as ``RowStream``
completes it, and hands both files' bytes to the operating system with the first row and then
every ``FLUSH_SECONDS``. A recorder killed with SIGKILL leaves the rows and the messages of all
but its last half second or so; ``close`` writes the rest, the CSV's trailer and the MCAP's
summary, and the figure is drawn from the rows it kept.

Its memory stays flat however long it records: the rows are written and let go, but for the
bounded, evenly thinned set the figure is drawn from (``FigureRows``); the ticks missing on the
node's grid are counted as the rows come (``TickCounter``); ``RowStream`` forgets the messages
and targets no row needs any more. The MCAP's summary (a chunk index per flush, some 200 bytes
each) is what grows, about 3 MB an hour.
"""

from pathlib import Path
import time
from typing import Callable, List, Mapping, Optional, Sequence, Tuple

from .csv_file import CsvFile
from .figure_rows import FigureRows
from .mcap_file import McapStream
from .missing_ticks import Grid, MissingTicks, TickCounter
from .received import Received
from .rows import Row, RowStream
from ..wire.cdr.stamped import decode_stamped, POSE, Refusal
from ..wire.interface import POSE_TOPIC

# How often the files' bytes go to the operating system (s).
FLUSH_SECONDS = 0.25


class RecordingFiles:
    """
    The CSV and, when asked, the MCAP file of one recording, written as it goes.

    :param csv_path: the CSV file.
    :param mcap_path: the MCAP file, or None for none.
    :param clock: seconds of a monotonic clock (when to flush).
    :param figure_rows: the rows the figure is drawn from, at most so many are kept.
    """

    def __init__(self, csv_path: Path, mcap_path: Optional[Path] = None, *,
                 clock: Callable[[], float] = time.monotonic,
                 figure_rows: Optional[FigureRows] = None) -> None:
        """Open nothing yet."""
        self._csv_path, self._mcap_path = csv_path, mcap_path
        self._clock = clock
        self.figure_rows = FigureRows() if figure_rows is None else figure_rows
        self.ticks: Optional[TickCounter] = None
        self._kept: List[Received] = []
        self._rows: Optional[RowStream] = None
        self._csv: Optional[CsvFile] = None
        self._mcap: Optional[McapStream] = None
        self._offered_qos: Mapping[str, str] = {}
        self._flushed = clock()
        self.frame_id: Optional[str] = None

    def start(self, parameters: Mapping[str, object], *, topic_names: Mapping[str, str],
              offered_qos: Mapping[str, str], metadata: Sequence[str] = ()) -> None:
        """
        Open the files and write what came so far: the recording starts.

        :param parameters: the recorded node's parameters at the start (``NodeView``).
        :param topic_names: the resolved topic of each recorded key.
        :param offered_qos: the publishers' QoS of each key, filled in as topics are seen.
        :param metadata: the CSV's first lines.
        """
        self._offered_qos = offered_qos
        self._rows = RowStream(parameters)
        grid = (Grid(parameters['rate_hz'], parameters.get('publish_rate_hz', 0.0))
                if 'rate_hz' in parameters else None)
        self.ticks = TickCounter(grid)
        self._csv = CsvFile(self._csv_path, metadata)
        if self._mcap_path is not None:
            self._mcap = McapStream(self._mcap_path, topic_names=topic_names)
        kept, self._kept = self._kept, []
        for message in kept:
            self.add(message)
        self.flush()

    def add(self, message: Received) -> None:
        """Take one message as received: kept until ``start``, then written."""
        if self._rows is None:
            self._kept.append(message)
            return
        if self.frame_id is None and message.topic == POSE_TOPIC:
            pose = decode_stamped(message.data, POSE)
            self.frame_id = None if isinstance(pose, Refusal) else pose.frame_id
        if self._mcap is not None:
            self._mcap.add(message, self._offered_qos.get(message.topic, ''))
        self._write(self._rows.add(message))
        self.flush_due()

    def flush_due(self) -> None:
        """Flush when ``FLUSH_SECONDS`` passed since the last flush (a paused node sends none)."""
        if self._clock() - self._flushed >= FLUSH_SECONDS:
            self.flush()

    def _write(self, rows: List[Row]) -> None:
        if rows:
            first = not self.figure_rows.count
            self._csv.write(rows, self._rows.joint_names)
            for row in rows:
                self.figure_rows.add(row)
                self.ticks.add(row.stamp_ns)
            if first:
                self.flush()  # the first rows at once: a recorder killed from here on keeps them

    def flush(self) -> None:
        """Hand both files' bytes to the operating system."""
        self._flushed = self._clock()
        if self._csv is not None:
            self._csv.flush()
        if self._mcap is not None:
            self._mcap.flush()

    def close(self) -> None:
        """Write the last rows, the CSV's trailer (the ticks missing) and the MCAP's summary."""
        if self._rows is None:
            return
        self._write(self._rows.finish())
        self._csv.close(self.missing().lines() if self.figure_rows.count else ())
        if self._mcap is not None:
            self._mcap.close(self._offered_qos)

    @property
    def joint_names(self) -> Tuple[str, ...]:
        """Return a robot's joints, the CSV's joint columns; none for a single body."""
        return () if self._rows is None else self._rows.joint_names

    def missing(self) -> Optional[MissingTicks]:
        """Return the ticks the rows so far lack on the node's grid; None before ``start``."""
        return None if self.ticks is None else self.ticks.result()

    def rows(self) -> List[Row]:
        """Return the rows the figure is drawn from (``FigureRows.rows``)."""
        return self.figure_rows.rows()

    def paths(self) -> List[Path]:
        """Return the files opened, the CSV first."""
        if self._rows is None:
            return []
        return [self._csv_path] + ([self._mcap_path] if self._mcap is not None else [])
