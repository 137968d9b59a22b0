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

"""What the simulated clock's pacing achieved between two samples, without ROS."""

import pytest

from mouse_constraint_ros.timing.sim_clock import PacingMeter, SimulatedClock

SECOND = 1_000_000_000


def test_the_meter_measures_simulated_per_wall_time_and_the_slip_between_samples():
    clock = SimulatedClock(100.0, 0.5, max_lag=0.1)
    meter = PacingMeter()
    assert meter.sample(SECOND, clock) == (None, 0.0)
    for _ in range(50):
        clock.advance()
    achieved, slipped = meter.sample(2 * SECOND, clock)
    assert achieved == pytest.approx(50 / clock.rate_hz)
    assert slipped == 0.0
    # Far behind: the clock gives up its lag beyond max_lag, and the meter shows it.
    clock.due(2 * SECOND)
    clock.due(12 * SECOND)
    achieved, slipped = meter.sample(12 * SECOND, clock)
    assert achieved == 0.0 and slipped == pytest.approx(clock.slipped_ns * 1e-9) and slipped > 0


def test_a_wall_clock_that_has_not_moved_measures_nothing():
    clock = SimulatedClock(100.0, 1.0, max_lag=0.1)
    meter = PacingMeter()
    meter.sample(SECOND, clock)
    clock.advance()
    assert meter.sample(SECOND, clock) == (None, 0.0)
