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
Each console script is named where a newcomer reads about its folder: the folder's docstring.

setup.py's ``console_scripts`` are the list; a script's entry point lies in a folder of the
package (``cli/``, ``view/``, ...), whose ``__init__.py`` says what the folder holds and so
names each of its scripts. Read from the source (``ast``), nothing imported.
"""

import ast
from pathlib import Path
import re

ROOT = Path(__file__).resolve().parent.parent


def console_scripts() -> dict:
    """Return script -> its entry point's module, from setup.py's ``console_scripts``."""
    tree = ast.parse((ROOT / 'setup.py').read_text())
    entries = next(node for node in ast.walk(tree) if isinstance(node, ast.Dict) and any(
        isinstance(key, ast.Constant) and key.value == 'console_scripts' for key in node.keys))
    [lines] = [value for key, value in zip(entries.keys, entries.values)
               if key.value == 'console_scripts']
    scripts = {}
    for line in ast.literal_eval(lines):
        name, target = (part.strip() for part in line.split('='))
        scripts[name] = target.split(':')[0]
    return scripts


def test_every_console_script_is_named_in_its_folder_s_docstring():
    """``mouse_ctl`` in ``cli/``'s, ``mouse_view`` in ``view/``'s, and so on for each script."""
    scripts = console_scripts()
    assert len(scripts) >= 7
    unnamed = []
    for name, module in sorted(scripts.items()):
        folder = ROOT.joinpath(*module.split('.')[:2])
        docstring = ast.get_docstring(ast.parse((folder / '__init__.py').read_text())) or ''
        if not re.search(rf'``{name}``', docstring):
            unnamed.append(f'{name} ({module}): not in {folder.relative_to(ROOT)}/__init__.py')
    assert not unnamed, '\n'.join(unnamed)
