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

"""When the node lets go of its target and its wrench, without ROS."""

import pytest

from mouse_constraint_ros.inputs.input_timeouts import (input_age, target_release_text, timed_out,
                                                        wrench_removal_text)

SECOND = 1_000_000_000


@pytest.mark.parametrize('age_ns, timeout, expected', [
    (SECOND // 2, 0.5, False),      # exactly the timeout: still held
    (SECOND // 2 + 1, 0.5, True),   # one nanosecond more: let go
    (10**6 * SECOND, 0.0, False),   # 0: never
    (-SECOND, 0.5, False),          # taken "after" now (a restarted clock)
])
def test_an_input_times_out_only_past_its_timeout(age_ns, timeout, expected):
    since = 7 * SECOND
    assert timed_out(since, since + age_ns, timeout) is expected


def test_an_age_is_in_seconds_and_never_negative():
    assert input_age(SECOND, 3 * SECOND + SECOND // 4) == pytest.approx(2.25)
    assert input_age(3 * SECOND, SECOND) == 0.0


def test_the_texts_name_the_timeout():
    assert target_release_text(0.5) == 'no target for 0.5 s: releasing the body'
    assert wrench_removal_text(2.0) == 'no wrench for 2 s: removing it'
