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


"""``test_support.beside``, which make test runs the unit tier beside the alone tests with."""

import os
from pathlib import Path
import signal
import subprocess
import sys
import time

import pytest

ROOT = Path(__file__).resolve().parent.parent


def python(code: str) -> list:
    """Return the command that runs ``code`` in this interpreter."""
    return [sys.executable, '-c', code]


def beside(other: list, main: list, **options) -> subprocess.Popen:
    """Start ``main`` with ``other`` beside it; stdout and stderr piped."""
    return subprocess.Popen(
        [sys.executable, '-m', 'test_support.beside', '--beside', subprocess.list2cmdline(other),
         '--', *main], cwd=ROOT, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
        **options)


@pytest.mark.system
@pytest.mark.parametrize('main, other, status', [(0, 0, 0), (0, 3, 3), (2, 0, 2), (2, 3, 2)])
def test_the_status_is_the_main_command_s_or_else_the_other_s(main, other, status):
    process = beside(python(f'raise SystemExit({other})'), python(f'raise SystemExit({main})'))
    process.communicate(timeout=30.0)
    assert process.returncode == status


@pytest.mark.system
def test_the_other_s_output_follows_the_main_one_s():
    """The other prints at once, the main command later; the other's lines come last."""
    process = beside(python('import sys; print("other"); print("other err", file=sys.stderr)'),
                     python('import time; time.sleep(0.3); print("main")'))
    stdout, stderr = process.communicate(timeout=30.0)
    assert process.returncode == 0, stderr
    assert stdout.splitlines() == ['main', 'other', 'other err']


@pytest.mark.system
def test_ctrl_c_ends_both_commands_and_it_exits_130(tmp_path):
    """SIGINT to the terminal's process group: both end at once, and it exits 130."""
    ready = tmp_path / 'other.pid'
    wait_forever = 'import time; time.sleep(60)'
    process = beside(
        python(f'import os; open({str(ready)!r}, "w").write(str(os.getpid())); {wait_forever}'),
        python(f'print("main", flush=True); {wait_forever}'), start_new_session=True)
    try:
        assert process.stdout.readline() == 'main\n'
        deadline = time.monotonic() + 20.0
        while not ready.exists() or not ready.read_text():
            assert time.monotonic() < deadline, 'the other command did not start'
            time.sleep(0.05)
        other = int(ready.read_text())
        started = time.monotonic()
        os.killpg(process.pid, signal.SIGINT)
        process.communicate(timeout=20.0)
    finally:
        if process.poll() is None:
            os.killpg(process.pid, signal.SIGKILL)
    assert process.returncode == 130
    assert time.monotonic() - started < 10.0
    with pytest.raises(ProcessLookupError):
        os.kill(other, 0)
