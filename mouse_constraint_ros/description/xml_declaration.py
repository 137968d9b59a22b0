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
The XML declaration of a URDF: a version other than 1.0 is read as 1.0, with a note.

pybullet's URDFs begin ``<?xml version="0.0" ?>``, which libxml2 refuses ("Unsupported version
'0.0'"), though the rest is plain XML 1.0. ``as_xml_1_0`` gives the text with its declaration
saying 1.0, and ``version_note`` the line the node warns with.
"""

import re
from typing import Optional

# The declaration's version at the start of the text (after a byte order mark or blanks).
_VERSION = re.compile(r'^(\ufeff?\s*<\?xml\s+version\s*=\s*)(["\'])([^"\']*)\2')


def declared_version(text: str) -> Optional[str]:
    """Return the version the XML declaration of ``text`` states, or None without one."""
    match = _VERSION.match(text)
    return match.group(3) if match else None


def as_xml_1_0(text: str) -> str:
    """Return ``text`` with its XML declaration's version, if any and not 1.0, made 1.0."""
    return _VERSION.sub(r'\g<1>\g<2>1.0\g<2>', text, count=1)


def version_note(text: str) -> Optional[str]:
    """Return the warning for a declaration whose version is not 1.0, or None."""
    version = declared_version(text)
    if version is None or version == '1.0':
        return None
    return (f'robot_description declares XML version {version!r}: read as XML 1.0 (write '
            '<?xml version="1.0"?> to silence this)')
