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

"""The Makefile's recipes, dry-run: what `make test` and `make view` run."""

from pathlib import Path
import subprocess

ROOT = Path(__file__).resolve().parent.parent


def dry_run(*arguments: str) -> str:
    """Return the commands ``make -n`` prints for ``arguments``."""
    result = subprocess.run(['make', '-n', '--no-print-directory', *arguments], cwd=ROOT,
                            capture_output=True, text=True, check=True)
    return result.stdout


def test_make_test_lists_every_skip_with_its_reason():
    """The pytest run lists each skip with its reason (-rs): what was not tested, and why."""
    commands = dry_run('test')
    assert 'pytest test/ -q -rs' in commands


def test_make_view_passes_its_options():
    """VIEW_ARGS reaches mouse_view: make view VIEW_ARGS='--port 8090'."""
    assert '.venv/bin/mouse_view --port 8090' in dry_run('view', 'VIEW_ARGS=--port 8090')
    assert dry_run('view').rstrip().endswith('.venv/bin/mouse_view')
