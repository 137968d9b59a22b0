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
Start-up refusals of the real executable: one FATAL line naming the parameter, exit 1.

Each case is a params file a user could write; the node is started as ``ros2 run`` starts it
(``mouse_constraint_node --ros-args --params-file F``) and its whole output is checked.
"""

import json
import os
from pathlib import Path
import select
import signal
import subprocess
import sys

import pytest

from mouse_constraint_ros.node.parameters import DEFAULTS
from test_support.meshes import bad_bodies, STARTED_BAD_BODY_NAMES

BIN = Path(sys.executable).parent
NODE = str(BIN / 'mouse_constraint_node')


def params_file(tmp_path: Path, *lines: str) -> Path:
    """Write a params file for every node with the given ``ros__parameters`` lines."""
    path = tmp_path / 'params.yaml'
    path.write_text('/**:\n  ros__parameters:\n' + ''.join(f'    {line}\n' for line in lines))
    return path


def run_node(*ros_arguments: str, timeout: float = 20.0) -> subprocess.CompletedProcess:
    """Run the node with ``ros_arguments`` until it exits; return what it printed."""
    return subprocess.run([NODE, '--ros-args', *ros_arguments], capture_output=True, text=True,
                          timeout=timeout)


def the_one_line(result: subprocess.CompletedProcess) -> str:
    """Return the process's only output line, asserting that it is one FATAL line."""
    lines = (result.stdout + result.stderr).splitlines()
    assert len(lines) == 1, lines
    assert lines[0].startswith('[FATAL]'), lines
    return lines[0]


# One file of each kind of refusal (a scalar, a bool and a list of the wrong type, a double and an
# integer out of range, a value not finite): test_startup reads every text from the function.
@pytest.mark.parametrize('line, expected', [
    ('mass: 2', 'mass: 2 is an integer, mass takes a double: write 2.0'),
    ('hold_initial_anchor: 1',
     'hold_initial_anchor: 1 is an integer, hold_initial_anchor takes a bool: write true'),
    ('gravity: [0, 0, -10]', 'gravity: [0, 0, -10] is a list of integers, gravity takes a list '
     'of doubles: write [0.0, 0.0, -10.0]'),
    ('rate_hz: 20000.0', 'rate_hz must be <= 10000.0, got 20000.0'),
    ('substeps: 0', 'substeps must be an integer >= 1, got 0'),
    ('mass: .nan', 'mass must be finite, got nan'),
])
def test_a_wrong_type_or_range_is_one_line_naming_the_parameter(tmp_path, line, expected):
    """Each bad value: exit 1 and one FATAL line with the parameter, the reason and the fix."""
    result = run_node('--params-file', str(params_file(tmp_path, line)))
    assert result.returncode == 1
    assert the_one_line(result).endswith(f'[mouse_constraint]: invalid parameters: {expected}')


def test_a_configuration_invalid_as_a_whole_is_one_line(tmp_path):
    """Values each in range but not together (a non-physical inertia): one line, exit 1."""
    result = run_node('--params-file', str(params_file(
        tmp_path, 'inertia: [1.0, 0.0, 0.0, 1.0, 0.0, 3.0]')))
    assert result.returncode == 1
    line = the_one_line(result)
    assert 'invalid parameters: ' in line and 'inertia' in line


def test_a_file_rcl_cannot_parse_is_one_line(tmp_path):
    """A list of mixed types: rcl refuses the file; one line with rcl's reason and the fix."""
    result = run_node('--params-file', str(params_file(tmp_path, 'anchor: [0.2, 0, 0.05]')))
    assert result.returncode == 1
    line = the_one_line(result)
    assert "cannot start: Couldn't parse params file" in line
    assert 'Sequence should be of same type' in line and 'e.g. [0.2, 0.0, 0.05]' in line
    assert '.c:' not in line  # no rcl source locations


ROOT = Path(__file__).resolve().parent.parent


def test_a_urdf_as_a_p_override_that_rcl_cannot_take_is_one_line():
    """-p robot_description:= a URDF whose comment holds ': ': one line with the way round."""
    text = (ROOT / 'config' / 'tool.urdf').read_text().replace('tool, a', 'tool: a')
    result = run_node('-p', f'robot_description:={text}', '-p', 'body_link:=tool')
    assert result.returncode == 1
    line = the_one_line(result)
    assert "cannot start: Couldn't parse parameter override rule: -p robot_description:=..." \
        in line and 'make run URDF=path/to.urdf' in line


@pytest.mark.parametrize('name, extra', [('tool', ()), ('mug', ('-p', 'density:=2400.0'))])
def test_the_shipped_urdfs_start_as_a_p_override(name, extra):
    """
    The ROS habit ``-p robot_description:="$(cat config/tool.urdf)"`` starts the shipped bodies.

    Their text is a YAML string (no ': ' or ' #' in their comments); the mug's package:// mesh
    is the package's own, found with no workspace. The node starts and says the link; SIGINT
    ends it with 0.
    """
    text = (ROOT / 'config' / f'{name}.urdf').read_text()
    environment = {k: v for k, v in os.environ.items() if k != 'AMENT_PREFIX_PATH'}
    process = subprocess.Popen([NODE, '--ros-args', '-p', f'robot_description:={text}',
                                '-p', f'body_link:={name}', *extra], env=environment,
                               stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
    try:
        # Its first line, or none by the deadline (a hang fails here instead of blocking).
        ready = select.select([process.stdout], [], [], 120.0)[0]
        first = process.stdout.readline() if ready else ''
    finally:
        process.send_signal(signal.SIGINT)
        rest, _ = process.communicate(timeout=60)
    assert f"link '{name}' (COM" in first, first + rest
    assert process.returncode == 0, first + rest


def test_a_missing_params_file_is_one_line(tmp_path):
    """A params file that is not there: one line naming it, exit 1."""
    missing = tmp_path / 'no_such.yaml'
    result = run_node('--params-file', str(missing))
    assert result.returncode == 1
    line = the_one_line(result)
    assert str(missing) in line and 'no such file' in line


@pytest.mark.parametrize('case', ['parameter', 'rcl'])
def test_the_fatal_line_carries_the_real_node_name(tmp_path, case):
    """Renamed and namespaced with remaps, the FATAL line is tagged with the real name."""
    line = 'mass: 2' if case == 'parameter' else 'anchor: [0.2, 0, 0.05]'
    result = run_node('--params-file', str(params_file(tmp_path, line)),
                      '-r', '__node:=other', '-r', '__ns:=/robot')
    assert result.returncode == 1
    assert '[robot.other]: ' in the_one_line(result)


def test_an_unknown_key_is_warned_about_with_the_nearest_name(tmp_path):
    """A typo'd key: the node runs, and warns at start with the key and the known name."""
    assert 'baumgarte' in DEFAULTS
    path = params_file(tmp_path, 'baumgarde: 0.5', 'rate_hz: 50.0')
    process = subprocess.Popen([NODE, '--ros-args', '--params-file', str(path)],
                               stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    try:
        # The node is up once it describes itself; the warning comes before.
        lines = []
        while not any('Hz x' in line for line in lines):
            line = process.stderr.readline()
            assert line, lines
            lines.append(line)
    finally:
        process.terminate()
        process.communicate(timeout=10.0)
    assert process.returncode == 0
    assert any('[WARN]' in line and
               "ignoring unknown parameter 'baumgarde': did you mean 'baumgarte'?" in line
               for line in lines), lines


@pytest.mark.parametrize('line, name', [
    ('real_time_factor: 1.0e-13', 'real_time_factor'),
    ('marker_rate_hz: 1.0e-11', 'marker_rate_hz'),
    ('diagnostics_rate_hz: 1.0e-11', 'diagnostics_rate_hz'),
])
def test_a_rate_whose_timer_cannot_run_is_one_line(tmp_path, line, name):
    """A factor or rate whose timer period overflows: one FATAL line, not a traceback."""
    result = run_node('--params-file', str(params_file(tmp_path, 'publish_clock: true', line)))
    assert result.returncode == 1
    assert f'{name} must be 0 or at least 0.001' in the_one_line(result)


@pytest.mark.parametrize('flag', ['--help', '-h'])
def test_help_prints_the_usage_and_every_parameter_and_starts_nothing(flag):
    """``mouse_constraint_node --help``: usage and the parameters, exit 0, no node started."""
    from mouse_constraint_ros.node.parameters import PARAMETERS
    result = subprocess.run([NODE, flag], capture_output=True, text=True, timeout=20.0)
    assert result.returncode == 0, result.stderr
    assert result.stdout.startswith('usage: mouse_constraint_node')
    for parameter in PARAMETERS:
        assert f'\n  {parameter.name}: ' in result.stdout, parameter.name
    assert result.stderr == '' and 'Hz x' not in result.stdout
    # A --help among the ROS arguments is theirs: the node starts (and here refuses a file).
    refused = run_node('--params-file', '/no/such/file.yaml', '--help')
    assert refused.returncode == 1


@pytest.mark.parametrize('arguments, line', [
    (['-p', 'mass:=3.0'], 'mouse_constraint_node: unknown arguments -p mass:=3.0: parameters go '
                          'after --ros-args, as in: mouse_constraint_node --ros-args -p '
                          'mass:=3.0 (--help lists them)'),
    (['--foo'], 'mouse_constraint_node: unknown argument --foo: parameters go after '
                '--ros-args, as in: mouse_constraint_node --ros-args -p NAME:=VALUE (--help '
                'lists them)'),
])
def test_arguments_outside_ros_args_are_refused_with_the_ros_args_form(arguments, line):
    """What is outside --ros-args, which rclpy ignores, is refused in one line, exit 2."""
    result = subprocess.run([NODE, *arguments], capture_output=True, text=True, timeout=20.0)
    assert result.returncode == 2 and result.stdout == ''
    assert result.stderr.splitlines() == [line]


@pytest.mark.parametrize('name', STARTED_BAD_BODY_NAMES)
def test_a_bad_urdf_body_is_one_line_and_exit_1(tmp_path, name):
    """Bad bodies of ``bad_bodies`` (XML, link, mesh, geometry, inertia, mass): one line."""
    text, link, words = bad_bodies(tmp_path)[name]
    result = run_node('--params-file', str(params_file(
        tmp_path, f'robot_description: {json.dumps(text)}', f'body_link: {json.dumps(link)}')))
    assert result.returncode == 1
    line = the_one_line(result)
    assert '[mouse_constraint]: invalid parameters: ' in line and words in line, line
