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
At most ``max_rate`` pushes a second to the browser, however fast poses come (no ROS here).

The node may publish its pose at 1 kHz or more; a browser draws at most 60 frames a second and
each push costs the view a websocket message. ``PushThrottle`` keeps the newest item offered and
lets one through when at least 1 / ``max_rate`` s passed since the last push. An item held back
is not lost: ``flush`` (called from a timer) pushes it once its slot comes, so the last pose of
a stream that stops (a pause, a single step) is always shown. Time comes from the caller, in
seconds of a monotonic clock.
"""

import math
from typing import Generic, Optional, TypeVar

Item = TypeVar('Item')

# The browser's frame rate: pushing faster shows nothing more.
MAX_PUSH_RATE = 60.0


class PushThrottle(Generic[Item]):
    """
    Pass the newest item at most once per 1 / ``max_rate`` seconds.

    :param max_rate: pushes per second at most (> 0).
    """

    def __init__(self, max_rate: float = MAX_PUSH_RATE) -> None:
        """Start with nothing pushed and nothing held."""
        if not max_rate > 0.0:
            raise ValueError(f'max_rate must be > 0, not {max_rate!r}')
        self.period = 1.0 / max_rate
        self._last = -math.inf
        self._held: Optional[Item] = None
        self._holding = False

    def offer(self, item: Item, now: float) -> Optional[Item]:
        """
        Return ``item`` to push now, or None and hold it (replacing any held one).

        :param item: the newest item.
        :param now: the time (s).
        """
        self._held, self._holding = item, True
        return self.flush(now)

    def flush(self, now: float) -> Optional[Item]:
        """Return the held item when its slot has come (and forget it), else None."""
        if not self._holding or now - self._last < self.period:
            return None
        item, self._held, self._holding = self._held, None, False
        self._last = now
        return item

    def take(self) -> Optional[Item]:
        """Return the held item now, its slot come or not (and forget it), else None."""
        if not self._holding:
            return None
        item, self._held, self._holding = self._held, None, False
        return item

    @property
    def holding(self) -> bool:
        """Whether an item waits for its slot."""
        return self._holding
