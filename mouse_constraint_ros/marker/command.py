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
The ``mouse_marker`` command: the body as an RViz interactive marker, until Ctrl-C.

``mouse_marker [--hold]`` serves the interactive marker of ``mouse_constraint`` in its
namespace (``--ros-args -r __ns:=/robot``) on ``mouse_marker/update``, ``mouse_marker/feedback``
and ``mouse_marker/get_interactive_markers``: in RViz, an InteractiveMarkers display on the
namespace ``/mouse_marker`` (``/robot/mouse_marker``) and the Interact tool drag the body.
``--hold`` keeps the body held where a drag ends (the parameter ``hold_on_release``).
"""

import argparse
import sys
from typing import List, Optional

import rclpy
from rclpy.parameter import Parameter
from rclpy.signals import SignalHandlerOptions
from rclpy.utilities import remove_ros_args

from .node import HOLD_PARAMETER, MouseMarkerNode
from ..timing.spin import NodeRun


def build_parser() -> argparse.ArgumentParser:
    """Return the command's argument parser."""
    parser = argparse.ArgumentParser(
        prog='mouse_marker',
        description='Serve the body of mouse_constraint as an RViz interactive marker: drag it '
                    'with the Interact tool.',
        epilog='in RViz: add an InteractiveMarkers display on the namespace /mouse_marker, pick '
               'the Interact tool, press on the body and drag; add --ros-args -r '
               '__ns:=/robot for /robot/mouse_constraint')
    parser.add_argument('--hold', action='store_true',
                        help='keep the body held where a drag ends (default: released)')
    return parser


def main(args: Optional[List[str]] = None) -> int:
    """Serve the marker until Ctrl-C, SIGTERM or SIGHUP; exit 0 then, 2 on bad arguments."""
    argv = sys.argv if args is None else args
    options = build_parser().parse_args(remove_ros_args(argv)[1:])
    rclpy.init(args=argv, signal_handler_options=SignalHandlerOptions.NO)
    with NodeRun() as run:
        overrides = [Parameter(HOLD_PARAMETER, value=True)] if options.hold else []
        node = run.node = MouseMarkerNode(parameter_overrides=overrides)
        node.get_logger().info(
            f'serving the body of {node.follower.target_node} as the interactive marker '
            f"'body' on {node.update_publisher.topic_name}")
        return run.serve()


if __name__ == '__main__':
    sys.exit(main())
