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
Ticks a device clocks: one per device pose, and the node's own ticks held back while they come.

With ``tick_source: target_pose`` each valid pose on ``target_pose`` runs one tick at once (dt
from ``rate_hz``), its force published right after: the pose -> force round trip is one hop
each way plus the tick, and the loop is the one the stability analysis has, with no tick of
delay. The tick is stamped on the node's grid one period after the latest tick
(``device_grid_tick``), so the stamps advance with the physics; its force carries the pose's
own stamp, by which the device knows the force of each pose it sent. The node's own clock
(its timer, or a caller's steps) keeps its grid: each of its ticks is held back while the
device ticks, and counts as dt of silence; once the silence exceeds
``device_timeout`` the node's own ticks run again, holding the last target, until a pose comes.
Before the first pose the node's own ticks run.

Each device tick is classed by the wall time since the previous one: early below half a tick,
late beyond one and a half (a device at the node's rate sends one pose per tick). Plain
integers only; the ticker owns it.
"""

# Why a device tick dropped ticks: the device's ticks fell behind the node's clock.
DEVICE_LAG_CAUSE = ("the device's ticks fell more than the catch-up bound behind the node's "
                    'clock (poses lost, or a device slower than rate_hz)')


def device_grid_tick(due: int, following: int, max_lag: int) -> int:
    """
    Return the tick of the node's grid a device tick runs as, on the node's clock.

    The one after the latest tick (``following``): the stamps advance with the physics, one
    period a tick. Once that falls more than ``max_lag`` ticks behind the latest tick due on
    the node's clock (``due``), the clock's: the ticks between are dropped, as the node's own
    clock drops the ticks beyond its catch-up bound.
    """
    return due if due - following > max_lag else following


# A device tick this much of dt after the previous one is on time; outside, early or late.
ON_TIME = (0.5, 1.5)
NEVER = float('inf')


class DeviceClock:
    """
    Whether the device clocks the ticks, how long it has been silent, and its ticks' timing.

    Off until ``configure`` turns it on.
    """

    def __init__(self) -> None:
        """Start off, with no device tick."""
        self.on = False
        self._dt_ns = 1_000_000
        self._timeout_ns = 100_000_000
        self._silence_ns = NEVER
        self._last_wall_ns = None
        self.ticks = self.early = self.late = 0

    def configure(self, *, on: bool, rate_hz: float, timeout: float) -> None:
        """Clock the ticks by the device or not, at ``rate_hz``; silent after ``timeout`` s."""
        if on != self.on:
            self._silence_ns = NEVER
            self._last_wall_ns = None
        self.on = on
        self._dt_ns = round(1e9 / rate_hz)
        self._timeout_ns = timeout * 1e9

    def take(self, wall_ns: int) -> None:
        """Count a device tick at ``wall_ns`` (a steady clock): early, late or on time."""
        last, dt = self._last_wall_ns, self._dt_ns
        if last is not None:
            gap = wall_ns - last
            if gap < ON_TIME[0] * dt:
                self.early += 1
            elif gap > ON_TIME[1] * dt:
                self.late += 1
        self._last_wall_ns = wall_ns
        self._silence_ns = 0
        self.ticks += 1

    @property
    def heard(self) -> bool:
        """Return whether the device clocks the ticks and one of its poses ran a tick."""
        return self.on and self._silence_ns != NEVER

    @property
    def silent(self) -> bool:
        """Return whether the device clocks the ticks, was heard, and is silent past timeout."""
        silence = self._silence_ns
        return self.on and silence != NEVER and 0.0 < self._timeout_ns < silence

    def own_tick(self) -> bool:
        """
        Return whether one of the node's own ticks runs; one held back adds dt of silence.

        A timeout of 0 never hands the ticks back to the node's clock while the device is on.
        """
        if not self.on or self._silence_ns == NEVER or self.silent:
            return True
        self._silence_ns += self._dt_ns
        return False
