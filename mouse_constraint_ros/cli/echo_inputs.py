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
``mouse_ctl echo inputs``: the node's inputs status from /diagnostics, a line per report.

The node reports, at ``diagnostics_rate_hz``, how many inputs it refused, by reason, the last
one's line, whether a device on ``target_pose`` is heard or silent (its force then zero) and,
when it clocks the ticks, how many of its poses were lost: ``monitoring.input_diagnostics``.
``InputsPrinter`` picks the status of one node (its fully qualified name) out of each
``DiagnosticArray`` and prints it; the other nodes' are skipped.
"""

from typing import Callable

from diagnostic_msgs.msg import DiagnosticArray

from ..wire.messages import stamp_nanoseconds

LEVELS = {0: 'OK', 1: 'WARN', 2: 'ERROR', 3: 'STALE'}


class InputsPrinter:
    """
    Lines for the inputs status of the node ``node_name`` (fully qualified).

    :param node_name: the node whose status is printed, e.g. ``/mouse_constraint``.
    :param write: called with each line.
    """

    def __init__(self, node_name: str, write: Callable[[str], None]) -> None:
        """Show nothing yet."""
        self._name = f'{node_name}: inputs'
        self._write = write
        self.topic = ''
        self.received = 0
        self.printed = 0
        self.unreadable = 0

    def take(self, message: DiagnosticArray) -> None:
        """Print the node's inputs status of ``message``, if it holds one."""
        for status in message.status:
            if status.name == self._name:
                self.received += 1
                self.printed += 1
                self._write(self.line(stamp_nanoseconds(message.header.stamp), status))

    @staticmethod
    def line(stamp_ns: int, status) -> str:
        """Return the line of one status: stamp, level, message, then each value."""
        level = LEVELS.get(status.level[0] if isinstance(status.level, bytes) else status.level,
                           str(status.level))
        values = '  '.join(f'{value.key}: {value.value}' for value in status.values)
        return f'{stamp_ns * 1e-9:.6f} s  {level}  {status.message}  {values}'
