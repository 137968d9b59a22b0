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
The files a recording writes, and the check before recording that they can be written.

``PREFIX.csv`` and ``PREFIX.png``, and ``PREFIX.mcap`` with ``--mcap``. An unwritable prefix
must fail at once, not after the recording: ``check_writable`` tries what writing will do.
"""

from pathlib import Path
from typing import List, Sequence


def output_paths(prefix: Path, mcap: bool) -> List[Path]:
    """Return the files a recording writes: PREFIX.csv, PREFIX.png and with ``mcap`` .mcap."""
    suffixes = ('.csv', '.png', '.mcap') if mcap else ('.csv', '.png')
    return [prefix.with_name(prefix.name + suffix) for suffix in suffixes]


def check_writable(paths: Sequence[Path]) -> None:
    """
    Make sure each of ``paths`` can be written, leaving the file system as it was.

    It does what writing does: creates the missing directories and opens each file for
    appending (creating it, truncating nothing), then removes what it created. Trying is the
    only reliable test: permissions say nothing for root, nor about /proc or a read-only mount.

    :raises OSError: the first failure, its ``filename`` the path that failed.
    """
    created: List[Path] = []
    try:
        for path in paths:
            missing = [d for d in (path.parent, *path.parent.parents) if not d.exists()]
            for directory in reversed(missing):
                directory.mkdir()
                created.append(directory)
            existed = path.exists()
            with open(path, 'ab'):
                pass
            if not existed:
                created.append(path)
    finally:
        for path in reversed(created):
            try:
                path.rmdir() if path.is_dir() else path.unlink()
            except OSError:
                pass


def describe_os_error(error: OSError) -> str:
    """Return 'PATH: reason' for an error of the file system, on one line."""
    reason = error.strerror or str(error)
    return f'{error.filename}: {reason}' if error.filename else reason
