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
The limits that keep the node's numbers in what runs: timer rates, and ranges of finite values.

A timer period is kept in int64 nanoseconds, so a rate of 1e-11 Hz (a period of 1e11 s) makes a
timer that cannot be created: ``off_or_at_least`` lets such a rate (and a real_time_factor,
whose tick timer period is 1 / (rate_hz real_time_factor)) be 0, off, or at least a bound that
gives periods of at most 1000 s. ``FINITE_MAX`` tops the declared range of a parameter that
takes every finite value but not ``.inf``. Plain floats; no ROS here.
"""

import math

# The slowest timer rate (Hz) and the smallest real_time_factor other than 0: the periods they
# give (at most 1000 s, rate_hz >= 1) are timers that run.
MIN_TIMER_RATE = 1e-3
MIN_REAL_TIME_FACTOR = 1e-3
# The largest float: the top of a range of every finite value.
FINITE_MAX = math.nextafter(math.inf, 0.0)


def off_or_at_least(name: str, value: float, low: float, unit: str = '') -> float:
    """Return ``value`` of parameter ``name`` when it is 0 or at least ``low``, else raise."""
    if 0.0 < value < low:
        raise ValueError(f'{name} must be 0 or at least {low:g}{unit}, got {value!r}: a '
                         'smaller one makes a timer period beyond what a timer runs')
    return value
