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
A URDF file as a parameters file: ``robot_description`` holding its text.

What the launch file does with ``urdf:=path``, for a node started without launch (``make run
URDF=config/tool.urdf``): ``python -m mouse_constraint_ros.cli.urdf_params FILE OUT`` writes
``OUT`` with the file's text as one YAML string, which ``--params-file OUT`` gives the node
whole. ``-p robot_description:=...`` cannot carry it: rcl reads a ``-p`` value as YAML, and
XML holds ``: `` and quotes.
"""

import json
from pathlib import Path
import sys
from typing import List, Optional


def params_text(urdf: str, path: str = '') -> str:
    """
    Return a parameters file for every node setting ``robot_description`` to ``urdf``.

    :param path: the file ``urdf`` was read from (``robot_description_file``: relative mesh
        paths resolve against its directory); empty: none.
    """
    # A JSON string is a YAML double-quoted scalar: every character survives.
    text = f'/**:\n  ros__parameters:\n    robot_description: {json.dumps(urdf)}\n'
    if path:
        text += f'    robot_description_file: {json.dumps(path)}\n'
    return text


def main(args: Optional[List[str]] = None) -> int:
    """Write the parameters file of a URDF file; exit 2 with one line when it cannot."""
    args = sys.argv[1:] if args is None else args
    if len(args) != 2:
        print('usage: python -m mouse_constraint_ros.cli.urdf_params URDF_FILE PARAMS_FILE',
              file=sys.stderr)
        return 2
    source, target = (Path(a) for a in args)
    try:
        Path(target).write_text(params_text(source.read_text(), str(source.resolve())))
    except (OSError, UnicodeDecodeError) as error:
        print(f'urdf_params: {error}', file=sys.stderr)
        return 2
    return 0


if __name__ == '__main__':
    sys.exit(main())
