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

``# `` lines first (what the recording is of), then the header, a line per row (floats with
every digit: repr), and ``# `` lines last (what the recording lacks, known at its end). The
header is ``COLUMNS``, and for a robot its joints' columns after them (``joints``): it is written
with the first rows, whose joints name them. ``flush`` hands what was written to the operating
system, so that a killed recorder leaves every row written before its last flush.
"""

import csv
from pathlib import Path
from typing import Iterable, Optional, Sequence, Tuple

from .joints import joint_columns, joint_fields
from .rows import COLUMNS, Row


class CsvFile:
    """
    A recording's CSV, open for its rows.

    :param path: the file (created or truncated).
    :param metadata: lines written first, each after ``# ``.
    """

    def __init__(self, path: Path, metadata: Sequence[str] = ()) -> None:
        """Open the file and write the metadata."""
        self._stream = open(path, 'w', newline='')
        for line in metadata:
            self._stream.write(f'# {line}\n')
        self._writer = csv.writer(self._stream)
        # The joints of the header written, None before it is.
        self._joints: Optional[Tuple[str, ...]] = None

    def _header(self, joint_names: Sequence[str]) -> None:
        self._joints = tuple(joint_names)
        self._writer.writerow(COLUMNS + joint_columns(self._joints))

    def write(self, rows: Iterable[Row], joint_names: Sequence[str] = ()) -> None:
        """
        Write ``rows``, one line each, after the header when they are the first.

        :param joint_names: a robot's joints, named in the header when it is written with these
            rows (``RowStream.joint_names``); none for a single body.
        """
        if self._joints is None:
            self._header(joint_names)
        joints = self._joints
        if joints:
            self._writer.writerows(row.fields() + joint_fields(row.joints, joints)
                                   for row in rows)
        else:
            self._writer.writerows(row.fields() for row in rows)

    def flush(self) -> None:
        """Hand what was written to the operating system."""
        self._stream.flush()

    def close(self, trailer: Sequence[str] = ()) -> None:
        """Write ``trailer``, each line after ``# ``, and close the file (with its header)."""
        if self._joints is None:
            self._header(())
        for line in trailer:
            self._stream.write(f'# {line}\n')
        self._stream.close()


def write_csv(path: Path, rows: Sequence[Row], metadata: Sequence[str] = (),
              trailer: Sequence[str] = (), joint_names: Sequence[str] = ()) -> None:
    """Write a whole recording's CSV: ``metadata``, the header, ``rows``, ``trailer``."""
    csv_file = CsvFile(path, metadata)
    try:
        csv_file.write(rows, joint_names)
    finally:
        csv_file.close(trailer)
