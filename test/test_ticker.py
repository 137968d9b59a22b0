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

"""The Ticker: one owner of which driver runs the ticks, the node's time, pause and rates."""

import pytest
from rclpy.parameter import Parameter

from mouse_constraint_ros.node.mouse_constraint_node import MouseConstraintNode
from mouse_constraint_ros.node.ticker import Driver

MS = 1_000_000


def test_a_node_on_its_own_clock_is_not_the_clock_and_refuses_step(ros):
    """The node's clock drives a timer; step() is for a node stepped by its caller."""
    node = ros.add(MouseConstraintNode(context=ros.context, parameter_overrides=[
        Parameter('rate_hz', value=200.0)]))
    ticker = node.ticker
    assert ticker.driver is Driver.NODE_CLOCK and not ticker.is_clock
    assert ticker.timer.timer_period_ns == 5 * MS
    assert ticker.waiting_for_clock() is None
    with pytest.raises(RuntimeError, match='stepped=True'):
        ticker.step()


def test_publish_clock_at_run_time_makes_the_node_the_clock_and_back(ros):
    """The simulated clock's pacing timer replaces the node-clock timer, and the reverse."""
    node = ros.add(MouseConstraintNode(context=ros.context, parameter_overrides=[
        Parameter('rate_hz', value=200.0)]))
    ticker = node.ticker
    node_timer = ticker.timer
    assert node.set_parameters([Parameter('publish_clock', value=True)])[0].successful
    assert ticker.driver is Driver.SIMULATED_CLOCK and ticker.is_clock
    assert ticker.timer is not node_timer and ticker.now_ns() == 0
    assert ros.spin_until(lambda: ticker.now_ns() >= 10 * MS)
    # The simulated time is on the grid of 200 Hz.
    assert ticker.now_ns() % (5 * MS) == 0
    assert node.set_parameters([Parameter('publish_clock', value=False)])[0].successful
    assert ticker.driver is Driver.NODE_CLOCK and not ticker.is_clock
    assert ticker.now_ns() > 1_000_000_000  # system time again


def test_a_stepped_node_runs_one_tick_per_step_unless_paused(simulated_body_factory):
    """Each step is one tick of the simulated clock; paused, none; resuming counts."""
    body = simulated_body_factory(rate_hz=100.0)
    ticker = body.node.ticker
    assert ticker.driver is Driver.CALLER and ticker.is_clock and ticker.timer is None
    body.step(3)
    assert ticker.now_ns() == 30 * MS and ticker.record.ticks_run == 3
    assert ticker.set_paused(True) and not ticker.set_paused(True)
    assert ticker.step() is False and ticker.now_ns() == 30 * MS
    ticker.step_once()
    assert ticker.now_ns() == 40 * MS and ticker.record.ticks_run == 4
    assert ticker.set_paused(False) and ticker.resumes == 1
    assert ticker.step() is True and ticker.now_ns() == 50 * MS


def test_a_new_rate_goes_on_from_the_time_reached(simulated_body_factory):
    """A rate change starts a new grid at the simulated time reached; dt follows at once."""
    body = simulated_body_factory(rate_hz=100.0)
    ticker = body.node.ticker
    body.step(3)
    body.set_parameters(rate_hz=50.0)
    assert ticker.rate_hz == 50.0 and ticker.record.dt == 0.02
    body.step(2)
    assert ticker.now_ns() == 70 * MS
