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
The device's ticks on the node's clock: their stamps on its grid, and the own ticks after them.

With ``tick_source: target_pose`` on the node's clock (not the node as the clock), each device
tick is stamped on the grid of the node's clock, one period after the latest tick, so that the
stamps advance with the physics (``device_stamp``; ``timing.device_clock.device_grid_tick``
says when a lag drops ticks instead). The device's ticks may run ahead of the clock; once the
device is silent the node's own ticks go on from the first tick of the grid after its latest
(``OwnTicks``), none repeated. ``ticker.Ticker`` owns it.
"""

from typing import Callable, Optional, Tuple

from .tick import Tick
from .tick_record import TickRecord
from ..timing.device_clock import device_grid_tick, DeviceClock
from ..timing.tick_grid import TickGrid


class OwnTicks:
    """
    The node clock's ticks, each run unless the device clocks the ticks now.

    A tick of the grid the device already ran, or passed (its ticks can run ahead of the clock),
    is not run again.
    """

    def __init__(self, tick: Tick, device_clock: DeviceClock,
                 grid: Callable[[], Optional[TickGrid]]) -> None:
        """Run ``tick`` when ``device_clock`` lets the node's own tick run."""
        self._tick = tick
        self._own_tick = device_clock.own_tick
        self._grid = grid
        # The grid's origin and the latest of its ticks the device ran.
        self._device_ran: Optional[Tuple[int, int]] = None

    def device_ran(self, origin: int, tick: int) -> None:
        """Note that the device ran ``tick`` of the grid whose origin is ``origin``."""
        self._device_ran = (origin, tick)

    def device_stamp(self, now: int, record: TickRecord) -> Tuple[int, int]:
        """
        Return the stamp of a device tick at the clock's reading ``now`` and the ticks it drops.

        The grid's tick one period after the latest tick (``record``), or the latest due at
        ``now`` once that lags by more than the grid's catch-up bound (``device_grid_tick``).
        """
        grid = self._grid()
        if not grid.started:
            grid.restart(now)
        due = grid.tick_at(now)
        following = grid.tick_after(record.stamp_ns) if record.ticks_run else due
        tick = device_grid_tick(due, following, grid.max_catch_up)
        self._device_ran = (grid.origin, tick)
        return grid.stamp(tick), tick - following

    def run(self, stamp: int, tick: Optional[int] = None) -> None:
        """Run the tick ``stamp`` unless the device ran it or holds it back."""
        ran = self._device_ran
        if (ran is not None and tick is not None and tick <= ran[1]
                and self._grid().origin == ran[0]):
            return
        if self._own_tick():
            self._tick.run(stamp, tick)
