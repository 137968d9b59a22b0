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
A URDF read from a file: its mesh paths relative to the file made absolute.

CAD exporters and many robot repositories name meshes relative to the URDF
(``meshes/link_1.stl``). ``robot_description`` is text with no directory, so such a path
resolves only when the node is told which file the text came from (``robot_description_file``,
which ``urdf:=``, ``make run URDF=`` and the harness's ``urdf_path=`` set): each ``<mesh
filename>`` that is neither ``package://``, ``file://`` nor absolute is then joined to the
file's directory, before anything reads the text.
"""

import os
import re

# A <mesh ...> element's filename attribute, in either quotes.
_MESH_FILENAME = re.compile(r'(<mesh\b[^>]*?\bfilename\s*=\s*)(["\'])(.*?)\2', re.DOTALL)
# The most a URDF file may hold to be read (characters), as ``text_size`` bounds the text.
MAX_FILE_BYTES = 4 * 2 ** 20


def absolute_meshes(text: str, directory: str) -> str:
    """Return ``text`` with each relative mesh filename joined to ``directory``."""
    def absolute(match: 're.Match') -> str:
        name = match.group(3)
        if not name or '://' in name or os.path.isabs(name):
            return match.group(0)
        path = os.path.normpath(os.path.join(directory, name))
        return f'{match.group(1)}{match.group(2)}{path}{match.group(2)}'
    return _MESH_FILENAME.sub(absolute, text)


def described(text: str, path: str) -> str:
    """
    Return the URDF the node works with: ``text``, or the file's when ``text`` is empty.

    :param text: the ``robot_description`` parameter.
    :param path: the ``robot_description_file`` parameter: the file the text came from
        (its directory resolves relative mesh paths); empty: none.
    :raises ValueError: one line, when the file cannot be read.
    """
    if not isinstance(path, str):
        raise ValueError(f'robot_description_file must be a path, got {path!r}')
    if not path:
        return text
    path = os.path.abspath(os.path.expanduser(path))
    if not text:
        try:
            if os.path.getsize(path) > MAX_FILE_BYTES:
                raise ValueError(f'robot_description_file {path!r} is over '
                                 f'{MAX_FILE_BYTES // 2 ** 20} MiB: not a URDF to read whole')
            with open(path, encoding='utf-8', errors='replace') as file:
                text = file.read()
        except OSError as error:
            raise ValueError(f'robot_description_file {path!r} cannot be read: '
                             f'{error.strerror or error}') from None
    return absolute_meshes(text, os.path.dirname(path))
