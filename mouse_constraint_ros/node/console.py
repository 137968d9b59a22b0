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
The ``mouse_constraint_node`` console script: Ctrl-C, SIGTERM and SIGHUP end it from the start.

Importing the node (rclpy, numpy, the message packages) and ``rclpy.init`` take some tenths of
a second before ``main`` installs its ``StopRequest``; until then Python's defaults answer
SIGINT with a KeyboardInterrupt traceback and SIGTERM and SIGHUP with death by the signal,
where the node promises exit 0. Here, before anything of the node is imported, each of them
ends the process at once with exit status 0 (``timing.early_signals``): no node exists before
``StopRequest`` takes the signals over, so there is nothing to close. ``StopRequest`` puts these
handlers back when the spin ends, so a second signal during the node's teardown ends it at once,
with 0 too. Once the node is torn down (destroyed, its context shut down), they are ignored
while the interpreter exits, where Python's defaults would end a clean stop with -2 or -15.
Standard library only: this module must load in no time.
"""

import sys

from ..timing import early_signals


def main() -> int:
    """Take the stop signals, then import and run the node's ``main``; return its status."""
    early_signals.take_early(0)
    from .mouse_constraint_node import main as node_main
    status = node_main()
    early_signals.ignore()
    return status


if __name__ == '__main__':
    sys.exit(main())
