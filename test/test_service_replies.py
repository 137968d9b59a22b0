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

"""The replies of ~/pause, ~/step, ~/reset and ~/release, without ROS."""

import pytest

from mouse_constraint_ros.node.service_replies import (pause_reply, release_reply, reset_refusal,
                                                       reset_reply, step_refusal, step_reply)

SIMULATED = 12.3456789


@pytest.mark.parametrize('pause, paused, reply', [
    (True, True, 'already paused'), (False, False, 'already running'),
    (True, False, 'paused at 12.345679 s simulated'),
    (False, True, 'running from 12.345679 s simulated'),
])
def test_pause_says_what_changed_and_when_in_simulated_time(pause, paused, reply):
    """The simulated time, not the node's clock (seconds since 1970 on system time)."""
    assert pause_reply(pause, paused, SIMULATED) == reply


def test_a_step_runs_only_paused_and_with_a_clock():
    assert 'pause it first' in step_refusal(False, None)
    assert 'pause it first' in step_refusal(False, '/clock on /clock')
    assert step_refusal(True, '/clock on /sim/clock') == (
        'waiting for /clock on /sim/clock: no time to stamp a step with')
    assert step_refusal(True, None) is None
    assert step_reply(0.001, SIMULATED) == 'one tick of 0.001 s, to 12.345679 s simulated'


def test_reset_and_release_say_what_is_left():
    assert reset_reply(True).endswith('anchor held where it starts')
    assert reset_reply(False).endswith('no target')
    assert reset_refusal((0.2, 0.1, 0.05), 'why') == (
        'cannot restore the configured anchor [0.2, 0.1, 0.05]: why; nothing reset')
    assert (release_reply(True), release_reply(False)) == ('released', 'already free')
