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
The tick a spin loop runs itself: ``LoopTimer``'s schedule, ``spin_until``'s pace, the node.

The schedule is an rclpy timer's (calls at start + k period, overrun periods skipped), read on
a clock the test sets. A node served by its own loop (``loop_ticks``: ``NodeRun.serve`` with a
pace, as the executable serves it) runs its ticks with no rclpy timer: a test of that wall-clock
path, on system time; a tick it takes late runs at once, before the callbacks queued
meanwhile.
"""

import time

from geometry_msgs.msg import PointStamped
import pytest
from rclpy.experimental import EventsExecutor
from rclpy.parameter import Parameter

from mouse_constraint_ros.node.mouse_constraint_node import main, MouseConstraintNode
from mouse_constraint_ros.node.ticker import Driver
from mouse_constraint_ros.timing.loop_timer import LoopTimer
from mouse_constraint_ros.timing.spin import NodeRun, spin_until, SpinEnd, StopRequest
from mouse_constraint_ros.wire.messages import point_message

MS = 1_000_000


class SetClock:
    """A steady clock that reads what the test sets (ns)."""

    def __init__(self, now: int) -> None:
        self.now = now

    def __call__(self) -> int:
        return self.now


def test_calls_fall_on_the_grid_of_the_start_and_overrun_periods_are_skipped():
    """Due at start + k period; a call late by 2.5 periods is one call, the next on the grid."""
    clock = SetClock(1_000 * MS)
    timer = LoopTimer(4 * MS, now_ns=clock)
    assert timer.timer_period_ns == 4 * MS and timer.time_until_next_call() == 4 * MS
    clock.now += 4 * MS - 1
    assert not timer.take() and timer.time_until_next_call() == 1
    clock.now += 1
    assert timer.take() and not timer.take()
    assert timer.late_ns == 0
    assert timer.time_until_next_call() == 4 * MS
    clock.now += 4 * MS + 10 * MS  # the call at 1008 ms runs at 1018 ms
    assert timer.take() and not timer.take()
    assert timer.late_ns == 10 * MS
    assert timer.time_until_next_call() == 2 * MS  # next on the grid: 1020 ms
    clock.now += 2 * MS + 2 * MS - 1  # 1020 ms, 2 ms - 1 ns late
    assert timer.take() and timer.late_ns == 2 * MS - 1
    clock.now += 4 * MS + 1  # 1024 ms, half a period late
    assert timer.take() and timer.late_ns == 2 * MS


@pytest.mark.parametrize('period', [0, -1])
def test_a_period_that_is_not_positive_is_refused(period):
    with pytest.raises(ValueError, match='period_ns must be > 0'):
        LoopTimer(period)


class RecordingExecutor:
    """An executor stand-in that records each spin_once timeout; the pace ends the loop."""

    def __init__(self, context) -> None:
        self.context = context
        self.timeouts = []

    def spin_once(self, timeout_sec: float) -> None:
        self.timeouts.append(timeout_sec)


def test_the_pace_bounds_each_wait_and_runs_before_it(ros):
    """spin_once waits until the pace's next call (not below 0), at most the poll period."""
    executor = RecordingExecutor(ros.context)
    paces = iter([0.002, None, -0.001, 1.0, 0.0005])
    stop = StopRequest()

    def pace():
        try:
            return next(paces)
        except StopIteration:
            stop.signal = 2
            return None

    assert spin_until(executor, stop, pace=pace, period=0.05) is SpinEnd.STOPPED
    # The stop the last pace asks for is seen before the next spin, after its own.
    assert executor.timeouts == [0.002, 0.05, 0.0, 0.05, 0.0005, 0.05]


@pytest.fixture
def loop_node(ros):
    """Yield a node with loop_ticks at 200 Hz and an EventsExecutor it is added to."""
    node = MouseConstraintNode(context=ros.context, loop_ticks=True, parameter_overrides=[
        Parameter('rate_hz', value=200.0)])
    executor = EventsExecutor(context=ros.context)
    executor.add_node(node)
    yield node, executor
    executor.shutdown()
    node.destroy_node()


def test_a_node_served_by_its_loop_ticks_at_its_rate_with_no_rclpy_timer(loop_node):
    """
    loop_ticks: the ticks are run_due's, on the rate's grid, none before its time.

    The loop runs until 100 ticks ran: their stamps lie on the 5 ms grid, the last not after
    the node's clock, and every grid tick between the first and the last was run or counted as
    dropped (a process kept off the core past the catch-up bound drops ticks, and says so).
    How many ticks a second the executable sustains is the machine's: ``make bench``
    (``bench.node_rate``).
    """
    node, executor = loop_node
    ticker = node.ticker
    record = ticker.record
    assert ticker.driver is Driver.NODE_CLOCK and type(ticker.timer) is LoopTimer
    assert ticker.timer.timer_period_ns == 5 * MS
    assert not node.timers or all(t.timer_period_ns != 5 * MS for t in node.timers)
    # Unpaced, nobody runs the ticks.
    spin_until(executor, StopRequest(), deadline=time.monotonic() + 0.1)
    assert record.ticks_run == 0

    def run_until(ticks: int) -> None:
        ended = spin_until(executor, StopRequest(), deadline=time.monotonic() + 60.0,
                           condition=lambda: record.ticks_run >= ticks, pace=ticker.run_due)
        assert ended is SpinEnd.CONDITION

    run_until(1)
    first, ran_before = record.stamp_ns, record.ticks_run
    handled_before = record.ticks_run + record.dropped_ticks
    run_until(ran_before + 100)
    now = node.get_clock().now().nanoseconds
    span = record.stamp_ns - first
    ran = record.ticks_run - ran_before
    handled = record.ticks_run + record.dropped_ticks - handled_before
    assert span % (5 * MS) == 0 and record.stamp_ns <= now
    assert ran * 5 * MS <= span <= handled * 5 * MS, (ran, handled, span)


def test_a_late_loop_call_runs_its_tick_before_the_messages_queued_meanwhile(ros):
    """
    The spin loop's tick, late behind a burst of targets, runs at once: the tick comes first.

    The node as its executable serves it (``loop_ticks``, an EventsExecutor), 100 Hz: a burst
    of 50 targets waits in the executor's queue when the loop's call comes 30 ms late. The
    call runs its ticks then and there; the targets are taken after it. A call posted behind
    them would wait for all of them, and under a flood for as many as keep coming: ticks later
    than the catch-up bound are dropped.
    """
    node = MouseConstraintNode(context=ros.context, loop_ticks=True, parameter_overrides=[
        Parameter('rate_hz', value=100.0), Parameter('marker_rate_hz', value=0.0),
        Parameter('diagnostics_rate_hz', value=0.0)])
    executor = EventsExecutor(context=ros.context)
    executor.add_node(node)
    try:
        target = ros.probe.create_publisher(PointStamped, '/target', 100)
        record = node.ticker.record

        def serve(condition) -> None:
            deadline = time.monotonic() + 10.0
            while not condition():
                assert time.monotonic() < deadline
                node.ticker.run_due()
                executor.spin_once(timeout_sec=0.001)
                ros.executor.spin_once(timeout_sec=0.0)

        serve(lambda: record.ticks_run > 3 and target.get_subscription_count() > 0)
        for k in range(50):
            target.publish(point_message((0.01 * k, 0.0, 1.0), 'world', 0))
        # Not a wait: the burst is in the node's reader once published (one participant), and
        # the loop's call comes 30 ms late, its ticks due: the case under test.
        time.sleep(0.03)
        ran, refused = record.ticks_run, node.refusals[0]
        node.ticker.run_due()
        assert record.ticks_run > ran
        serve(lambda: node.simulation.target == (0.49, 0.0, 1.0))
        assert node.refusals[0] == refused
    finally:
        executor.shutdown()
        node.destroy_node()


def test_a_new_publish_rate_keeps_the_loop_timer_on_its_batch(ros):
    """publish_rate_hz 100 at 1 kHz: one call per 10 ticks, still the loop's."""
    node = MouseConstraintNode(context=ros.context, loop_ticks=True, parameter_overrides=[
        Parameter('rate_hz', value=1000.0)])
    try:
        assert node.set_parameters([Parameter('publish_rate_hz', value=100.0)])[0].successful
        assert type(node.ticker.timer) is LoopTimer
        assert node.ticker.timer.timer_period_ns == 10 * MS
    finally:
        node.destroy_node()


def test_use_sim_time_hands_the_ticks_to_an_rclpy_timer_that_clock_drives(loop_node):
    """The loop's call that finds simulated time switches to a timer on /clock."""
    node, executor = loop_node
    ticker = node.ticker
    assert node.set_parameters([Parameter('use_sim_time', value=True)])[0].successful
    handed_over = spin_until(executor, StopRequest(), deadline=time.monotonic() + 5.0,
                             condition=lambda: type(ticker.timer) is not LoopTimer,
                             pace=ticker.run_due)
    assert handed_over is SpinEnd.CONDITION
    assert ticker.timer in node.timers and ticker.run_due() is None
    assert ticker.timer.timer_period_ns == 5 * MS
    assert ticker.waiting_for_clock() is not None


@pytest.mark.ros
def test_the_executable_serves_its_node_from_its_loop(monkeypatch):
    """``main`` makes the node with loop_ticks and serves it with ``run_due`` as the pace."""
    served = []

    def serve(run, pace=None):
        served.append((type(run.node.ticker.timer), pace == run.node.ticker.run_due))
        return 0

    monkeypatch.setattr(NodeRun, 'serve', serve)
    assert main(['mouse_constraint_node']) == 0
    assert served == [(LoopTimer, True)]
