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
``mouse_constraint_node`` as the executable runs it, but served by its own spin loop.

``python -m bench.loop_node --ros-args ...`` makes ``MouseConstraintNode(loop_ticks=True)`` and
serves it with ``NodeRun.serve(pace=ticker.run_due)``: on system time the ticks are the spin
loop's, not an rclpy timer's (``timing/loop_timer.py``). The benchmarks run it beside the
shipped node to weigh that choice: the CPU it saves (``bench.node_cost``) against the latency it
costs (``bench.latency``). Parameters and remaps come after ``--ros-args`` as for the node.
"""

import sys

import rclpy
from rclpy.signals import SignalHandlerOptions

from mouse_constraint_ros.node.mouse_constraint_node import MouseConstraintNode
from mouse_constraint_ros.timing.spin import NodeRun


def main() -> int:
    """Serve the node from its own loop until Ctrl-C or SIGTERM; exit 0 then."""
    rclpy.init(args=sys.argv, signal_handler_options=SignalHandlerOptions.NO)
    with NodeRun() as run:
        run.node = MouseConstraintNode(loop_ticks=True)
        return run.serve(pace=run.node.ticker.run_due)


if __name__ == '__main__':
    sys.exit(main())
