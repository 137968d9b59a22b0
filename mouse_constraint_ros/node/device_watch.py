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
A device on ``target_pose``: whether it is heard or silent, and the poses it lost.

Once a pose came, the device is silent while no valid pose came for ``device_timeout``
(``silent``): the force it is sent is then zero, and the node logs a line when it falls silent
and when it comes back. Once its poses clock the ticks (``tick_source: target_pose``), its
silence is counted in the node's own ticks held back since its last pose (the ticker's
``DeviceClock``), and the poses it sent that never came are counted from the gaps in their
stamps (``lost``, ``inputs.pose_gaps``). Each valid pose runs its tick (``pose_tick``).

The target input (``target_input``) tells it of every pose that came (``came``) and of
every pose it took (``taken``); the ticks and the inputs status ask it.
"""

from typing import Callable, Optional

from .parameters import NodeConfig
from ..inputs.input_timeouts import input_age, timed_out
from ..inputs.pose_gaps import back_text, PoseGaps, silent_text
from ..timing.device_clock import DeviceClock


class DeviceWatch:
    """
    Whether a device on ``target_pose`` is heard or silent, its poses lost, their ticks.

    :param config: the node's configuration (``configure`` replaces it): the device's
        timeout and tick source, the rate.
    :param now_ns: the node's time (ns).
    :param log: logs a line at INFO.
    :param clock: the ticker's device clock: while on, it says whether the device is silent.
    :param pose_tick: called with its stamp (ns) after each valid pose is taken (the ticker's
        ``device_tick``: the tick it runs when the device clocks the ticks).
    """

    def __init__(self, *, config: NodeConfig, now_ns: Callable[[], int],
                 log: Callable[[str], None], clock: Optional[DeviceClock] = None,
                 pose_tick: Callable[[int], None] = lambda _stamp: None) -> None:
        """Start unheard."""
        self._now_ns = now_ns
        self._log = log
        self._clock = clock
        self._pose_tick = pose_tick
        # Whether a pose came on target_pose, and when the last valid one came (ns).
        self.heard = False
        self.last_valid_ns = 0
        # The device's poses lost (gaps in their stamps), and since when it is silent (ns).
        self._gaps = PoseGaps()
        self._silent_since: Optional[int] = None
        self.configure(config)

    def configure(self, config: NodeConfig) -> None:
        """Take a new configuration: the device's timeout, whether its poses clock the ticks."""
        self._timeout = config.device.timeout
        self._gaps.configure(on=config.device.tick_source == 'target_pose',
                             rate_hz=config.rate_hz, timeout=config.device.timeout)

    def came(self, stamp_ns: int, now_ns: int) -> None:
        """Count a pose stamped ``stamp_ns`` that came at ``now_ns``, valid or not."""
        if not self.heard:
            self.heard, self.last_valid_ns = True, now_ns
        self._gaps.take(stamp_ns)

    def taken(self, stamp_ns: int, now_ns: int) -> None:
        """Count a valid pose stamped ``stamp_ns``, taken at ``now_ns``; run its tick."""
        self.last_valid_ns = now_ns
        self._pose_tick(stamp_ns)

    def age(self, now_ns: int) -> Optional[float]:
        """Return how long ago (s) the last valid pose came (or the first pose), None unheard."""
        return input_age(self.last_valid_ns, now_ns) if self.heard else None

    @property
    def lost(self) -> Optional[int]:
        """Return the device's poses lost so far (``PoseGaps``), None unless it clocks ticks."""
        return self._gaps.lost if self._gaps.on else None

    def silent(self, now_ns: int) -> bool:
        """
        Return whether a device was heard and no valid pose came for ``device_timeout``.

        Once the device's poses clock the ticks, its silence is counted in the node's own ticks
        held back since its last pose (``DeviceClock.silent``): on a simulated clock the node's
        time stands still without ticks. Before (every pose refused), in the node's time. The
        node logs a line when the device falls silent, and one when it comes back.
        """
        clock = self._clock
        if clock is not None and clock.heard:
            silent = clock.silent
        else:
            silent = self.heard and timed_out(self.last_valid_ns, now_ns, self._timeout)
        if silent != (self._silent_since is not None):
            now = self._now_ns()
            if silent:
                self._silent_since = now
                self._log(silent_text(self._timeout))
            else:
                self._log(back_text(input_age(self._silent_since, now)))
                self._silent_since = None
        return silent
