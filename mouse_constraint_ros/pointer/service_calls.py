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
The calls a client makes of the node's services, each given up when it goes unanswered.

rclpy's ``Client`` keeps every request it sent until its answer comes. A node that never
answers (gone, stuck, a request lost before its server matched the client) would leave one
pending request for every release, step or question the web view and the RViz marker send, for
as long as they run. ``ServiceCalls`` sends through any of the client's ``Client``s and gives
up, at each later call and at each ``give_up_late`` (the owner's work timer), the requests
unanswered for ``timeout`` seconds: removed from their client (a late answer is then dropped)
and their ``on_give_up`` called. What is pending is bounded by the calls of the last
``timeout`` seconds. Time comes from the caller, in seconds of a monotonic clock.
"""

from collections import deque
import time
from typing import Callable, Deque, NamedTuple, Optional

from rclpy.client import Client
from rclpy.task import Future

# How long a request may go unanswered before it is given up (s): the node answers within a
# tick; this only bounds what a node that is gone or stuck leaves pending.
GIVE_UP_SECONDS = 5.0


class _Sent(NamedTuple):
    at: float
    client: Client
    future: Future
    on_give_up: Optional[Callable[[], None]]


class ServiceCalls:
    """
    Requests in flight, in the order sent, each given up ``timeout`` seconds after it went.

    :param timeout: how long a request may go unanswered (s, > 0).
    :param clock: seconds of a monotonic clock.
    """

    def __init__(self, *, timeout: float = GIVE_UP_SECONDS,
                 clock: Callable[[], float] = time.monotonic) -> None:
        """Start with nothing in flight."""
        if not timeout > 0.0:
            raise ValueError(f'timeout must be > 0, not {timeout!r}')
        self.timeout = timeout
        self._clock = clock
        self._sent: Deque[_Sent] = deque()
        self.given_up = 0

    @property
    def pending(self) -> int:
        """Return how many requests sent through this are still unanswered."""
        return sum(not sent.future.done() for sent in self._sent)

    def call(self, client: Client, request, *,
             on_answer: Optional[Callable[[Future], None]] = None,
             on_give_up: Optional[Callable[[], None]] = None) -> Future:
        """
        Send ``request`` through ``client`` once; return its future.

        :param on_answer: called with the future once the answer came (never after a give-up).
        :param on_give_up: called when it is given up, unanswered.
        """
        self.give_up_late()
        future = client.call_async(request)
        if on_answer is not None:
            future.add_done_callback(on_answer)
        self._sent.append(_Sent(self._clock(), client, future, on_give_up))
        return future

    def give_up_late(self) -> int:
        """Give up the requests unanswered for ``timeout`` seconds; return how many."""
        now, sent, count = self._clock(), self._sent, 0
        while sent and (sent[0].future.done() or now - sent[0].at >= self.timeout):
            oldest = sent.popleft()
            if oldest.future.done():
                continue
            oldest.client.remove_pending_request(oldest.future)
            count += 1
            if oldest.on_give_up is not None:
                oldest.on_give_up()
        self.given_up += count
        return count
