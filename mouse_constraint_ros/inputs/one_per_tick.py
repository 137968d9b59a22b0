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
At most one input taken between two ticks; the newest of the others held for the next tick.

A target costs the node a fit of the stream it belongs to, and a client may send them faster
than the node ticks (a flood: 5 000 a second at a 500 Hz node). Only the newest is of use to
the next tick, so ``OnePerTick`` lets the first input after a tick be taken at once, as it
comes, and holds the ones after it, each replacing the one held, until the next tick takes the
newest (``tick``). An input taken at the tick is the one that came last, taken as it would have
been when it came (the caller keeps its arrival); a stream that comes no faster than the ticks
loses nothing. Whatever else changes what an input changes (a grab, a release, a reset) takes
the held one first (``flush``), so that the order they came in holds. No ROS here.
"""

from typing import Generic, Optional, TypeVar

Item = TypeVar('Item')


class OnePerTick(Generic[Item]):
    """The input to take now, or the newest held for the next tick."""

    def __init__(self) -> None:
        """Open: the first input is taken at once."""
        self._held: Optional[Item] = None
        self._taken = False
        self.held_over = 0  # inputs replaced by a newer one before a tick took them

    def offer(self, item: Item) -> Optional[Item]:
        """Return ``item`` to take now, or None: it is held (the one held before dropped)."""
        if not self._taken:
            self._taken = True
            return item
        if self._held is not None:
            self.held_over += 1
        self._held = item
        return None

    def flush(self) -> Optional[Item]:
        """Return the input held, to take now (before another change), or None."""
        held, self._held = self._held, None
        return held

    def tick(self) -> Optional[Item]:
        """
        Return the input held, to take at this tick, or None.

        After a tick that took one, the inputs until the next are held again; after one that
        took none, the first is taken at once.
        """
        held = self.flush()
        self._taken = held is not None
        return held
