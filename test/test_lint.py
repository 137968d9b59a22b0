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

"""The code follows ament's flake8 conventions: 99 columns, single quotes, pep257."""

from pathlib import Path
import subprocess
import sys

ROOT = Path(__file__).resolve().parent.parent


def test_flake8():
    """Flake8 with the repository's ament-mirroring configuration reports nothing."""
    names = ('mouse_constraint_ros', 'test', 'test_support', 'bench', 'demo', 'launch', 'setup.py')
    paths = [str(ROOT / name) for name in names if (ROOT / name).exists()]
    result = subprocess.run([sys.executable, '-m', 'flake8', '--config', str(ROOT / '.flake8'),
                             *paths], capture_output=True, text=True, cwd=ROOT)
    assert result.returncode == 0, result.stdout + result.stderr
