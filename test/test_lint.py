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
The code follows ament's flake8 conventions: 99 columns, single quotes, pep257.

Flake8 runs in this process, one job, over three parts of the tree of about equal size: each
file is checked on its own, so the parts are checked in parallel when the tests are spread over
workers, and no process is started.
"""

from pathlib import Path

from flake8.main.application import Application
import pytest

ROOT = Path(__file__).resolve().parent.parent
PARTS = [('mouse_constraint_ros',), ('test',),
         ('test_support', 'bench', 'demo', 'launch', 'setup.py')]


@pytest.mark.parametrize('names', PARTS, ids='+'.join)
def test_flake8(names, capsys, monkeypatch):
    """Flake8 with the repository's ament-mirroring configuration reports nothing."""
    paths = [str(ROOT / name) for name in names if (ROOT / name).exists()]
    monkeypatch.chdir(ROOT)
    application = Application()
    application.run(['--config', str(ROOT / '.flake8'), '--jobs', '1', *paths])
    output = capsys.readouterr()
    assert application.result_count == 0, output.out + output.err
    assert not application.catastrophic_failure, output.out + output.err
