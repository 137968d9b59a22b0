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

"""``Throttle``: one line per period and reason, the held-back count, lazy messages."""

from mouse_constraint_ros.inputs.throttle import Throttle

PERIOD = 2.0


class FakeClock:
    """A clock that moves only when told to."""

    def __init__(self) -> None:
        """Start at 100 s."""
        self.now = 100.0

    def __call__(self) -> float:
        """Return the current time (s)."""
        return self.now


def test_one_line_per_period_then_the_count_of_the_held_back_ones():
    """Within a period only the first is logged; the next line says how many were held back."""
    lines, clock = [], FakeClock()
    throttle = Throttle(lines.append, period=PERIOD, clock=clock)
    assert throttle('frame', lambda: 'first')
    for _ in range(3):
        clock.now += PERIOD / 4
        assert not throttle('frame', lambda: 'held back')
    clock.now += PERIOD / 4 - 1e-9
    assert not throttle('frame', lambda: 'still held back')
    clock.now += 1e-9
    assert throttle('frame', lambda: 'second')
    assert lines == ['first', 'second (4 more since the last one)']
    clock.now += PERIOD
    assert throttle('frame', lambda: 'third')
    assert lines[-1] == 'third'


def test_each_reason_has_its_own_throttle():
    """A line of one reason does not hold back a line of another."""
    lines, clock = [], FakeClock()
    throttle = Throttle(lines.append, period=PERIOD, clock=clock)
    assert throttle('frame', lambda: 'a')
    assert throttle('rate', lambda: 'b')
    assert not throttle('frame', lambda: 'c')
    assert lines == ['a', 'b']


def test_a_held_back_message_is_never_built():
    """The message callable runs only for lines that are logged."""
    built, clock = [], FakeClock()
    throttle = Throttle(lambda line: None, period=PERIOD, clock=clock)

    def message() -> str:
        built.append(clock.now)
        return 'x'
    for _ in range(5):
        throttle('finite', message)
        clock.now += PERIOD / 10
    assert built == [100.0]
