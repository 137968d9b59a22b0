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
``mouse_constraint_node`` as the executable runs it, but with its ticks on an rclpy timer.

``python -m bench.timer_node --ros-args ...`` makes ``MouseConstraintNode()`` (no
``loop_ticks``: the node as an application that adds it to its own executor gets it) and serves
it with ``NodeRun.serve()``: each tick is an rclpy timer's call, which rclpy's timers thread
hands to the spinning thread through the executor's queue. The benchmarks run it beside the
executable, which runs its ticks from its own spin loop, to weigh that choice: the CPU
(``bench.node_cost``) and the latency (``bench.latency``). Parameters and remaps come after
``--ros-args`` as for the node.
"""

import sys

import rclpy
from rclpy.signals import SignalHandlerOptions

from mouse_constraint_ros.node.mouse_constraint_node import MouseConstraintNode
from mouse_constraint_ros.timing.spin import NodeRun


def main() -> int:
    """Serve the node, its ticks on an rclpy timer, until Ctrl-C or SIGTERM; exit 0 then."""
    rclpy.init(args=sys.argv, signal_handler_options=SignalHandlerOptions.NO)
    with NodeRun() as run:
        run.node = MouseConstraintNode()
        return run.serve()


if __name__ == '__main__':
    sys.exit(main())
