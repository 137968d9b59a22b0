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
This package's own share directory, found from where its code is, without the ament index.

The shipped examples name their meshes ``package://mouse_constraint_ros/config/...``. Where the
ament index does not list the package (a terminal with no workspace sourced, the venv outside
``make run``), the package still finds its own files: the directory that holds its
``package.xml`` and ``config/``, which is the source tree (a checkout, the editable install of
the venv) or ``share/mouse_constraint_ros`` of the prefix it is installed in (colcon's, or a
venv's ``data_files``).
"""

from pathlib import Path
from typing import Optional

PACKAGE = 'mouse_constraint_ros'


def own_share() -> Optional[str]:
    """Return the directory of this package's ``package.xml`` and ``config/``, or None."""
    code = Path(__file__).resolve().parent.parent  # the folder of the package's modules
    for folder in code.parents:
        for share in (folder, folder / 'share' / PACKAGE):
            manifest = share / 'package.xml'
            if (share / 'config').is_dir() and manifest.is_file() and \
                    f'<name>{PACKAGE}</name>' in manifest.read_text(errors='replace'):
                return str(share)
    return None
