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
Which ticks of the grid publish the state, at a publish rate apart from the physics rate.

The physics steps every tick of the grid (``tick_grid``); pose, twist, TF and odometry go out
on the ticks that ``PublishTicks.due`` picks, stamped with those ticks' own grid stamps. With
publish rate p and tick rate r (0 < p <= r), tick n publishes when floor(n p / r) differs from
floor((n - 1) p / r), computed exactly on the rationals of the two floats:

- when p divides r, every (r / p)-th tick publishes, tick 0 first (100 Hz at 1 kHz: ticks 0,
  10, 20, ..., stamps exactly 10 ms apart);
- otherwise the gaps are the two integers around r / p, spread evenly (300 Hz at 1 kHz: gaps
  4, 3, 3, 4, 3, 3, ...), so that over any run of ticks the count of publishes is within one of
  p / r times its length: the mean rate is exactly p and every stamp lies on the grid.

p = 0 means every tick. Tick numbers count from the grid's tick 0, which the node puts at its
first tick and again at each grid restart (a clock jump back, a new ``rate_hz``), so the first
tick after one always publishes. A dropped tick (the node fell behind) that was due to publish
is not moved to another: what is published stays on the grid.
"""

from fractions import Fraction
import math

# With a publish rate, one timer callback runs at most this much simulated time of ticks.
MAX_BATCH_SECONDS = 0.01


class PublishTicks:
    """
    The publishing ticks of a grid at ``rate_hz`` for ``publish_rate_hz``.

    :param rate_hz: the tick rate (> 0).
    :param publish_rate_hz: the publish rate, 0 (every tick) or within (0, rate_hz].
    :raises ValueError: if ``publish_rate_hz`` is not 0 and not within (0, rate_hz].
    """

    def __init__(self, rate_hz: float, publish_rate_hz: float) -> None:
        """Keep p / r as an exact fraction."""
        if not (publish_rate_hz == 0.0 or 0.0 < publish_rate_hz <= rate_hz):
            raise ValueError(f'publish_rate_hz must be 0 or within (0, {rate_hz!r}], got '
                             f'{publish_rate_hz!r}')
        self.rate_hz = float(rate_hz)
        self.publish_rate_hz = float(publish_rate_hz)
        ratio = (Fraction(1) if publish_rate_hz == 0.0
                 else Fraction(publish_rate_hz) / Fraction(rate_hz))
        self._numerator, self._denominator = ratio.numerator, ratio.denominator
        self.every_tick = ratio == 1

    def due(self, tick: int) -> bool:
        """Return whether ``tick`` (>= 0) publishes."""
        numerator, denominator = self._numerator, self._denominator
        return tick * numerator // denominator != (tick - 1) * numerator // denominator


def ticks_per_callback(rate_hz: float, publish_rate_hz: float) -> int:
    """
    Return how many ticks one timer callback runs: 1 at every-tick publishing, else a batch.

    An executor turn costs about as much as the physics of a tick, so at a lower publish rate
    the node's timer fires once per publish period, not per tick, and each call runs the ticks
    due since the last: each is stepped on the grid, and the publishing ones are published with
    their own stamps. The batch is the whole number of ticks in one publish
    period, at most ``MAX_BATCH_SECONDS`` of them (10 ms: the callback stays far inside its
    wall budget, and a target waits at most that long). The trade: a target that arrives during
    a batch is used from the next one, up to one batch later than at every-tick publishing,
    for some 1 / k of the executor turns (100 Hz at 1 kHz: 10 ms, a tenth of the turns).

    :param rate_hz: the tick rate (> 0).
    :param publish_rate_hz: the publish rate, 0 (every tick) or within (0, rate_hz].
    """
    if publish_rate_hz == 0.0:
        return 1
    period = min(1.0 / publish_rate_hz, MAX_BATCH_SECONDS)
    return max(1, math.floor(period * rate_hz * (1.0 + 1e-12)))
