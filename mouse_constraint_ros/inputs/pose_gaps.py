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
A device's poses lost on the way, counted from the gaps in its stamps, and its silences.

A device that clocks the ticks sends one pose a period (1 / ``rate_hz``), each stamped by its
clock: a gap of k periods between the stamps of two poses that came one after the other means
k - 1 poses sent between them never came (a queue that overflowed while the node was busy, a
network that dropped them). ``PoseGaps`` counts them over every pose that comes, refused or
not (a refused pose came: the refusals count it). A gap longer than ``device_timeout`` is a
silence of the device, not poses lost (0: every gap counts); a zero stamp (a device that does
not stamp) or one not after the previous (a clock that restarted) counts nothing.

The lines the node logs when the device falls silent and when it comes back are here too.
Plain integers only.
"""


class PoseGaps:
    """The poses lost so far, from the gaps in the stamps of those that came."""

    def __init__(self) -> None:
        """Count nothing until ``configure`` turns it on."""
        self.on = False
        self.lost = 0
        self._period_ns = 1_000_000
        self._silence_ns = 0
        self._last_ns = 0

    def configure(self, *, on: bool, rate_hz: float, timeout: float) -> None:
        """Count at ``rate_hz`` (the device's) when ``on``; a gap past ``timeout`` s is silence."""
        self.on = on
        self._period_ns = 1e9 / rate_hz
        self._silence_ns = timeout * 1e9

    def take(self, stamp_ns: int) -> int:
        """Take the stamp of a pose that came; return how many poses its gap says were lost."""
        last, self._last_ns = self._last_ns, stamp_ns
        if not self.on or stamp_ns == 0 or last == 0 or stamp_ns <= last:
            return 0
        gap = stamp_ns - last
        if 0.0 < self._silence_ns < gap:
            return 0
        lost = max(0, round(gap / self._period_ns) - 1)
        self.lost += lost
        return lost


def silent_text(timeout: float) -> str:
    """Return the line logged when the device falls silent (``timeout``: device_timeout, s)."""
    return (f'device silent: no valid pose on target_pose for more than device_timeout '
            f'{timeout:g} s: the force sent is zero until one comes')


def back_text(silent: float) -> str:
    """Return the line logged when the device comes back, ``silent`` s after it fell silent."""
    return (f'device back on target_pose, {silent:.3f} s after it fell silent: the force is '
            'sent again')
