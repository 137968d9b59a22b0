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
The ``mouse_ctl`` console script: Ctrl-C, SIGTERM and SIGHUP end it from the start.

Importing the command (rclpy, the message packages) and ``rclpy.init`` take some tenths of a
second, longer on a busy machine, before the command takes the signals with its
``StopRequest``; until then Python's defaults answer Ctrl-C with a KeyboardInterrupt traceback.
Here, before anything of the command is imported, a stop signal ends the process at once with
``INTERRUPTED_STATUS``, as a call stopped before its answer: nothing was sent yet, nothing is
left to close (``timing.early_signals``). Once the command returned they are ignored while the
interpreter exits. Standard library only: this module must load in no time.
"""

import sys
from typing import List, Optional

from .exit_status import INTERRUPTED_STATUS
from ..timing import early_signals


def ctl(args: Optional[List[str]] = None) -> int:
    """Take the stop signals, then import and run ``mouse_ctl``'s ``main``; return its status."""
    early_signals.take_early(INTERRUPTED_STATUS)
    from .ctl import main
    status = main(args)
    early_signals.ignore()
    return status


if __name__ == '__main__':
    sys.exit(ctl())
