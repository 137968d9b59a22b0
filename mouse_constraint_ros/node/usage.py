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
What ``mouse_constraint_node --help`` prints: how to run the node, and its parameters.

The parameters are ``PARAMETERS``: each name with its default and its description, as the
node declares them (``ros2 param describe`` shows the same). An argument the node does not
understand (anything but ``-h`` and ``--help`` outside ``--ros-args``: rclpy would ignore it,
and ``mass:=3.0`` would start a 2 kg body) is refused with one line that shows the
``--ros-args -p`` form, exit status 2 (``refuse_unknown_arguments``). Plain Python only.
"""

import sys
import textwrap
from typing import List, Sequence, TextIO

from .parameters import PARAMETERS
from .startup import yaml_text

USAGE = """usage: mouse_constraint_node [-h] [--ros-args [-p NAME:=VALUE ...] [--params-file FILE]
                             [-r __ns:=/NAMESPACE] [-r __node:=NAME] ...]

Serve one rigid body dragged by a mouse constraint: subscribes target, target_pose, grab and
wrench, publishes pose and twist (and TF, odometry, the felt force and /clock when asked),
offers ~/reset, ~/release, ~/pause and ~/step. Ctrl-C, SIGTERM and SIGHUP end it with exit
code 0; invalid parameters at start with exit code 1 and one line naming the parameter.

options:
  -h, --help            show this message and exit
  --ros-args ...        ROS arguments: -p NAME:=VALUE sets a parameter (a double is written
                        with a decimal point: mass:=2.0), --params-file FILE reads them from
                        YAML (config/params.yaml lists every one), -r remaps names

parameters (default, then what it does):"""

HELP_FLAGS = ('-h', '--help')
# The exit status of a command line the node does not understand (argparse's).
USAGE_STATUS = 2
ROS_ARGS = '--ros-args'


def asks_for_help(args: Sequence[str]) -> bool:
    """Return whether the command line, before any --ros-args, asks for the help."""
    arguments = list(args[1:])
    if '--ros-args' in arguments:
        arguments = arguments[:arguments.index('--ros-args')]
    return any(argument in HELP_FLAGS for argument in arguments)


def usage_text(width: int = 94) -> str:
    """Return the help: usage, options, and every parameter with its default and meaning."""
    lines = [USAGE]
    for parameter in PARAMETERS:
        lines.append(f'  {parameter.name}: {yaml_text(parameter.default)}')
        lines.extend(textwrap.wrap(parameter.description, width, initial_indent=' ' * 6,
                                   subsequent_indent=' ' * 6))
    return '\n'.join(lines)


def unknown_arguments(args: Sequence[str]) -> List[str]:
    """
    Return the arguments of the command line ``args`` the node does not understand.

    Those outside ``--ros-args`` (before it, or after a ``--`` that ends it), but for the help
    flags; what is inside, rcl reads (and refuses itself when it cannot).
    """
    unknown, inside = [], False
    for argument in args[1:]:
        if argument == ROS_ARGS:
            inside = True
        elif inside and argument == '--':
            inside = False
        elif not inside and argument not in HELP_FLAGS:
            unknown.append(argument)
    return unknown


def _as_parameters(unknown: Sequence[str]) -> List[str]:
    """Return ``unknown`` as the ``-p NAME:=VALUE`` it meant, or [] when it is not that."""
    given = [argument for argument in unknown if argument != '-p']
    if given and all(':=' in argument and not argument.startswith('-') for argument in given):
        return [word for argument in given for word in ('-p', argument)]
    return []


def unknown_arguments_line(unknown: Sequence[str], program: str = 'mouse_constraint_node') -> \
        str:
    """Return the one line that refuses ``unknown``, with the ``--ros-args -p`` form to use."""
    meant = _as_parameters(unknown)
    form = ' '.join(meant) if meant else '-p NAME:=VALUE'
    return (f'{program}: unknown argument{"s" if len(unknown) > 1 else ""} '
            f'{" ".join(unknown)}: parameters go after --ros-args, as in: {program} '
            f'{ROS_ARGS} {form} (--help lists them)')


def refuse_unknown_arguments(args: Sequence[str], stream: TextIO = None) -> None:
    """
    Exit with status 2 and one line on stderr when ``args`` hold arguments the node ignores.

    :param args: the command line, the program first (``sys.argv``).
    :raises SystemExit: with ``USAGE_STATUS``, after the line.
    """
    unknown = unknown_arguments(args)
    if unknown:
        print(unknown_arguments_line(unknown), file=sys.stderr if stream is None else stream)
        raise SystemExit(USAGE_STATUS)
