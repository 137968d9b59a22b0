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
At most ``max_rate`` inputs a second to the node, grabs, targets and releases together (no ROS).

Every client's feedback ends in one stream of inputs: RViz sends a target per frame (30 a
second), a client gone wrong any number of targets, or of press, move and release cycles, each
a grab, a target and a ``~/release``. ``InputPacer`` lets the oldest input waiting go only when
at least 1 / ``max_rate`` s passed since the last one went, whatever its kind, and keeps what
waits short by dropping what a later input makes moot:

- a target replaces a target that waits right before it (the newest point is the one that
  counts);
- a grab drops the targets and grabs that wait after the last release: it sets the anchor and
  the target anew;
- a release drops them too (the body is let go), and is one with a release that waits before
  them.

So at most a release, a grab and a target wait, in that order, and nothing a hand does is lost:
a press right after a release grabs one slot later. Time comes from the caller, in seconds of a
monotonic clock.
"""

import math
from typing import Generic, List, Optional, Tuple, TypeVar

from ..pointer.gestures import GRAB, RELEASE, TARGET

Item = TypeVar('Item')

# A slot comes this much early (s): the rounding of a difference of clock readings.
ROUNDING = 1e-9


class InputPacer(Generic[Item]):
    """
    Let inputs go at most once per 1 / ``max_rate`` seconds, in order (see the module).

    :param max_rate: inputs per second at most (> 0).
    """

    def __init__(self, max_rate: float) -> None:
        """Start with nothing sent and nothing waiting."""
        if not max_rate > 0.0:
            raise ValueError(f'max_rate must be > 0, not {max_rate!r}')
        self.period = 1.0 / max_rate
        self._last = -math.inf
        self._waiting: List[Tuple[str, Item]] = []

    @property
    def waiting(self) -> List[str]:
        """Return the kinds of the inputs waiting for their slots, oldest first."""
        return [kind for kind, _ in self._waiting]

    def add(self, kind: str, item: Item) -> None:
        """
        Queue an input, dropping what it makes moot (see the module); nothing goes.

        :param kind: GRAB, TARGET or RELEASE.
        :param item: what goes to the node for it.
        """
        waiting = self._waiting
        if kind == TARGET:
            if waiting and waiting[-1][0] == TARGET:
                waiting.pop()
            waiting.append((kind, item))
        elif kind in (GRAB, RELEASE):
            while waiting and waiting[-1][0] != RELEASE:
                waiting.pop()
            if kind == GRAB or not waiting:
                waiting.append((kind, item))
        else:
            raise ValueError(f'no input of kind {kind!r}')

    def flush(self, now: float) -> Optional[Tuple[str, Item]]:
        """Return the oldest input waiting, with its kind, when its slot came at ``now`` (s)."""
        if not self._waiting or now - self._last < self.period - ROUNDING:
            return None
        self._last = now
        return self._waiting.pop(0)
