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
How long a ``robot_description`` may be: told without the parser, so the node asks it at once.

The text is measured in bytes of UTF-8, of which there are at least as many as characters: a
text longer than the limit in characters is refused (by that count) before it is encoded.
"""

from typing import Optional

# The longest robot_description read (bytes of UTF-8): a single link's URDF is a few kB, a
# whole robot's a few hundred.
MAX_DESCRIPTION_BYTES = 4 * 1024 * 1024


def oversized(text: str) -> Optional[str]:
    """Return why ``text`` is too long to be read as a URDF, or None."""
    size = len(text)
    if size <= MAX_DESCRIPTION_BYTES:
        size = len(text.encode('utf-8', 'replace'))
    if size <= MAX_DESCRIPTION_BYTES:
        return None
    return (f'robot_description is {size / 2 ** 20:.1f} MiB, over the limit of '
            f'{MAX_DESCRIPTION_BYTES / 2 ** 20:g} MiB: give the URDF of the body, its meshes in '
            'files')
