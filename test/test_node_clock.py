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
The node on its own clock: the tick timer's rate, /clock with use_sim_time, jumps and waits.

These are the tests of the real timer path (``NodeClockTicks``): what only it can show. The
simulated clock is advanced by a probe; each advance waits until the node's clock reads it and
its tick timer has run for it (``SimClock``), never a fixed wall time. The one wall-clock test
(the rate on system time) asserts the grid and how the stamps span the time it spun.
"""

import time

from diagnostic_msgs.msg import DiagnosticArray, DiagnosticStatus
from geometry_msgs.msg import PointStamped, PoseStamped, TwistStamped
import numpy as np
from rclpy.parameter import Parameter

from mouse_constraint_ros.node.mouse_constraint_node import MouseConstraintNode
from mouse_constraint_ros.wire.messages import point_message
from test_support.ros_harness import assert_on_grid, SimClock, stamp_of


def start_node(ros, **overrides) -> MouseConstraintNode:
    """Start the node in ``ros``'s context with parameter ``overrides``."""
    node = MouseConstraintNode(context=ros.context, parameter_overrides=[
        Parameter(name, value=value) for name, value in overrides.items()])
    return ros.add(node)


def test_messages_arrive_at_the_rate_with_grid_stamps(ros):
    """
    On system time: pose and twist every tick, stamped t0 + n / rate_hz, pose and twist alike.

    Stamps are the system clock's readings on the grid: from the first pose to the last they
    span the wall time that passed between them, within a tick and the timer's lag.
    """
    node = start_node(ros, rate_hz=200.0)
    poses = ros.collect(PoseStamped, 'pose')
    twists = ros.collect(TwistStamped, 'twist')
    assert ros.spin_until(lambda: len(poses) > 0)
    first_wall = time.time_ns()
    ros.spin_for(2.0)
    assert ros.spin_until(lambda: len(twists) >= len(poses))
    stamps = np.array([stamp_of(m) for m in poses])
    # Every message and no gap: consecutive stamps one period apart (but for the ticks the node
    # counted as dropped, should the machine stall it past its catch-up bound).
    assert_on_grid(stamps, 5_000_000, node.ticker.record.dropped_ticks)
    assert stamps[0] <= first_wall + 5_000_000
    assert len(poses) > 100
    assert [stamp_of(m) for m in twists[:len(poses)]] == list(stamps[:len(twists)])
    assert {m.header.frame_id for m in poses + twists} == {'world'}


def test_the_timer_follows_a_new_rate_at_run_time(ros):
    """A new rate_hz restarts the grid at the new period, on a timer of that period."""
    node = start_node(ros, rate_hz=100.0)
    poses = ros.collect(PoseStamped, 'pose')
    assert ros.spin_until(lambda: len(poses) > 5)
    assert node.ticker.timer.timer_period_ns == 10_000_000
    assert node.set_parameters([Parameter('rate_hz', value=400.0)])[0].successful
    assert node.ticker.timer.timer_period_ns == 2_500_000
    count = len(poses)
    assert ros.spin_until(lambda: len(poses) > count + 310)
    # The last 300 poses all come after the restart, whatever was in flight.
    stamps = np.array([stamp_of(m) for m in poses[-300:]])
    assert_on_grid(stamps, 2_500_000, node.ticker.record.dropped_ticks)


def test_sim_time_driven_by_clock(ros):
    """With use_sim_time the ticks follow /clock: grid stamps, catch-up, and a jump back."""
    node = start_node(ros, rate_hz=100.0, use_sim_time=True)
    poses = ros.collect(PoseStamped, 'pose')
    clock = SimClock(ros, node)
    start = 1_000_000_000_000
    for k in range(50):
        clock.advance_to(start + k * 10_000_000)
    stamps = np.array([stamp_of(m) for m in poses])
    # The first reading starts the grid; every later one runs its one tick.
    np.testing.assert_array_equal(stamps, start + np.arange(50) * 10_000_000)
    # A late clock: the missed ticks are all run, on the grid.
    clock.advance_to(start + 57 * 10_000_000)
    stamps = np.array([stamp_of(m) for m in poses])
    np.testing.assert_array_equal(stamps[50:], start + np.arange(50, 58) * 10_000_000)
    assert node.ticker.record.late_ticks == 7
    # Later than the catch-up bound (0.1 s = 10 ticks): the older ticks are dropped.
    count = len(poses)
    clock.advance_to(start + 100 * 10_000_000)
    stamps = np.array([stamp_of(m) for m in poses[count:]])
    assert node.ticker.record.dropped_ticks == 33
    np.testing.assert_array_equal(stamps, start + np.arange(91, 101) * 10_000_000)
    # The clock jumps back (a replay restarts): no burst, the grid restarts there.
    count = len(poses)
    clock.advance_to(start)
    clock.advance_to(start + 10_000_000)
    new = [stamp_of(m) for m in poses[count:]]
    # rclpy may or may not fire the timer on the backward jump itself; either way one tick each.
    assert new in ([start, start + 10_000_000], [start + 10_000_000])
    assert node.ticker.record.clock_restarts == 1


def test_a_clock_jumping_forwards_restarts_the_grid_and_drops_nothing(ros, capfd):
    """
    use_sim_time, /clock at 100 Hz, then 60 s forwards in one message (a seek), then on.

    A restart of the grid at the new time, counted and warned as one: no tick dropped, none
    said to be missed, the stamps on the new grid from the jump on.
    """
    node = start_node(ros, rate_hz=100.0, use_sim_time=True)
    poses = ros.collect(PoseStamped, 'pose')
    clock = SimClock(ros, node)
    start = 10 ** 12
    for k in range(20):
        clock.advance_to(start + k * 10_000_000)
    jumped = start + 60 * 10 ** 9 + 3_000_000
    for k in range(20):
        clock.advance_to(jumped + k * 10_000_000)
    record = node.ticker.record
    assert (record.dropped_ticks, record.clock_restarts, record.ticks_run) == (0, 1, 40)
    stamps = [stamp_of(m) for m in poses]
    assert stamps[20:] == [jumped + k * 10_000_000 for k in range(20)]
    err = capfd.readouterr().err
    assert 'clock jumped forwards by 59.813000000 s: restarting the tick grid' in err, err
    assert 'cannot keep' not in err


def test_each_warning_reason_has_its_own_throttle(ros, capfd):
    """A foreign-frame target, then the clock jumps 0.5 s: 'cannot keep' is logged too."""
    node = start_node(ros, use_sim_time=True, rate_hz=100.0)
    target = ros.probe.create_publisher(PointStamped, '/target', 10)
    clock = SimClock(ros, node)
    assert ros.spin_until(lambda: target.get_subscription_count() > 0)
    clock.advance_to(10 ** 12)
    target.publish(point_message((0.1, 0.2, 1.0), 'map', 0))
    assert ros.spin_until(lambda: node.refusals[0] == 1)
    clock.advance_to(10 ** 12 + 500_000_000)  # 50 ticks due, 10 run, 40 dropped
    assert node.ticker.record.dropped_ticks == 40
    err = capfd.readouterr().err
    assert "ignoring target in frame 'map'" in err
    assert 'cannot keep 100 Hz: dropped 40 ticks' in err, err


def rate_of(arrays) -> DiagnosticStatus:
    """Return the rate status of the newest diagnostics array."""
    return arrays[-1].status[0]


def test_without_clock_the_node_says_it_waits_then_runs_when_one_comes(ros, capfd):
    """
    use_sim_time and no /clock: a warning and a diagnostics status name the topic, no pose.

    /diagnostics keep coming (steady-clock timer), stamped zero: the node's clock has no time
    yet. Once /clock publishes, ticks run and the status stops waiting.
    """
    node = start_node(ros, rate_hz=100.0, use_sim_time=True, diagnostics_rate_hz=10.0,
                      marker_rate_hz=0.0)
    poses = ros.collect(PoseStamped, 'pose')
    arrays = ros.collect(DiagnosticArray, '/diagnostics')
    assert ros.spin_until(lambda: len(arrays) >= 5, timeout=20.0)
    topic = node.resolve_topic_name('/clock')
    status = rate_of(arrays)
    assert status.level == DiagnosticStatus.WARN
    assert f'waiting for /clock on {topic}' in status.message
    assert {stamp_of(a) for a in arrays} == {0}
    assert poses == [] and node.ticker.record.ticks_run == 0
    assert ros.spin_until(lambda: f'waiting for /clock on {topic}' in capfd.readouterr().err,
                          timeout=10.0)
    clock = SimClock(ros, node)
    start = 7_000_000_000
    for k in range(30):
        clock.advance_to(start + k * 10_000_000)
    assert ros.spin_until(lambda: len(poses) == 30)
    assert stamp_of(poses[0]) == start
    count = len(arrays)
    assert ros.spin_until(lambda: len(arrays) > count + 1, timeout=10.0)
    assert 'waiting' not in rate_of(arrays).message
    assert stamp_of(arrays[-1]) >= start


def test_switching_use_sim_time_off_restarts_the_grid_without_drops(ros, capfd):
    """From simulated to system time the clock leaps forwards: a restart, no ticks dropped."""
    node = start_node(ros, rate_hz=100.0, use_sim_time=True, diagnostics_rate_hz=10.0)
    poses = ros.collect(PoseStamped, 'pose')
    arrays = ros.collect(DiagnosticArray, '/diagnostics')
    clock = SimClock(ros, node)
    for k in range(20):
        clock.advance_to(5 * 10 ** 9 + k * 10_000_000)
    assert node.ticker.record.ticks_run == 20
    assert node.set_parameters([Parameter('use_sim_time', value=False)])[0].successful
    count = len(poses)
    assert ros.spin_until(lambda: len(poses) > count + 20, timeout=10.0)
    assert node.ticker.record.dropped_ticks == 0 and node.ticker.record.clock_restarts == 1
    assert stamp_of(poses[-1]) > 10 ** 18  # system time now
    count = len(arrays)
    assert ros.spin_until(lambda: len(arrays) > count + 2, timeout=10.0)
    values = {kv.key: kv.value for kv in rate_of(arrays).values}
    assert values['dropped ticks since start'] == '0'
    err = capfd.readouterr().err
    assert 'clock changed to system time: restarting the tick grid' in err
    assert 'cannot keep' not in err


def test_a_negative_clock_is_ignored_with_one_warning(ros, capfd):
    """
    use_sim_time and a /clock of -1 s (``ros2 topic pub --once /clock ... {sec: -1}``).

    rclpy's own time source raises on it inside the executor, which ended the node; the node
    ignores it with one warning, the clock stays where it was, and the next valid /clock
    drives the ticks as before. use_sim_time switched off and on again keeps the guard.
    """
    node = start_node(ros, rate_hz=100.0, use_sim_time=True)
    poses = ros.collect(PoseStamped, 'pose')
    clock = SimClock(ros, node)
    clock.advance_to(5 * 10 ** 9)
    for count in range(1, 4):
        clock.publish(-1, 0)
        assert ros.spin_until(lambda: node._time_source.ignored == count)
    assert node.get_clock().now().nanoseconds == 5 * 10 ** 9
    clock.advance_to(5_500_000_000)
    assert stamp_of(poses[-1]) == 5_500_000_000
    assert node.set_parameters([Parameter('use_sim_time', value=False)])[0].successful
    assert node.set_parameters([Parameter('use_sim_time', value=True)])[0].successful
    clock.publish(-2, 0)
    clock.advance_to(6 * 10 ** 9)
    err = capfd.readouterr().err
    assert err.count('ignoring /clock -1 s 0 ns') == 1, err
    assert 'the clock stays where it was' in err and 'Traceback' not in err
