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
The CSV file of a recording, written row by row as the rows come: a crash keeps what came first.

``# `` lines first (what the recording is of), then the ``COLUMNS`` header, a line per row
(floats with every digit: repr), and ``# `` lines last (what the recording lacks, known at its
end). ``flush`` hands what was written to the operating system, so that a killed recorder
leaves every row written before its last flush.
"""

import csv
from pathlib import Path
from typing import Iterable, Sequence

from .rows import COLUMNS, Row


class CsvFile:
    """
    A recording's CSV, open for its rows.

    :param path: the file (created or truncated).
    :param metadata: lines written first, each after ``# ``.
    """

    def __init__(self, path: Path, metadata: Sequence[str] = ()) -> None:
        """Open the file and write the metadata and the header."""
        self._stream = open(path, 'w', newline='')
        for line in metadata:
            self._stream.write(f'# {line}\n')
        self._writer = csv.writer(self._stream)
        self._writer.writerow(COLUMNS)

    def write(self, rows: Iterable[Row]) -> None:
        """Write ``rows``, one line each."""
        self._writer.writerows(row.fields() for row in rows)

    def flush(self) -> None:
        """Hand what was written to the operating system."""
        self._stream.flush()

    def close(self, trailer: Sequence[str] = ()) -> None:
        """Write ``trailer``, each line after ``# ``, and close the file."""
        for line in trailer:
            self._stream.write(f'# {line}\n')
        self._stream.close()


def write_csv(path: Path, rows: Sequence[Row], metadata: Sequence[str] = (),
              trailer: Sequence[str] = ()) -> None:
    """Write a whole recording's CSV: ``metadata``, the header, ``rows``, ``trailer``."""
    csv_file = CsvFile(path, metadata)
    try:
        csv_file.write(rows)
    finally:
        csv_file.close(trailer)
