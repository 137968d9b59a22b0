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
How much later than its least latency a late target stream is presented: its lag.

A stamped stream presented at its least latency D is extrapolated past its newest stamp over
its horizon, the longest interval plus the latencies' spread above D, and a drag that stops at
once overshoots by that much travel. A late stream has time to spare: ``Lag`` presents it later
by the part of the horizon past one mean interval (the latencies' spread and the intervals'
jitter, ``jitter``), by ``LATE_SHARE`` of D at most, so that a stop overshoots by one interval
of travel; the lag goes to its goal at ``DELAY_SLEW`` and never jumps. A stream on time
(D about 0) keeps no lag and is followed without one.

Plain float arithmetic, deterministic for the same inputs.
"""

from typing import Sequence

import numpy as np

# At most this share of the least latency is added to it. A browser's 20 Hz drag 200 ms late
# takes 37-40 ms of the 50 allowed, and a stop overshoots by 26 mm instead of 44-46 mm
# (bench/late_streams.py).
LATE_SHARE = 0.25
# The lag goes to its goal at this rate (s per s): the presented time runs 5 % slower or faster
# while it moves, and never jumps.
DELAY_SLEW = 0.05


def jitter(times: Sequence[float]) -> float:
    """Return the longest interval between ``times`` (increasing, s) less their mean; 0 for < 3."""
    if len(times) < 3:
        return 0.0
    intervals = np.diff(times)
    return float(intervals.max() - intervals.mean())


class Lag:
    """A late stream's lag (s): its value at a core time and the goal it moves to."""

    def __init__(self) -> None:
        """Start at no lag."""
        self.value, self.since, self.goal = 0.0, 0.0, 0.0

    def at(self, time: float) -> float:
        """Return the lag (s) at core ``time``."""
        step = DELAY_SLEW * max(0.0, time - self.since)
        value, goal = self.value, self.goal
        if abs(goal - value) <= step:
            return goal
        return value + step if value < goal else value - step

    def aim(self, time: float, *, delay: float, need: float, continues: bool) -> None:
        """
        Aim at the lag for a stream ``delay`` late (s) that ``need`` s more would serve.

        :param time: the core time the new goal is set at (a point's arrival).
        :param continues: False for a new stream: the lag is its goal at once.
        """
        goal = max(0.0, min(need, LATE_SHARE * delay))
        self.value = self.at(time) if continues else goal
        self.since, self.goal = time, goal

    def reset(self) -> None:
        """No lag (a stream timed by arrival, or none)."""
        self.value = self.since = self.goal = 0.0

    def shift(self, seconds: float) -> None:
        """Move the time the lag was set at by ``seconds`` (``TargetStream.shift``)."""
        self.since += seconds
