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

"""The package's folders are layers: a module imports only from its layer and those beneath."""

import ast
from pathlib import Path
import re

import pytest

PACKAGE = Path(__file__).resolve().parent.parent / 'mouse_constraint_ros'

ARCHITECTURE = PACKAGE.parent / 'docs' / 'architecture.md'


def layer_table() -> dict:
    """
    Return folder -> the places its modules may import from, read from architecture.md.

    The page's layer table is the one statement of the rule: each row's folder (backquoted,
    ending in /) may import from itself and from every backquoted place in its last column
    (``name/`` a folder, ``name/module.py`` one module), but a part after a semicolon that
    begins "never" or "not", which names what it may not.
    """
    section = ARCHITECTURE.read_text().split('## The layers', 1)[1].split('\n## ', 1)[0]
    allowed = {}
    for row in section.splitlines():
        cells = [cell.strip() for cell in row.strip().strip('|').split('|')]
        if len(cells) != 4 or not cells[1].startswith('`'):
            continue
        # What a row forbids ("never `marker/`") follows a semicolon: only the rest allows.
        allows = ';'.join(part for part in cells[3].split(';')
                          if not part.strip().startswith(('never', 'not ')))
        places = re.findall(r'`([a-z_]+)/(?:([a-z_]+\.py))?`', allows)
        for folder in re.findall(r'`([a-z_]+)/`', cells[1]):
            allowed[folder] = {folder} | {f'{name}/{module}' if module else name
                                          for name, module in places}
    return allowed


ALLOWED = layer_table()


def imported_places(path: Path):
    """Yield each place in the package a module imports: a folder, or a folder/module.py."""
    package = list(path.relative_to(PACKAGE).parent.parts)
    for node in ast.walk(ast.parse(path.read_text())):
        if not isinstance(node, ast.ImportFrom):
            continue
        if node.level:
            base = package[:len(package) - (node.level - 1)]
            parts = base + (node.module.split('.') if node.module else [])
        elif node.module and node.module.split('.')[0] == PACKAGE.name:
            parts = node.module.split('.')[1:]
        else:
            continue
        if parts:
            yield parts[0], '/'.join(parts[:2]) + '.py'


def modules():
    """Return every module of the package in a folder, as paths."""
    return sorted(p for p in PACKAGE.glob('*/**/*.py'))


def test_every_folder_of_the_package_is_a_layer():
    """Each subpackage has its row in ALLOWED, and no module lies outside the folders."""
    assert {p.parent.name for p in PACKAGE.glob('*/__init__.py')} == set(ALLOWED)
    assert [p.name for p in PACKAGE.glob('*.py')] == ['__init__.py']


def test_the_web_view_and_the_rviz_marker_import_neither_each_other():
    """What the two tools share lies beneath both (pointer/), never in one of them."""
    assert not any(place.startswith('marker') for place in ALLOWED['view'])
    assert not any(place.startswith('view') for place in ALLOWED['marker'])


@pytest.mark.parametrize('path', modules(), ids=lambda p: str(p.relative_to(PACKAGE)))
def test_a_module_imports_only_from_its_layer_and_those_beneath(path):
    """``from ..x import`` and ``from mouse_constraint_ros.x import`` name allowed folders."""
    allowed = ALLOWED[path.relative_to(PACKAGE).parts[0]]
    wrong = [module for folder, module in imported_places(path)
             if folder not in allowed and module not in allowed]
    assert not wrong, wrong
