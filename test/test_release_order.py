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

"""``ReleaseOrder``: nothing goes past a release before its answer, or its wait is up."""

import pytest

from mouse_constraint_ros.pointer.release_order import ANSWER_WAIT, ReleaseGate, ReleaseOrder

RELEASE = 'release'


def order(wait: float = ANSWER_WAIT) -> ReleaseOrder:
    """Return an empty order whose releases are the string RELEASE."""
    return ReleaseOrder(lambda item: item == RELEASE, wait=wait)


def taken(inputs: ReleaseOrder, at: float) -> list:
    """Return every item that may go at ``at``, in order."""
    items = []
    while (item := inputs.take(at)) is not None:
        items.append(item)
    return items


def test_without_a_release_everything_goes_at_once_in_order():
    """Grabs and targets alone never wait."""
    inputs = order()
    inputs.add(['grab', 'target 1', 'target 2'])
    assert taken(inputs, 0.0) == ['grab', 'target 1', 'target 2']
    assert inputs.waiting == 0 and inputs.sent == 0


def test_what_follows_a_release_goes_once_it_is_answered():
    """The release goes; the grab after it waits, for any time short of the wait, then goes."""
    inputs = order()
    inputs.add(['target', RELEASE, 'grab', 'target 2'])
    assert taken(inputs, 5.0) == ['target', RELEASE]
    assert inputs.sent == 1 and inputs.waiting == 2
    assert taken(inputs, 5.0 + 0.999 * ANSWER_WAIT) == []
    inputs.add(['target 3'])
    inputs.answered(1)
    assert taken(inputs, 5.1) == ['grab', 'target 2', 'target 3']


def test_a_release_left_unanswered_lets_what_waits_go_after_the_wait():
    """A node that never answers holds the inputs ``wait`` seconds, no longer."""
    inputs = order(wait=0.25)
    inputs.add([RELEASE, 'grab'])
    assert taken(inputs, 1.0) == [RELEASE]
    assert taken(inputs, 1.0 + 0.2499) == []
    assert taken(inputs, 1.25) == ['grab']


def test_the_answer_to_a_release_given_up_on_frees_nothing_after_a_later_one():
    """Each release has its number: an old answer arriving late does not free a new release."""
    inputs = order(wait=0.25)
    inputs.add([RELEASE, 'grab', RELEASE, 'grab 2'])
    assert taken(inputs, 0.0) == [RELEASE]
    assert taken(inputs, 0.3) == ['grab', RELEASE]
    assert inputs.sent == 2
    inputs.answered(1)
    assert taken(inputs, 0.31) == []
    inputs.answered(2)
    assert taken(inputs, 0.31) == ['grab 2']


def test_each_release_waits_for_its_own_answer():
    """Two releases in a row: the second goes only after the first's answer."""
    inputs = order()
    inputs.add([RELEASE, RELEASE, 'grab'])
    assert taken(inputs, 0.0) == [RELEASE]
    inputs.answered(1)
    assert taken(inputs, 0.0) == [RELEASE]
    inputs.answered(2)
    assert taken(inputs, 0.0) == ['grab']


def test_the_gate_alone_closes_at_a_release_until_its_answer_or_its_wait():
    """What the marker's pacer asks before it lets an input go."""
    gate = ReleaseGate(wait=0.5)
    assert gate.is_open(0.0)
    first = gate.released(1.0)
    assert not gate.is_open(1.0) and not gate.is_open(1.4999)
    gate.answered(first)
    assert gate.is_open(1.1)
    second = gate.released(2.0)
    assert second == first + 1 == gate.sent
    assert not gate.is_open(2.4999) and gate.is_open(2.5)


@pytest.mark.parametrize('wait', [0.0, -1.0, float('nan')])
def test_a_wait_that_is_not_positive_is_refused(wait):
    """A wait of zero or less, or NaN, would let a grab overtake its release."""
    with pytest.raises(ValueError, match='wait must be > 0'):
        ReleaseGate(wait=wait)
    with pytest.raises(ValueError, match='wait must be > 0'):
        order(wait=wait)
