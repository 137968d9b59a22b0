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
The node's tick counters between two samples: the window the rate status judges (no rclpy here).

The node keeps running totals of its ticks (``TickCounters``: run, run late, dropped, clock
restarts). Sampled at the diagnostics rate, ``TickWindow`` closes a window at each sample: the
seconds of the node's clock since the previous one and the totals' differences (``Window``),
from which ``diagnostics.rate_status`` takes the achieved rate. There is no window to judge at
the first sample, when the rate changed, or while the clock does not advance or reads zero.
"""

from typing import NamedTuple, Optional


class TickCounters(NamedTuple):
    """The node's running totals: ticks run, run late (in catch-up), dropped; clock restarts."""

    ticks: int
    late: int
    dropped: int
    clock_restarts: int


class Window(NamedTuple):
    """What happened between two samples: ``seconds`` of the node's clock and counter deltas."""

    seconds: float
    ticks: int
    late: int
    dropped: int
    clock_restarts: int


class TickWindow:
    """The node's tick counters between consecutive samples, at one requested rate."""

    def __init__(self) -> None:
        """Create a window that starts at the first sample."""
        self._previous = None

    def sample(self, now_ns: int, counters: TickCounters, rate_hz: float) -> Optional[Window]:
        """
        Close the window at ``now_ns`` and start the next one; return the closed one.

        :param now_ns: the node's clock (ns).
        :param counters: the node's totals now.
        :param rate_hz: the requested rate now.
        :returns: None for the first sample, or when the rate changed, the clock did not advance
            or reads zero (sim time before the first /clock): there is no window to judge then.
        """
        previous = self._previous
        self._previous = (now_ns, counters, rate_hz)
        if previous is None or now_ns <= 0:
            return None
        then, before, previous_rate = previous
        if previous_rate != rate_hz or now_ns <= then or then <= 0:
            return None
        deltas = (total - start for total, start in zip(counters, before))
        return Window((now_ns - then) * 1e-9, *deltas)
