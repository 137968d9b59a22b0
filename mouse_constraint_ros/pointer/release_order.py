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
Inputs sent after a release go once the node answered it (no ROS here).

A release is a call to the node's ``~/release``, a grab or a target a message on a topic, and
the node takes a request and a message that wait at once in no set order: they come on two DDS
readers, and rclpy's SingleThreadedExecutor takes a waiting message first. A grab sent right
after a release, a press right after letting go, or the next segment of a drag that came late,
could then be taken first and be undone by the release: the body would fly free in the hand
that holds it. ``ReleaseOrder`` keeps what comes after a release until the node answered it, or
``wait`` seconds passed (a node that stopped answering), and then lets it go in the order it
came. ``ReleaseGate`` is the wait alone, for inputs queued elsewhere (the marker's
``InputPacer``). Time comes from the caller, in seconds of a monotonic clock.
"""

from collections import deque
from typing import Callable, Deque, Generic, Iterable, Optional, Tuple, TypeVar

Item = TypeVar('Item')

# How long inputs wait for a release's answer at most (s): the node answers within a tick; this
# only bounds the wait on a node that is gone or stuck.
ANSWER_WAIT = 1.0


class ReleaseGate:
    """
    Closed from a release until the node answered it, or ``wait`` seconds passed.

    :param wait: how long it stays closed for an unanswered release at most (s, > 0).
    """

    def __init__(self, wait: float = ANSWER_WAIT) -> None:
        """Start open, no release sent."""
        if not wait > 0.0:
            raise ValueError(f'wait must be > 0, not {wait!r}')
        self.wait = wait
        self._unanswered: Optional[Tuple[int, float]] = None  # the release's number, when sent
        self.sent = 0  # releases sent so far; the last one's number

    def is_open(self, at: float) -> bool:
        """Return whether inputs may go at ``at`` (s)."""
        if self._unanswered is not None and at - self._unanswered[1] >= self.wait:
            self._unanswered = None
        return self._unanswered is None

    def released(self, at: float) -> int:
        """Close for a release sent at ``at`` (s); return its number, for ``answered``."""
        self.sent += 1
        self._unanswered = (self.sent, at)
        return self.sent

    def answered(self, release: int) -> None:
        """
        Take the node's answer to release number ``release``: open.

        The answer to an older release, one given up on after ``wait``, changes nothing.
        """
        if self._unanswered is not None and self._unanswered[0] == release:
            self._unanswered = None


class ReleaseOrder(Generic[Item]):
    """
    Inputs in the order they came, none past a release the node has not answered.

    :param is_release: whether an item is a release.
    :param wait: how long items wait for a release's answer at most (s, > 0).
    """

    def __init__(self, is_release: Callable[[Item], bool], wait: float = ANSWER_WAIT) -> None:
        """Start with nothing waiting, open."""
        self.gate = ReleaseGate(wait)
        self._is_release = is_release
        self._items: Deque[Item] = deque()

    @property
    def waiting(self) -> int:
        """Return how many items wait."""
        return len(self._items)

    def add(self, items: Iterable[Item]) -> None:
        """Queue ``items`` after those that wait."""
        self._items.extend(items)

    def take(self, at: float) -> Optional[Item]:
        """
        Return the oldest item if it may go at ``at`` (s), else None.

        A release that goes closes the gate from ``at`` on; its number is ``sent``, to pass to
        ``answered`` with the node's answer.
        """
        if not self._items or not self.gate.is_open(at):
            return None
        item = self._items.popleft()
        if self._is_release(item):
            self.gate.released(at)
        return item

    @property
    def sent(self) -> int:
        """Return the number of the last release taken (0: none)."""
        return self.gate.sent

    def answered(self, release: int) -> None:
        """Take the node's answer to release number ``release`` (``ReleaseGate.answered``)."""
        self.gate.answered(release)
