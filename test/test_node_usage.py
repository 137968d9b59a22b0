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
The node's command line: what it does not understand is refused with the ``--ros-args`` form.

rclpy ignores arguments outside ``--ros-args``: ``mouse_constraint_node -p mass:=3.0`` would
start a 2 kg body. ``refuse_unknown_arguments`` says so in one line and exits 2.
"""

import io

import pytest

from mouse_constraint_ros.node.usage import (refuse_unknown_arguments, unknown_arguments,
                                             USAGE_STATUS)

PROGRAM = 'mouse_constraint_node'


@pytest.mark.parametrize('arguments, unknown', [
    (['-p', 'mass:=3.0'], ['-p', 'mass:=3.0']),
    (['--foo'], ['--foo']),
    (['mass:=3.0', '--ros-args', '-p', 'substeps:=4'], ['mass:=3.0']),
    (['--ros-args', '-p', 'mass:=3.0', '--', 'extra'], ['extra']),
    (['--ros-args', '-p', 'mass:=3.0'], []),
    (['--ros-args', '--params-file', 'p.yaml', '--ros-args', '-r', '__ns:=/robot'], []),
    (['-h'], []), (['--help'], []), ([], []),
])
def test_only_ros_arguments_and_help_are_understood(arguments, unknown):
    """Outside --ros-args (before it, after its --) only -h and --help."""
    assert unknown_arguments([PROGRAM, *arguments]) == unknown


@pytest.mark.parametrize('arguments, line', [
    (['-p', 'mass:=3.0'], 'mouse_constraint_node: unknown arguments -p mass:=3.0: parameters go '
     'after --ros-args, as in: mouse_constraint_node --ros-args -p mass:=3.0 (--help lists '
     'them)'),
    (['mass:=3.0', 'frequency_hz:=5.0'], 'mouse_constraint_node: unknown arguments mass:=3.0 '
     'frequency_hz:=5.0: parameters go after --ros-args, as in: mouse_constraint_node '
     '--ros-args -p mass:=3.0 -p frequency_hz:=5.0 (--help lists them)'),
    (['--foo'], 'mouse_constraint_node: unknown argument --foo: parameters go after --ros-args, '
     'as in: mouse_constraint_node --ros-args -p NAME:=VALUE (--help lists them)'),
])
def test_what_is_not_understood_is_refused_in_one_line_with_exit_2(arguments, line):
    """One line that shows the --ros-args -p form (the user's own when it was meant so)."""
    stream = io.StringIO()
    with pytest.raises(SystemExit) as exit_info:
        refuse_unknown_arguments([PROGRAM, *arguments], stream)
    assert exit_info.value.code == USAGE_STATUS == 2
    assert stream.getvalue() == line + '\n'


def test_a_command_line_it_understands_passes():
    """ROS arguments and help: nothing printed, no exit."""
    stream = io.StringIO()
    refuse_unknown_arguments([PROGRAM, '--ros-args', '-p', 'mass:=3.0'], stream)
    refuse_unknown_arguments([PROGRAM, '--help'], stream)
    assert stream.getvalue() == ''
