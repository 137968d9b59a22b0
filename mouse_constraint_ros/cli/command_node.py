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
The node of a command (``mouse_ctl``, ``mouse_wrench``): made, spun and torn down in one order.

``command_node`` starts rclpy with the command line's ROS arguments and without rclpy's signal
handlers (the command's ``StopRequest`` takes the signals), makes the node and a
single-threaded executor with it, and tears all three down in reverse however the command
ends; a context shut down from outside while it runs is exit status 1.
"""

from contextlib import contextmanager
from typing import Any, Iterator, Sequence, Tuple

import rclpy
from rclpy.executors import SingleThreadedExecutor
from rclpy.node import Node
from rclpy.signals import SignalHandlerOptions

# The exit status of a command whose context was shut down from outside.
SHUTDOWN_STATUS = 1


@contextmanager
def command_node(name: str, argv: Sequence[str],
                 **node_options: Any) -> Iterator[Tuple[Node, SingleThreadedExecutor]]:
    """
    Yield the node ``name`` and its executor; destroy them and shut rclpy down after.

    :param argv: the command line, whose ``--ros-args`` rclpy reads.
    :param node_options: passed to ``rclpy.node.Node``.
    """
    rclpy.init(args=argv, signal_handler_options=SignalHandlerOptions.NO)
    node = Node(name, **node_options)
    executor = SingleThreadedExecutor(context=node.context)
    executor.add_node(node)
    try:
        yield node, executor
    finally:
        executor.shutdown()
        node.destroy_node()
        rclpy.try_shutdown()
