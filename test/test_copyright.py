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
Every source file carries the Apache-2.0 header, as ament_copyright checks (``colcon test``).

Where ament_copyright is installed (an apt ROS install: package.xml's test_depend) it runs as in
the ROS packages' own ``test_copyright.py``. It is not on PyPI, so its rule is also checked here
directly: the Python files it would read (not in folders starting with '.' or '_', not the
``setup.py`` beside ``package.xml``) open, after any shebang or coding line, with a comment
block holding a ``Copyright YEAR NAME`` line followed by the licence's header (the text the
Apache License's appendix gives for it, read from LICENSE); LICENSE is the licence and
CONTRIBUTING.md quotes its section 5 (ament_copyright reads both at a repository's root).
"""

import os
from pathlib import Path
import re

import pytest

ROOT = Path(__file__).resolve().parent.parent
# ament_copyright's pattern of a copyright line: years or year ranges, then the holder.
COPYRIGHT = re.compile(r'^copyright(?:\s+\(c\))?\s+\d{4}(?:-\d{4})?(?:,\s*\d{4}(?:-\d{4})?)*,?'
                       r'\s+\S.*$', re.IGNORECASE)


def normalized(text: str) -> str:
    """Return ``text`` with every run of white space one blank (ament's remove_formatting)."""
    return ' '.join(text.split())


def license_header() -> str:
    """Return the file header the Apache License's appendix gives, after its copyright line."""
    appendix = (ROOT / 'LICENSE').read_text().split('Copyright [yyyy] [name of copyright owner]')
    assert len(appendix) == 2, 'LICENSE is not the Apache License 2.0 with its appendix'
    return normalized(appendix[1])


def source_files() -> list:
    """Return the .py files ament_copyright reads under the package's root."""
    found = []
    for folder, folders, files in os.walk(ROOT):
        if 'AMENT_IGNORE' in folders + files:
            folders[:] = []
            continue
        folders[:] = sorted(name for name in folders if name[0] not in '._')
        for name in sorted(files):
            path = Path(folder) / name
            if name == 'setup.py' and (path.parent / 'package.xml').exists():
                continue
            if name.endswith('.py'):
                found.append(path)
    return found


def first_comment_block(text: str) -> str:
    """Return the first '#' comment block after shebang and coding lines, tokens removed."""
    lines = text.splitlines()
    while lines and lines[0].startswith('#') and (
            lines[0].startswith('#!') or 'coding:' in lines[0] or 'coding=' in lines[0]):
        lines.pop(0)
    while lines and not lines[0].strip():
        lines.pop(0)
    block = []
    for line in lines:
        if not line.startswith('#'):
            break
        block.append(line[2:])
    return '\n'.join(block)


def header_problem(path: Path, header: str):
    """Return what is missing from the header of ``path``, or None (an empty file is fine)."""
    text = path.read_text(encoding='utf-8')
    if not text:
        return None
    block = first_comment_block(text).splitlines()
    lines = [i for i, line in enumerate(block) if COPYRIGHT.match(line.strip())]
    if not lines:
        return 'could not find copyright notice'
    if header not in normalized('\n'.join(block[lines[-1] + 1:])):
        return 'no Apache-2.0 licence header after the copyright notice'
    return None


def test_licence_and_contributing_files():
    """LICENSE is the Apache License 2.0 (package.xml's licence); CONTRIBUTING.md its section 5."""
    text = (ROOT / 'LICENSE').read_text()
    assert text.lstrip().startswith('Apache License\n') and 'Version 2.0, January 2004' in text
    assert '<license>Apache-2.0</license>' in (ROOT / 'package.xml').read_text()
    section = text[text.index('5. Submission of Contributions.'):text.index('6. Trademarks.')]
    assert normalized(section) in normalized((ROOT / 'CONTRIBUTING.md').read_text())


def test_every_source_file_carries_the_licence_header():
    """ament_copyright's rule, checked directly: a copyright line and the Apache-2.0 header."""
    header = license_header()
    files = source_files()
    assert ROOT / 'launch' / 'mouse_constraint.launch.py' in files
    assert ROOT / 'setup.py' not in files
    problems = {str(path.relative_to(ROOT)): header_problem(path, header) for path in files}
    assert {path: problem for path, problem in problems.items() if problem} == {}


def test_ament_copyright():
    """ament_copyright itself, where it is installed, as the ROS packages run it."""
    main = pytest.importorskip(
        'ament_copyright.main', reason='ament_copyright is not installed (not on PyPI; '
        'an apt ROS install has it)').main
    previous = os.getcwd()
    os.chdir(ROOT)
    try:
        assert main(argv=['.', 'test']) == 0, 'Found errors'
    finally:
        os.chdir(previous)
