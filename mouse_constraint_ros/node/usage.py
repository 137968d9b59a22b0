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
node declares them (``ros2 param describe`` shows the same). Plain Python only.
"""

import textwrap
from typing import Sequence

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
