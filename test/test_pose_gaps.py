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

"""A device's poses lost, counted from the gaps in its stamps at its rate."""

import pytest

from mouse_constraint_ros.inputs.pose_gaps import PoseGaps

MS = 1_000_000


def gaps(stamps, *, on=True, timeout=0.1):
    counter = PoseGaps()
    counter.configure(on=on, rate_hz=1000.0, timeout=timeout)
    return [counter.take(stamp) for stamp in stamps], counter.lost


@pytest.mark.unit
def test_a_gap_of_k_periods_is_k_minus_one_poses_lost():
    stamps = [5 * MS, 6 * MS, 9 * MS, 10 * MS, 10 * MS + 1_400_000, 12 * MS + 1_900_000]
    assert gaps(stamps) == ([0, 0, 2, 0, 0, 1], 3)


@pytest.mark.unit
def test_silence_unstamped_poses_a_clock_going_back_and_off_count_nothing():
    assert gaps([MS, 2 * MS, 200 * MS, 201 * MS]) == ([0, 0, 0, 0], 0)  # > 0.1 s: silence
    assert gaps([MS, 2 * MS, 200 * MS], timeout=0.0) == ([0, 0, 197], 197)  # 0: never silent
    assert gaps([0, 0, 0, 0]) == ([0, 0, 0, 0], 0)
    assert gaps([50 * MS, 51 * MS, 3 * MS, 6 * MS]) == ([0, 0, 0, 2], 2)
    assert gaps([MS, 5 * MS], on=False) == ([0, 0], 0)
