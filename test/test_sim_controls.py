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

"""The node as the clock (publish_clock, real_time_factor), ~/pause and ~/step."""

import contextlib
import signal
import subprocess
import sys
import time

from diagnostic_msgs.msg import DiagnosticArray
from geometry_msgs.msg import PoseStamped, WrenchStamped
import numpy as np
import pytest
from rcl_interfaces.msg import Parameter as ParameterMessage, ParameterType, ParameterValue
from rcl_interfaces.srv import SetParameters
from rclpy.node import Node
from rclpy.parameter import Parameter
from rosgraph_msgs.msg import Clock
from std_srvs.srv import SetBool, Trigger

from mouse_constraint_ros.node import clock_ticks
from mouse_constraint_ros.node.mouse_constraint_node import (CLOCK_LOOP, MouseConstraintNode,
                                                             StartupRefusal)
from mouse_constraint_ros.timing.sim_clock import SimulatedClock
from test_support.ros_harness import assert_on_grid

MS = 1_000_000
S = 1_000_000_000


# The pacing alone, on a wall clock given by hand.

def run(clock: SimulatedClock, wall_ns: int) -> int:
    """Run every tick due at ``wall_ns``; return how many."""
    count = clock.due(wall_ns)
    for _ in range(count):
        clock.advance()
    return count


def test_the_clock_paces_ticks_at_the_factor_on_an_exact_grid():
    """At factor 4 and 1 kHz, 1 s of wall time runs 4000 ticks, tick n at n ms."""
    clock = SimulatedClock(1000.0, 4.0, max_lag=0.1)
    assert clock.now_ns == 0 and run(clock, 5 * S) == 0  # the first call anchors
    for step in range(1, 1001):
        run(clock, 5 * S + step * MS)
    assert clock.ticks == 4000 and clock.now_ns == 4 * S
    assert [clock.stamp(n) for n in (1, 2, 3)] == [MS, 2 * MS, 3 * MS]


def test_a_new_factor_goes_on_from_the_time_the_clock_reads():
    """Changing the factor moves no simulated time; the new pace holds from there on."""
    clock = SimulatedClock(100.0, 2.0, max_lag=10.0)
    run(clock, 0)
    run(clock, S)
    before = clock.now_ns
    clock.set_real_time_factor(0.5)
    assert clock.now_ns == before and run(clock, S) == 0
    run(clock, 3 * S)
    assert clock.now_ns == before + S


def test_pause_stops_the_clock_and_resume_catches_nothing_up():
    """Paused, nothing is due; after a resume the pace starts where the clock stood."""
    clock = SimulatedClock(1000.0, 1.0, max_lag=10.0)
    run(clock, 0)
    run(clock, S)
    clock.pause()
    assert run(clock, 10 * S) == 0
    assert clock.advance() == S + MS  # a step while paused
    clock.resume()
    assert run(clock, 10 * S) == 0
    assert run(clock, 10 * S + 3 * MS) == 3


def test_a_clock_that_cannot_keep_up_slips_instead_of_skipping():
    """More than max_lag of due ticks: the kept ones run on the grid, the rest is given up."""
    clock = SimulatedClock(1000.0, 1.0, max_lag=0.1)
    run(clock, 0)
    assert run(clock, 2 * S) == 100
    assert clock.now_ns == 100 * MS and clock.slipped_ns == 2 * S - 100 * MS
    assert run(clock, 2 * S + MS) == 1


def test_factor_zero_has_no_bound_and_a_new_rate_starts_at_the_reading():
    """Factor 0: any number of ticks is due; a new rate's grid starts where the clock is."""
    clock = SimulatedClock(1000.0, 0.0, max_lag=0.1)
    assert clock.due(0) is None
    for _ in range(3):
        clock.advance()
    clock.set_rate(400.0)
    assert clock.advance() == 3 * MS + 2_500_000


# The node.

def start_node(ros, namespace='', **overrides) -> MouseConstraintNode:
    """Start the node in ``ros``'s context, in ``namespace``, with parameter ``overrides``."""
    return ros.add(MouseConstraintNode(context=ros.context, namespace=namespace,
                                       parameter_overrides=[
                                           Parameter(name, value=value)
                                           for name, value in overrides.items()]))


def stamp_ns(stamp) -> int:
    """Return a builtin_interfaces/Time in nanoseconds."""
    return stamp.sec * S + stamp.nanosec


@contextlib.contextmanager
def node_process(*arguments: str):
    """
    Run the node as its own process (its EventsExecutor, as installed) with ``arguments``.

    For the pacing tests: in-process, the test's executor would share the node's core.
    """
    process = subprocess.Popen([sys.executable, '-m',
                                'mouse_constraint_ros.node.mouse_constraint_node', '--ros-args',
                                *arguments], stdout=subprocess.DEVNULL, stderr=subprocess.PIPE,
                               text=True)
    try:
        yield process
    finally:
        process.send_signal(signal.SIGINT)
        process.wait(timeout=10.0)


@pytest.mark.system
def test_publish_clock_runs_four_times_real_time_in_a_namespace(ros):
    """
    /clock advances 4 s per wall second, monotonically; poses are stamped with its values.

    The factor is the node's own, measured on its wall clock over each half second between
    its /diagnostics (the median of those windows): what this process reads of /clock as it
    comes measures this process too, which lags on a loaded machine (printed, not asserted).
    In a namespace: /clock is absolute, pose relative. A second node with use_sim_time
    follows the published time.
    """
    rate = 250.0
    arrays = ros.collect(DiagnosticArray, '/diagnostics')
    with node_process('-r', '__ns:=/fast', '-p', 'publish_clock:=true',
                      '-p', 'real_time_factor:=4.0', '-p', f'rate_hz:={rate}',
                      '-p', 'diagnostics_rate_hz:=2.0'):
        clocks, poses, follower, first, advanced, wall = run_four_times(ros)
    values = np.array([stamp_ns(c.clock) for c in clocks])
    factors = achieved_factors(arrays)
    print(f'/clock advanced {advanced:.3f} s in {wall:.3f} s of wall time as read here '
          f'({advanced / wall:.3f}x); the node achieved {factors}')
    assert len(factors) >= 3 and np.median(factors) == pytest.approx(4.0, rel=0.05)
    assert np.all(np.diff(values) > 0)
    period = round(1e9 / rate)
    stamps = np.array([stamp_ns(p.header.stamp) for p in poses])
    assert len(stamps) > 0.9 * len(values) and np.all(stamps % period == 0)
    # The pose and /clock subscriptions match at their own times: poses from before the first
    # /clock seen have no value to be among.
    assert set(stamps[stamps >= values[0]]) <= set(values)
    follower_now = follower.get_clock().now().nanoseconds
    # A /clock value (on the 4 ms grid, from within the run); its subscription may have taken
    # a later one than the collector did before the node ended.
    assert follower_now % period == 0 and follower_now >= values[first]


def achieved_factors(arrays) -> list:
    """Return the achieved real time factors the node's /diagnostics reported, in order."""
    return [float(value.value) for array in arrays for status in array.status
            if status.name.endswith(': simulator') for value in status.values
            if value.key == 'achieved real time factor' and value.value != 'n/a']


def run_four_times(ros):
    """Collect /clock and /fast/pose for 2 s of wall time; a follower takes use_sim_time."""
    follower = ros.add(Node('follower', context=ros.context, parameter_overrides=[
        Parameter('use_sim_time', value=True)]))
    clocks = ros.collect(Clock, '/clock', depth=10000)
    poses = ros.collect(PoseStamped, '/fast/pose', depth=10000)
    assert ros.spin_until(lambda: len(clocks) > 10 and len(poses) > 10)
    first, started = len(clocks), time.monotonic()
    start_value = stamp_ns(clocks[-1].clock)
    ros.spin_for(2.0)
    wall = time.monotonic() - started
    # What came within the 2 s, read once they are all in.
    end_value = stamp_ns(clocks[-1].clock)
    ros.spin_for(0.3)
    return clocks, poses, follower, first, (end_value - start_value) * 1e-9, wall


@pytest.mark.system
def test_factor_zero_runs_as_fast_as_it_can(ros):
    """
    real_time_factor 0 at 1 kHz: unpaced, at least twice real time, as /diagnostics reports it.

    How much faster is the machine's (4x to 20x here, the less with another process keeping a
    core busy): the factor reached is printed; ``make bench`` measures speed. Nothing
    subscribes /clock or pose, which would measure the subscriber.
    """
    arrays = ros.collect(DiagnosticArray, '/diagnostics')
    with node_process('-p', 'publish_clock:=true', '-p', 'real_time_factor:=0.0',
                      '-p', 'diagnostics_rate_hz:=2.0'):
        assert ros.spin_until(lambda: len(achieved_factors(arrays)) >= 3, timeout=20.0)
    factors = achieved_factors(arrays)
    print(f'real_time_factor 0 at 1 kHz reached {factors}x real time')
    assert max(factors[1:]) >= 2.0


def test_pause_stops_clock_and_poses_step_runs_one_tick_resume_does_not_burst(ros):
    """Paused: /clock and pose stamps stand still; ~/step: exactly one tick; resume: paced."""
    rate = 200.0
    start_node(ros, publish_clock=True, rate_hz=rate, marker_rate_hz=0.0)
    clocks = ros.collect(Clock, '/clock', depth=10000)
    poses = ros.collect(PoseStamped, 'pose', depth=10000)
    assert ros.spin_until(lambda: len(poses) > 10)
    response = ros.call(Trigger, '/mouse_constraint/step', Trigger.Request())
    assert not response.success and 'pause it first' in response.message
    assert ros.call(SetBool, '/mouse_constraint/pause', SetBool.Request(data=True)).success
    ros.drain()
    held = (len(clocks), len(poses))
    ros.spin_for(0.5)
    assert (len(clocks), len(poses)) == held
    last = stamp_ns(poses[-1].header.stamp)
    period = round(1e9 / rate)
    assert ros.call(Trigger, '/mouse_constraint/step', Trigger.Request()).success
    assert ros.spin_until(lambda: len(poses) > held[1])
    ros.spin_for(0.1)
    assert len(poses) == held[1] + 1 and len(clocks) == held[0] + 1
    assert stamp_ns(poses[-1].header.stamp) == stamp_ns(clocks[-1].clock) == last + period
    assert ros.call(SetBool, '/mouse_constraint/pause', SetBool.Request(data=False)).success
    resumed, started = len(poses), time.monotonic()
    ros.spin_for(0.5)
    wall = time.monotonic() - started
    # No catch-up of the 0.6 s paused: the stamps after the resume go on from the step's, one
    # period apart, and span no more simulated time than the wall time since (factor 1), where
    # a burst would have added the 0.6 s paused (120 ticks) at once.
    stamps = np.array([stamp_ns(p.header.stamp) for p in poses[held[1]:]])
    np.testing.assert_array_equal(np.diff(stamps), period)
    assert len(poses) > resumed
    assert (stamps[-1] - stamps[1]) * 1e-9 <= wall + 2.0 / rate


def test_pause_without_publish_clock_holds_the_physics_and_restarts_the_grid(ros):
    """On the node's clock: paused, no pose; resumed, stamps jump to now, then one per tick."""
    rate = 200.0
    node = start_node(ros, rate_hz=rate, marker_rate_hz=0.0)
    poses = ros.collect(PoseStamped, 'pose', depth=10000)
    assert ros.spin_until(lambda: len(poses) > 10)
    assert ros.call(SetBool, '/mouse_constraint/pause', SetBool.Request(data=True)).success
    ros.spin_for(0.05)
    held, state = len(poses), node.simulation.state
    ros.spin_for(0.5)
    assert len(poses) == held and node.simulation.state == state
    paused_at = stamp_ns(poses[-1].header.stamp)
    assert ros.call(SetBool, '/mouse_constraint/pause', SetBool.Request(data=False)).success
    started = time.monotonic()
    ros.spin_for(0.5)
    wall = time.monotonic() - started
    after = np.array([stamp_ns(p.header.stamp) for p in poses[held:]])
    assert after[0] - paused_at > 0.5 * S
    assert_on_grid(after, round(1e9 / rate), node.ticker.record.dropped_ticks)
    # Ticks go on (a loaded machine may run fewer of them) and none catches up the paused time:
    # the stamps after the resume span no more than the wall time since it.
    assert len(after) > 0.1 * wall * rate
    assert after[-1] - after[0] <= wall * S


def test_a_reset_while_paused_on_the_node_s_clock_has_a_stamp_of_its_own(ros):
    """On the node's clock, paused: ~/reset's pose is stamped after the paused tick's."""
    start_node(ros, rate_hz=200.0, marker_rate_hz=0.0)
    poses = ros.collect(PoseStamped, 'pose', depth=10000)
    assert ros.spin_until(lambda: len(poses) > 10)
    assert ros.call(SetBool, '/mouse_constraint/pause', SetBool.Request(data=True)).success
    ros.drain()
    held = len(poses)
    assert ros.call(Trigger, '/mouse_constraint/reset', Trigger.Request()).success
    assert ros.spin_until(lambda: len(poses) > held)
    assert stamp_ns(poses[held].header.stamp) > stamp_ns(poses[held - 1].header.stamp)


def test_pause_step_and_resume_in_lockstep(simulated_body_factory):
    """
    ~/pause from another node: ticks run no physics, the clock stands still; ~/step: one tick.

    Resumed, the clock goes on from where it stood: no tick catches up the paused ones.
    """
    body = simulated_body_factory(rate_hz=200.0)
    caller = body.add_node(Node('caller', context=body.context))
    pause = caller.create_client(SetBool, '/mouse_constraint/pause')
    step = caller.create_client(Trigger, '/mouse_constraint/step')

    def call(client, request):
        future = client.call_async(request)
        body.drain()
        return future.result()

    body.step(10)
    refused = call(step, Trigger.Request())
    assert not refused.success and 'pause it first' in refused.message
    assert call(pause, SetBool.Request(data=True)).message == 'paused at 0.050000 s simulated'
    state, pose = body.node.simulation.state, body.pose.message
    body.step(100)
    assert body.node.ticker.paused and body.time == 0.05
    assert body.node.simulation.state is state and body.pose.message is pose
    assert call(step, Trigger.Request()).message == 'one tick of 0.005 s, to 0.055000 s simulated'
    assert body.time == pytest.approx(0.055, abs=1e-12) and body.pose.time == body.time
    assert call(pause, SetBool.Request(data=False)).message == 'running from 0.055000 s simulated'
    body.step(10)
    assert body.time == pytest.approx(0.105, abs=1e-12) and body.node.ticker.record.ticks_run == 21


def test_a_reset_while_paused_publishes_the_state_it_leaves(simulated_body_factory):
    """
    Paused with the body fallen: ~/reset publishes the initial pose at once, no tick run.

    The reset's state has a stamp of its own, one tick after the paused tick's (the simulated
    clock moves on to it, /clock says so): a reader keyed by stamp, as tf2 is, takes it rather
    than dropping it as a repeat; the ticks after the resume go on from it.
    """
    body = simulated_body_factory(rate_hz=200.0, hold_initial_anchor=False)
    caller = body.add_node(Node('caller', context=body.context))
    pause = caller.create_client(SetBool, '/mouse_constraint/pause')
    poses = []
    caller.create_subscription(PoseStamped, 'pose', poses.append, 10)
    body.step(40)
    future = pause.call_async(SetBool.Request(data=True))
    body.drain()
    assert future.result().success
    fallen, count, ticks = body.pose, len(poses), body.node.ticker.record.ticks_run
    assert fallen.position[2] < 0.99
    body.reset()
    assert len(poses) == count + 1 and body.node.ticker.record.ticks_run == ticks
    reset = poses[-1]
    assert (reset.pose.position.x, reset.pose.position.y, reset.pose.position.z) == (
        0.0, 0.0, 1.0)
    period = round(1e9 / 200.0)
    paused_stamp = stamp_ns(fallen.message.header.stamp)
    assert stamp_ns(reset.header.stamp) == paused_stamp + period
    assert round(body.time * 1e9) == paused_stamp + period
    future = pause.call_async(SetBool.Request(data=False))
    body.drain()
    assert future.result().success
    body.step(3)
    stamps = [stamp_ns(pose.header.stamp) for pose in poses[count - 1:]]
    assert np.all(np.diff(stamps) == period) and len(stamps) == 5


def test_a_reset_while_paused_publishes_no_force(simulated_body_factory):
    """
    With publish_force: the reset's state goes out at a stamp of its own, without a force.

    No tick ran: there is no reaction to send, and a zero force would tell a device that the
    body let go.
    """
    body = simulated_body_factory(rate_hz=200.0, publish_force=True)
    caller = body.add_node(Node('caller', context=body.context))
    pause = caller.create_client(SetBool, '/mouse_constraint/pause')
    poses, forces = [], []
    caller.create_subscription(PoseStamped, 'pose', poses.append, 10)
    caller.create_subscription(WrenchStamped, 'force', forces.append, 10)
    body.step(40)
    future = pause.call_async(SetBool.Request(data=True))
    body.drain()
    assert future.result().success and len(forces) == len(poses) == 40
    weight = forces[-1].wrench.force.z
    assert weight < -1.0
    body.reset()
    assert len(poses) == 41 and len(forces) == 40
    assert forces[-1].wrench.force.z == weight
    assert stamp_ns(poses[-1].header.stamp) > stamp_ns(forces[-1].header.stamp)


def test_a_step_on_a_clock_that_stands_still_is_refused(ros):
    """
    use_sim_time, paused, /clock at 5 s: one step at 5 s; the next is refused until it moves.

    A step is stamped with the node's clock: on a /clock that stands still a second step would
    publish a second state of the same stamp.
    """
    node = start_node(ros, use_sim_time=True, rate_hz=100.0, marker_rate_hz=0.0,
                      diagnostics_rate_hz=0.0)
    poses = ros.collect(PoseStamped, 'pose')
    clock = ros.probe.create_publisher(Clock, '/clock', 10)
    assert ros.call(SetBool, '/mouse_constraint/pause', SetBool.Request(data=True)).success

    def clock_at(seconds: int, nanoseconds: int = 0) -> None:
        message = Clock()
        message.clock.sec, message.clock.nanosec = seconds, nanoseconds
        clock.publish(message)
        assert ros.spin_until(
            lambda: node.get_clock().now().nanoseconds == seconds * S + nanoseconds)

    def step():
        return ros.call(Trigger, '/mouse_constraint/step', Trigger.Request())

    clock_at(5)
    assert step().success
    assert ros.spin_until(lambda: len(poses) == 1)
    refused = step()
    assert not refused.success and refused.message == (
        "the node's clock stands at 5.000000000 s, the stamp of the latest tick: a step would "
        'publish a second state of that stamp; step once the clock moves on')
    clock_at(5, 10 * MS)
    assert step().success
    assert ros.spin_until(lambda: len(poses) == 2)
    ros.spin_for(0.1)
    assert [stamp_ns(pose.header.stamp) for pose in poses] == [5 * S, 5 * S + 10 * MS]


def test_publish_clock_with_use_sim_time_is_refused(ros):
    """At start (StartupRefusal with the reason) and at run time, either way round."""
    with pytest.raises(StartupRefusal, match='cannot follow the clock it publishes'):
        MouseConstraintNode(context=ros.context, parameter_overrides=[
            Parameter('publish_clock', value=True), Parameter('use_sim_time', value=True)])
    node = start_node(ros, publish_clock=True)
    result = node.set_parameters([Parameter('use_sim_time', value=True)])[0]
    assert not result.successful and result.reason == CLOCK_LOOP
    assert not node.get_clock().ros_time_is_active


class SetWall:
    """The steady clock the node's pacing reads (ns): it stands until the test moves it."""

    def __init__(self, now: int) -> None:
        self.now = now
        self.reads = 0

    def monotonic_ns(self) -> int:
        self.reads += 1
        return self.now


def test_the_factor_changes_at_run_time_without_a_jump(ros, monkeypatch):
    """
    ros2 param set real_time_factor: /clock goes on from where it stood, at the new pace.

    In lockstep with the wall clock the pacing reads, which the test moves: each step of it
    makes the ticks due, and the test spins until /clock shows the last of them. At factor 1,
    80 ms of wall time are 80 ms of /clock; after the change, 1 s of wall time is 3 s of
    /clock on from the value it stood at, every value 4 ms after the one before.
    """
    wall = SetWall(10 * S)
    monkeypatch.setattr(clock_ticks, 'time', wall)
    start_node(ros, publish_clock=True, rate_hz=250.0, real_time_factor=1.0,
               marker_rate_hz=0.0)
    clocks = ros.collect(Clock, '/clock', depth=10000)

    def step_wall(wall_ns: int, clock_ns: int) -> None:
        wall.now += wall_ns
        assert ros.spin_until(lambda: clocks and stamp_ns(clocks[-1].clock) == clock_ns), (
            wall.now, stamp_ns(clocks[-1].clock) if clocks else None)

    assert ros.spin_until(lambda: wall.reads > 0)  # the pacing starts at this wall time
    step_wall(80 * MS, 80 * MS)
    client = ros.probe.create_client(SetParameters, '/mouse_constraint/set_parameters')
    assert client.wait_for_service(timeout_sec=5.0)
    value = ParameterValue(type=ParameterType.PARAMETER_DOUBLE, double_value=3.0)
    future = client.call_async(SetParameters.Request(parameters=[
        ParameterMessage(name='real_time_factor', value=value)]))
    assert ros.spin_until(future.done) and future.result().results[0].successful
    reads = wall.reads
    assert ros.spin_until(lambda: wall.reads > reads)  # paced anew from this wall time
    for k in range(1, 51):
        step_wall(20 * MS, 80 * MS + k * 60 * MS)
    values = np.array([stamp_ns(c.clock) for c in clocks])
    np.testing.assert_array_equal(np.diff(values), 4 * MS)
    assert values[-1] == 80 * MS + 3 * S


@pytest.mark.system
@pytest.mark.parametrize('namespace', ['', '/fast'])
def test_factor_zero_with_a_publish_rate_publishes_every_tenth_tick(ros, namespace):
    """
    Factor 0 at 1 kHz, poses at 100 Hz: faster than real time, pose stamps 10 ticks apart.

    First only the poses are taken, over 2 s of wall time: their stamps give the factor
    reached (printed), and they lie on the 1 ms grid exactly 10 ticks apart. Then /clock is
    taken too, for 500 values: every /clock value at a publishing tick (a multiple of 10 ms) is
    a pose stamp, so the poses carry /clock's values. /clock has depth 1: at this pace a Python
    subscriber sees only some of its values, and taking them slows the node and this process
    down, which is why the factor is measured without it and it is taken briefly. In a
    namespace /clock stays absolute and pose is relative.
    """
    rate, publish_rate = 1000.0, 100.0
    period = round(1e9 / rate)
    every = round(rate / publish_rate)
    arguments = ['-p', 'publish_clock:=true', '-p', 'real_time_factor:=0.0',
                 '-p', f'rate_hz:={rate}', '-p', f'publish_rate_hz:={publish_rate}',
                 '-p', 'marker_rate_hz:=0.0', '-p', 'diagnostics_rate_hz:=0.0']
    if namespace:
        arguments = ['-r', f'__ns:={namespace}', *arguments]
    poses = ros.collect(PoseStamped, f'{namespace}/pose', depth=100000)
    with node_process(*arguments):
        assert ros.spin_until(lambda: len(poses) > 10, timeout=20.0)
        first, started = len(poses), time.monotonic()
        ros.spin_for(2.0)
        wall = time.monotonic() - started
        measured = np.array([stamp_ns(p.header.stamp) for p in poses[first - 1:]])
        clocks = []
        subscription = ros.probe.create_subscription(Clock, '/clock', clocks.append, 100000)
        assert ros.spin_until(lambda: len(clocks) >= 500, timeout=10.0)
        ros.probe.destroy_subscription(subscription)
        clock_values = {stamp_ns(c.clock) for c in clocks}
        ros.spin_for(0.3)  # the poses of the last clock values are in
    factor = (measured[-1] - measured[0]) * 1e-9 / wall
    print(f'real_time_factor 0 at {rate:g} Hz, poses at {publish_rate:g} Hz'
          f'{" in " + namespace if namespace else ""}: {factor:.1f}x real time '
          f'({len(measured) - 1} poses in {wall:.2f} s)')
    # As fast as it can: faster than real time (the factor reached is printed; it depends on
    # the machine and its load, docs/simulator.md), however loaded the machine is.
    assert factor > 1.0
    stamps = np.array([stamp_ns(p.header.stamp) for p in poses])
    assert np.all(stamps % (every * period) == 0)
    # Every tenth tick publishes. A Python subscriber flooded at this pace may miss some of the
    # poses (the publisher's history is KEEP_LAST): gaps are whole publishing periods, and few.
    gaps = np.diff(stamps)
    assert np.all(gaps > 0) and np.all(gaps % (every * period) == 0)
    assert np.count_nonzero(gaps == every * period) >= 0.95 * len(gaps)
    assert all(value % period == 0 for value in clock_values)
    publishing = {value for value in clock_values if value % (every * period) == 0}
    # Each is a pose stamp, but for the few poses the flooded subscriber missed (in the gaps).
    carried = publishing & set(stamps.tolist())
    assert publishing and len(carried) >= 0.95 * len(publishing), sorted(publishing - carried)


@pytest.mark.parametrize('name, value', [
    ('real_time_factor', 1.0e-13), ('marker_rate_hz', 1.0e-11),
    ('diagnostics_rate_hz', 1.0e-11)])
def test_a_rate_whose_timer_cannot_run_is_refused_at_run_time(ros, name, value):
    """
    ros2 param set of a factor or a rate whose timer period overflows: refused, nothing changes.

    Such a value used to end the node from create_timer (the period overflows a timer's int64
    nanoseconds); now it is refused with the reason and the clock runs on at its factor.
    """
    node = start_node(ros, publish_clock=True, rate_hz=250.0, marker_rate_hz=10.0)
    clocks = ros.collect(Clock, '/clock', depth=10000)
    assert ros.spin_until(lambda: len(clocks) > 10)
    client = ros.probe.create_client(SetParameters, '/mouse_constraint/set_parameters')
    assert client.wait_for_service(timeout_sec=5.0)
    future = client.call_async(SetParameters.Request(parameters=[
        ParameterMessage(name=name, value=ParameterValue(type=ParameterType.PARAMETER_DOUBLE,
                                                         double_value=value))]))
    assert ros.spin_until(future.done)
    [result] = future.result().results
    assert not result.successful
    assert f'{name} must be 0 or at least 0.001' in result.reason
    assert node.get_parameter(name).value != value
    before = len(clocks)
    ros.spin_for(0.3)
    assert len(clocks) > before
