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
What the ticks leave for the rest of the node to read: the latest stamp, the tick length, counts.

A target's stamp is mapped onto the core's time through the latest tick's stamp (the
simulation's time after it is the simulation's own); /diagnostics reports the running counts.
"""

from dataclasses import dataclass
from typing import Optional

from ..monitoring.tick_window import TickCounters


@dataclass
class TickRecord:
    """
    What the ticks have done: the latest one, its length, and the node's running counts.

    ``Tick`` writes ``stamp_ns``, ``dt`` and ``ticks_run``; the drivers count late and dropped
    ticks and clock restarts; the inputs and the monitors read.
    """

    # The stamp of the latest tick run (ns, the node's time); 0 before the first.
    stamp_ns: int = 0
    # The tick length (s), 1 / rate_hz.
    dt: float = 0.001
    ticks_run: int = 0
    late_ticks: int = 0
    dropped_ticks: int = 0
    clock_restarts: int = 0
    # Why ticks were last dropped, for /diagnostics; None while none were.
    drop_cause: Optional[str] = None

    def counters(self) -> TickCounters:
        """Return the running totals /diagnostics samples."""
        return TickCounters(self.ticks_run, self.late_ticks, self.dropped_ticks,
                            self.clock_restarts)

    def drop(self, count: int, cause: str) -> None:
        """Count ``count`` ticks dropped for ``cause``."""
        self.dropped_ticks += count
        self.drop_cause = cause
