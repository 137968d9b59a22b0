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
The Makefile's recipes, dry-run: what `make test`, `make run` and `make view` run.

Ctrl-C of `make run` in a terminal: the recipe `make -n run` prints runs in a pseudo-terminal
under a stand-in for make (the recipe's shell, its process dying of SIGINT as make does),
and the terminal's Ctrl-C and Ctrl-Z are typed into it.
"""

import contextlib
import os
from pathlib import Path
import pty
import re
import select
import signal
import subprocess
import sys
import time
from xml.etree import ElementTree

import pytest

ROOT = Path(__file__).resolve().parent.parent


def dry_run(*arguments: str) -> str:
    """Return the commands ``make -n`` prints for ``arguments``."""
    result = subprocess.run(['make', '-n', '--no-print-directory', *arguments], cwd=ROOT,
                            capture_output=True, text=True, check=True)
    return result.stdout


@pytest.mark.system
def test_make_test_lists_every_skip_with_its_reason():
    """The pytest run lists each skip with its reason (-rs): what was not tested, and why."""
    commands = dry_run('test')
    assert 'pytest test/ -q -rs' in commands


# Collects the tests and prints each one's markers, one test a line: 'nodeid marker marker ...'.
MARKERS_OF_EACH_TEST = (
    'import sys, pytest\n'
    'class Print:\n'
    '    def pytest_collection_finish(self, session):\n'
    '        for item in session.items:\n'
    "            print('MARKS', item.nodeid, *sorted({m.name for m in item.iter_markers()}))\n"
    "sys.exit(pytest.main(['test/', '-q', '--collect-only', '-p', 'no:cacheprovider'],\n"
    '                     plugins=[Print()]))\n')


@pytest.mark.system
def test_make_test_runs_every_test_once():
    """
    The marker expressions of make test's pytest runs share out every test, none twice.

    With chromium there (any executable stands in for it); without it, the last run leaves the
    browser tests out, and make says so.
    """
    def expressions(commands: str) -> list:
        return [''.join(match) for match in re.findall(
            r"""pytest test/ -q -rs -m (?:'([^']*)'|"([^"]*)"|(\w+))""", commands)]
    without = dry_run('test', 'CHROMIUM=/nonexistent/chromium')
    assert expressions(without)[-1] == 'alone and not browser'
    assert "echo 'browser tier skipped: no /nonexistent/chromium" in without
    with_browser = expressions(dry_run('test', f'CHROMIUM={sys.executable}'))
    assert len(with_browser) == 3 and with_browser[-1] == 'alone or browser'
    listing = subprocess.run([sys.executable, '-c', MARKERS_OF_EACH_TEST], cwd=ROOT,
                             capture_output=True, text=True, timeout=120)
    assert listing.returncode == 0, listing.stdout + listing.stderr
    tests = [line.split()[1:] for line in listing.stdout.splitlines()
             if line.startswith('MARKS ')]
    assert len(tests) > 1000
    for nodeid, *markers in tests:
        names = {name: name in markers for name in
                 ('unit', 'ros', 'system', 'browser', 'alone')}
        runs = [e for e in with_browser if eval(e, {}, names)]  # and, or, not of marker names
        assert len(runs) == 1, (nodeid, markers, runs)


@pytest.mark.system
def test_make_view_passes_its_options():
    """VIEW_ARGS reaches mouse_view: make view VIEW_ARGS='--port 8090'."""
    assert '.venv/bin/mouse_view --port 8090' in dry_run('view', 'VIEW_ARGS=--port 8090')
    assert "echo '.venv/bin/mouse_view '" in dry_run('view')


# What the stand-ins print (a shell's expansion; make's recipe doubles the $).
PRINTED = 'profile [$FASTRTPS_DEFAULT_PROFILES_FILE]'


def _stand_in_venv(folder: Path) -> Path:
    """Return a venv whose node and view print the profile they were started with."""
    bin_folder = folder / 'bin'
    bin_folder.mkdir(parents=True)
    (bin_folder / 'python').symlink_to(sys.executable)
    for name in ('mouse_constraint_node', 'mouse_view'):
        (bin_folder / name).write_text(f'#!/bin/sh\necho "{PRINTED}"\n')
        (bin_folder / name).chmod(0o755)
    (folder / '.stamp').touch()  # newer than the requirements: nothing to install
    return folder


@pytest.mark.system
@pytest.mark.parametrize('target, own', [('run', None), ('view', None),
                                         ('run', '/etc/my_profiles.xml')])
def test_make_run_and_view_start_with_the_discovery_profile_unless_one_is_named(
        target, own, tmp_path):
    """
    Their command gets config/fast_discovery.xml, or the environment's own; other targets none.

    The profile is Fast DDS's: participants announce themselves every 0.25 s, so a command
    started beside the node finds it within 0.4 s, not up to 3 s (the file says why). The
    recipes run for real, with a venv whose commands print the variable.
    """
    environment = {k: v for k, v in os.environ.items() if k != 'FASTRTPS_DEFAULT_PROFILES_FILE'}
    if own is not None:
        environment['FASTRTPS_DEFAULT_PROFILES_FILE'] = own
    venv = _stand_in_venv(tmp_path / 'venv')
    result = subprocess.run(['make', '--no-print-directory', target, f'VENV={venv}'], cwd=ROOT,
                            env=environment, stdin=subprocess.DEVNULL, capture_output=True,
                            text=True, timeout=60)
    assert result.returncode == 0, result.stderr
    profile = ROOT / 'config' / 'fast_discovery.xml'
    assert f'profile [{profile if own is None else own}]' in result.stdout
    other = subprocess.run(['make', '--no-print-directory', '-f', 'Makefile', '-f', '-', 'other'],
                           cwd=ROOT, env=environment, capture_output=True, text=True,
                           input=f'other:\n\t@echo "{PRINTED.replace("$", "$$")}"\n',
                           timeout=60)
    assert f'profile [{own or ""}]' in other.stdout, other.stderr
    period = ElementTree.parse(profile).find('.//{*}discovery_config/{*}leaseAnnouncement')
    assert (int(period.findtext('{*}sec')), int(period.findtext('{*}nanosec'))) == (0, 250000000)


# make, as far as a signal goes: it runs the recipe line with its shell and dies of SIGINT.
MAKE_STAND_IN = ('import signal, subprocess, sys\n'
                 'signal.signal(signal.SIGINT, signal.SIG_DFL)\n'
                 "sys.exit(subprocess.call(['/bin/bash', '-c', sys.argv[1]]))\n")


def recipe(target: str) -> str:
    """Return the line of ``target``'s recipe that runs its command (the last)."""
    return dry_run(target).rstrip().splitlines()[-1]


@pytest.mark.system
def test_run_and_view_run_their_command_in_the_foreground():
    """Both recipes give the terminal to their command alone (job control), and say it first."""
    for target, command in (('run', '.venv/bin/mouse_constraint_node --ros-args --params-file '
                                    'config/params.yaml'), ('view', '.venv/bin/mouse_view')):
        line = recipe(target)
        assert line.startswith('if [ -t 0 ]; then set -m; ' + command), line
        assert f"echo '{command}" in dry_run(target)


def read_until(fd: int, text: bytes, timeout: float = 30.0) -> bytes:
    """Return what the pseudo-terminal printed until ``text`` (or the timeout)."""
    out, deadline = b'', time.monotonic() + timeout
    while text not in out and time.monotonic() < deadline:
        if select.select([fd], [], [], 0.1)[0]:
            try:
                out += os.read(fd, 4096)
            except OSError:
                break
    return out


@contextlib.contextmanager
def run_in_a_terminal(target: str):
    """Yield (pid, fd) of ``target``'s recipe under make's stand-in on a new terminal."""
    pid, fd = pty.fork()
    if pid == 0:  # the child: make's stand-in, in the repository, on the terminal
        os.chdir(ROOT)
        os.execv(sys.executable, [sys.executable, '-c', MAKE_STAND_IN, recipe(target)])
    try:
        started = read_until(fd, b'Hz x')
        assert b'Hz x' in started, started
        yield pid, fd
    finally:
        kill_session(pid)
        os.close(fd)


def wait(pid: int, options: int = 0, timeout: float = 20.0):
    """Return the wait status of ``pid`` once it changed (options: os.WUNTRACED), or None."""
    deadline = time.monotonic() + timeout
    while time.monotonic() < deadline:
        done, status = os.waitpid(pid, options | os.WNOHANG)
        if done:
            return status
        time.sleep(0.02)
    return None


@pytest.mark.system
def test_ctrl_c_of_make_run_in_a_terminal_exits_0():
    """The node alone gets Ctrl-C and exits 0, and so does make (it died of SIGINT: 130)."""
    with run_in_a_terminal('run') as (pid, fd):
        os.write(fd, b'\x03')
        status = wait(pid)
        assert status is not None and os.waitstatus_to_exitcode(status) == 0, status


@pytest.mark.system
def test_ctrl_z_of_make_run_stops_it_until_fg():
    """Ctrl-Z stops the node, then make; going on (fg), Ctrl-C ends both with 0."""
    with run_in_a_terminal('run') as (pid, fd):
        os.write(fd, b'\x1a')
        status = wait(pid, os.WUNTRACED)
        assert status is not None and os.WIFSTOPPED(status)
        os.killpg(pid, signal.SIGCONT)  # fg: make goes on, and gives the node the terminal
        assert wait_until(lambda: foreground_runs(fd, pid)), 'the node not in the foreground'
        os.write(fd, b'\x03')
        status = wait(pid)
        assert status is not None and os.waitstatus_to_exitcode(status) == 0, status


def wait_until(condition, timeout: float = 20.0) -> bool:
    """Return whether ``condition()`` held within ``timeout`` s."""
    deadline = time.monotonic() + timeout
    while not condition():
        if time.monotonic() > deadline:
            return False
        time.sleep(0.02)
    return True


def processes_of(session: int):
    """Yield (pid, state, process group) of each process of the session ``session``."""
    for stat in Path('/proc').glob('[0-9]*/stat'):
        try:
            fields = stat.read_text().rsplit(')', 1)[1].split()
        except OSError:
            continue
        if int(fields[3]) == session:  # the session id, after state, ppid and pgrp
            yield int(stat.parent.name), fields[0], int(fields[2])


def foreground_runs(fd: int, session: int) -> bool:
    """Return whether a group other than make's has the terminal ``fd``, none of it stopped."""
    group = os.tcgetpgrp(fd)
    states = [state for _, state, pgrp in processes_of(session) if pgrp == group]
    return group != session and bool(states) and not any(s in 'Tt' for s in states)


def kill_session(session: int) -> None:
    """Kill every process of the terminal's session ``session``, whatever its process group."""
    for pid, _, _ in list(processes_of(session)):
        try:
            os.kill(pid, signal.SIGKILL)
        except ProcessLookupError:
            pass


def recipe_lines() -> list:
    """Return (target, line) for every recipe line of the Makefile, continuations joined."""
    lines, target, pending = [], None, ''
    for line in (ROOT / 'Makefile').read_text().splitlines():
        if pending or line.startswith('\t'):
            pending += line.strip().removesuffix('\\') + ' '
            if not line.endswith('\\'):
                lines.append((target, pending.strip()))
                pending = ''
        elif re.match(r'^[^#\s=]+(?:\s[^#=]*)?:(?!=)', line):
            target = line.split(':', 1)[0]
    return lines


def test_make_echoes_every_command_it_runs():
    """
    A recipe line is echoed by make, or prints itself: nothing runs unseen.

    A silent line (``@``) only prints a message, or runs the command the line before printed
    (``make run`` and ``make view``: the command, then the same in its job-control wrapper).
    """
    lines = recipe_lines()
    assert len(lines) > 15
    unseen = []
    for (target, line), (_, before) in zip(lines, [(None, '')] + lines):
        if not line.startswith('@') or line.startswith('@echo '):
            continue
        printed = re.fullmatch(r"@echo '(.*)'", before)
        if not (printed and line.startswith('@$(call foreground,' + printed.group(1).rstrip())):
            unseen.append(f'{target}: {line}')
    assert not unseen


@pytest.mark.system
def test_the_venv_install_shows_its_progress():
    """The venv install shows pip's and uv's progress: make venv waits there."""
    installs = [line for line in dry_run('-B', 'venv').splitlines() if ' install ' in line]
    assert len(installs) >= 3
    for line in installs:
        assert not re.search(r'\s(?:-q+|--quiet)\b', line), line


def test_make_run_takes_a_urdf_and_the_parameters_beside_it():
    """URDF=config/tool.urdf: its text as robot_description, then config/tool.yaml, in order."""
    commands = dry_run('run', 'URDF=config/tool.urdf')
    assert ('.venv/bin/python -m mouse_constraint_ros.cli.urdf_params config/tool.urdf '
            '.venv/robot_description.yaml') in commands
    assert ('.venv/bin/mouse_constraint_node --ros-args --params-file config/params.yaml '
            '--params-file .venv/robot_description.yaml --params-file config/tool.yaml'
            ) in commands
    assert 'urdf_params' not in dry_run('run')


@pytest.mark.system
def test_make_run_starts_the_shipped_mug_with_its_package_mesh():
    """
    The shipped mug's package:// mesh resolves in .venv: ``make run URDF=config/mug.urdf``.

    The mug's mesh is named by package://, which the ament prefix of the source tree in .venv
    resolves; the node starts with the link and the mass its density gives. SIGINT to make's
    process group (no terminal: make dies of it, as the Makefile says) ends it without a
    traceback; Ctrl-C in a terminal is ``test_ctrl_c_of_make_run_in_a_terminal_exits_0``'s.
    """
    process = subprocess.Popen(['make', '--no-print-directory', 'run', 'URDF=config/mug.urdf'],
                               cwd=ROOT, stdin=subprocess.DEVNULL, stdout=subprocess.PIPE,
                               stderr=subprocess.STDOUT, start_new_session=True)
    try:
        out, deadline = b'', time.monotonic() + 60.0
        while b"link 'mug'" not in out and time.monotonic() < deadline:
            if select.select([process.stdout], [], [], 0.1)[0]:
                chunk = os.read(process.stdout.fileno(), 4096)
                if not chunk:
                    break
                out += chunk
        assert b"link 'mug' (COM" in out and b'mass 0.390176 kg' in out, out
    finally:
        os.killpg(process.pid, signal.SIGINT)
        rest, _ = process.communicate(timeout=30)
    assert process.returncode == -signal.SIGINT, out + rest
    assert b'Traceback' not in out + rest, out + rest


# A stand-in for the venv's python: ``-m pytest`` prints a closing line and writes a JUnit
# report, failing the tier whose marker expression is FAILING; anything else runs for real.
FAKE_PYTEST = """#!{python}
import os, sys
arguments = sys.argv[1:]
if arguments[:2] != ['-m', 'pytest']:
    os.execv(sys.executable, [sys.executable, *arguments])
markers = arguments[arguments.index('-m', 2) + 1]
report = next((a.split('=', 1)[1] for a in arguments if a.startswith('--junitxml=')), None)
failing = markers == {failing!r}
cases = '<testcase classname="test.test_fake" name="test_fine" time="0.1"/>'
if failing:
    cases += ('<testcase classname="test.test_fake" name="test_broken" time="0.1">'
              '<failure message="assert 3 &lt;= 2"/></testcase>')
with open(report or os.devnull, 'w') as out:
    out.write('<testsuites><testsuite name="pytest" tests="%d" failures="%d" errors="0" '
              'skipped="0" time="0.2">%s</testsuite></testsuites>'
              % (1 + failing, int(failing), cases))
print('ran tier', markers)
print('1 failed, 1 passed in 0.20s' if failing else '1 passed in 0.10s')
sys.exit(1 if failing else 0)
"""


@pytest.mark.system
@pytest.mark.parametrize('failing', ['not system and not browser', None])
def test_make_test_runs_every_tier_and_sums_them_up_at_the_end(failing, tmp_path):
    """
    A failed tier does not stop the others: each runs, the last lines name what failed.

    The recipe runs for real with a venv whose pytest fails the unit and ros tier (or none):
    the system and the alone tiers still run, then each tier's totals and the failed test are
    printed, and make exits non-zero; with none failing it exits 0.
    """
    venv = tmp_path / 'venv'
    (venv / 'bin').mkdir(parents=True)
    python = venv / 'bin' / 'python'
    python.write_text(FAKE_PYTEST.format(python=sys.executable, failing=failing))
    python.chmod(0o755)
    (venv / '.stamp').touch()  # newer than the requirements: nothing to install
    result = subprocess.run(['make', '--no-print-directory', 'test', f'VENV={venv}',
                             'CHROMIUM=/nonexistent/chromium'], cwd=ROOT,
                            stdin=subprocess.DEVNULL, capture_output=True, text=True,
                            timeout=120)
    out = result.stdout
    tiers = re.findall(r'^ran tier (.*)$', out, re.MULTILINE)
    assert tiers == ['not system and not browser', 'system and not alone',
                     'alone and not browser'], out + result.stderr
    summary = out[out.index('make test, every tier:'):].splitlines()
    if failing is None:
        assert result.returncode == 0, out + result.stderr
        assert summary == ['make test, every tier:', '  unit-ros: 1 passed in 0.2 s',
                           '  system: 1 passed in 0.2 s', '  alone: 1 passed in 0.2 s',
                           'make test: all 3 tiers passed']
    else:
        assert result.returncode != 0
        assert summary == ['make test, every tier:',
                           '  unit-ros: 1 failed, 1 passed in 0.2 s (exit 1)',
                           '  system: 1 passed in 0.2 s', '  alone: 1 passed in 0.2 s',
                           '  FAILED test/test_fake.py::test_broken',
                           'make test: 1 of 3 tiers failed: unit-ros'], out


def test_a_tier_left_without_a_test_by_a_filter_is_no_failure(tmp_path, capsys):
    """Exit 5 of pytest (none selected, e.g. PYTEST_ARGS='-k name'): said, not a failure."""
    from test_support import tier_summary

    report = ('<testsuites><testsuite name="pytest" tests="{}" failures="0" errors="0" '
              'skipped="0" time="1.0"></testsuite></testsuites>')
    for name, status, tests in (('1-unit-ros', 0, 2), ('2-system', 5, 0)):
        (tmp_path / f'{name}.status').write_text(f'{status}\n')
        (tmp_path / f'{name}.xml').write_text(report.format(tests))
    assert tier_summary.main(['tier_summary', str(tmp_path)]) == 0
    assert capsys.readouterr().out.splitlines() == [
        'make test, every tier:', '  unit-ros: 2 passed in 1.0 s',
        '  system: no tests ran in 1.0 s (none selected)', 'make test: all 2 tiers passed']
    (tmp_path / '1-unit-ros.status').write_text('2\n')  # interrupted: no report of failures
    assert tier_summary.main(['tier_summary', str(tmp_path)]) == 1
    assert capsys.readouterr().out.splitlines()[-1] == 'make test: 1 of 2 tiers failed: unit-ros'
