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
Ctrl-C, SIGTERM and SIGHUP in the node's first instants end it with exit 0, no traceback.

The node is started as its console script starts it (``setup.py``'s entry point), and each
signal is sent once the process has taken the signals (its ``SigCgt`` in ``/proc`` holds
SIGHUP, which Python alone does not catch), and at 0.1 and 0.3 s after: while it imports rclpy,
initializes and creates the node. Python's defaults gave a KeyboardInterrupt traceback and exit
-2, and death by SIGTERM (-15) and SIGHUP (-1). A second signal soon after the first, at a
running node, ends it with exit 0 too: Python's exit puts back the defaults that died by it.
"""

from pathlib import Path
import re
import signal
import subprocess
import sys
import time

import pytest

ROOT = Path(__file__).resolve().parent.parent
ENTRY = 'mouse_constraint_node = mouse_constraint_ros.node.console:main'
SCRIPT = ('import sys; from mouse_constraint_ros.node.console import main; sys.exit(main())')


def test_the_console_script_is_the_early_one():
    """setup.py installs the node's console script from ``node.console``."""
    assert f"'{ENTRY}'," in (ROOT / 'setup.py').read_text()


def caught(pid: int) -> int:
    """Return the mask of the signals the process ``pid`` has handlers for."""
    status = Path(f'/proc/{pid}/status').read_text()
    return int(re.search(r'^SigCgt:\s*([0-9a-f]+)$', status, re.M).group(1), 16)


@pytest.mark.system
@pytest.mark.parametrize('delay', [0.0, 0.1, 0.3])
@pytest.mark.parametrize('signum', [signal.SIGINT, signal.SIGTERM, signal.SIGHUP])
def test_a_signal_during_start_up_exits_0_without_a_traceback(signum, delay):
    """Exit 0 and nothing on stderr but the node's own lines, at each moment of start-up."""
    process = subprocess.Popen(
        [sys.executable, '-c', SCRIPT, '--ros-args', '-p', 'marker_rate_hz:=0.0', '-p',
         'diagnostics_rate_hz:=0.0'], stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    try:
        deadline = time.monotonic() + 20.0
        while not caught(process.pid) & (1 << (signal.SIGHUP - 1)):
            assert time.monotonic() < deadline and process.poll() is None
            time.sleep(0.001)
        time.sleep(delay)  # not a wait: the moment of start-up under test
        process.send_signal(signum)
        status = process.wait(timeout=20.0)
    finally:
        if process.poll() is None:
            process.kill()
    out, err = process.communicate()
    assert status == 0, err
    assert 'Traceback' not in err and 'KeyboardInterrupt' not in err
    assert all(line.startswith('[INFO]') for line in err.splitlines()), err
    if delay == 0.0:  # it came while the node was being imported: it never started
        assert 'Hz x' not in err, err


@pytest.mark.system
@pytest.mark.parametrize('gap', [0.01, 0.06, 0.12])
@pytest.mark.parametrize('signum', [signal.SIGINT, signal.SIGTERM])
def test_a_second_signal_soon_after_the_first_still_exits_0(signum, gap):
    """
    Two signals ``gap`` s apart at a running node: exit 0, as after one.

    The second comes while the node is torn down or while the interpreter exits after it, whose
    default handlers would end the process with the signal (-2, -15).
    """
    process = subprocess.Popen(
        [sys.executable, '-c', SCRIPT, '--ros-args', '-p', 'marker_rate_hz:=0.0', '-p',
         'diagnostics_rate_hz:=0.0'], stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    try:
        lines = []
        while not any('Hz x' in line for line in lines):  # its start line: it serves
            line = process.stderr.readline()
            assert line, ''.join(lines)
            lines.append(line)
        process.send_signal(signum)
        time.sleep(gap)  # not a wait: the gap between the signals under test
        process.send_signal(signum)
        status = process.wait(timeout=20.0)
    finally:
        if process.poll() is None:
            process.kill()
    err = ''.join(lines) + process.communicate()[1]
    assert status == 0, err
    assert 'Traceback' not in err, err
