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

"""Ticks the device clocks: one tick per pose at once, its force right after, through ROS."""

import copy
import math
from pathlib import Path

from geometry_msgs.msg import PoseStamped, WrenchStamped
import numpy as np
import pytest
from rclpy.node import Node
from rclpy.parameter import Parameter
import yaml

from mouse_constraint_ros.cli import ctl
from mouse_constraint_ros.node.device_ticks import OwnTicks
from mouse_constraint_ros.node.mouse_constraint_node import MouseConstraintNode
from mouse_constraint_ros.node.parameters import DEFAULTS, node_config
from mouse_constraint_ros.physics import MouseSimulation
from mouse_constraint_ros.physics.coupling_stability import Device, largest_stable_stiffness
from mouse_constraint_ros.testing import SimulatedBody
from mouse_constraint_ros.timing.device_clock import device_grid_tick, DeviceClock
from mouse_constraint_ros.timing.tick_grid import TickGrid
from mouse_constraint_ros.wire.interface import (FORCE_QOS, FORCE_TOPIC, POSE_TOPIC, STATE_QOS,
                                                 TARGET_POSE_TOPIC, TARGET_QOS)
from mouse_constraint_ros.wire.messages import felt_force, set_stamp, stamp_nanoseconds
from test_support.haptic_device import (DeviceNode, HAND, loop, LOOP_BODY, ORIGIN, PERIOD,
                                        TRIAL_TICKS, WINDOW)
from test_support.haptic_listener import StateListener

PRESET = {**yaml.safe_load((Path(__file__).resolve().parent.parent / 'config' / 'haptic.yaml')
                           .read_text())['/**']['ros__parameters'], 'tick_source': 'target_pose'}
G = 9.80665
T = 0.001
START = np.array([0.0, 0.0, float(np.linalg.norm(PRESET['anchor']))])


def test_the_device_clock_holds_the_own_ticks_back_for_the_timeout_and_classes_its_ticks():
    clock = DeviceClock()
    clock.configure(on=True, rate_hz=1000.0, timeout=0.005)
    assert clock.own_tick() and not clock.silent  # before the first pose
    clock.take(0)
    clock.take(1_000_000)
    clock.take(1_400_000)  # 0.4 dt: early
    clock.take(3_000_000)  # 1.6 dt: late
    assert (clock.ticks, clock.early, clock.late) == (4, 1, 1)
    held = [clock.own_tick() for _ in range(8)]
    assert held == [False] * 6 + [True] * 2 and clock.silent  # more than 5 ms: 6 held
    clock.take(4_000_000)
    assert not clock.own_tick() and not clock.silent
    clock.configure(on=False, rate_hz=1000.0, timeout=0.005)
    assert clock.own_tick() and not clock.silent


def test_a_device_tick_is_the_one_after_the_latest_unless_it_lags_past_the_catch_up_bound():
    assert device_grid_tick(due=500, following=450, max_lag=100) == 450  # behind: catching up
    assert device_grid_tick(due=500, following=520, max_lag=100) == 520  # ahead: a fast device
    assert device_grid_tick(due=500, following=399, max_lag=100) == 500  # lost: dropped


class RecordedTicks:
    """Stands in for the node's ``Tick``: records the stamps it runs."""

    def __init__(self) -> None:
        """Run none yet."""
        self.stamps = []

    def run(self, stamp: int, tick=None, force_stamp=None) -> None:
        """Record ``stamp``."""
        self.stamps.append(stamp)


def test_the_node_s_own_ticks_go_on_after_the_device_s_without_repeating_one():
    """
    A device that ran ahead of the clock: the own ticks start after its latest.

    The ticks it ran are no silence; the six after it (past the 5 ms timeout) are held back.
    """
    grid = TickGrid.for_rate(1000.0)
    grid.restart(0)
    clock = DeviceClock()
    clock.configure(on=True, rate_hz=1000.0, timeout=0.005)
    ticks = RecordedTicks()
    own = OwnTicks(ticks, clock, lambda: grid)
    clock.take(0)
    own.device_ran(grid.origin, 20)  # the device's ticks reached tick 20 at tick 0's time
    for tick in range(1, 31):
        own.run(grid.stamp(tick), tick)
    assert ticks.stamps == [grid.stamp(tick) for tick in range(27, 31)]
    grid.restart(5_000)  # a new grid (a resume, a clock that jumped): its ticks all run
    own.run(grid.stamp(3), 3)
    assert ticks.stamps[-1] == 3_005_000


class Hand(Node):
    """A device sending the hand's pose when asked: lifted at ``acceleration`` from ``START``."""

    def __init__(self, *, context, acceleration) -> None:
        """Publish on target_pose."""
        super().__init__('hand', context=context, start_parameter_services=False)
        self.acceleration = np.array(acceleration)
        self.publisher = self.create_publisher(PoseStamped, TARGET_POSE_TOPIC, TARGET_QOS)
        self.sent = []

    def send(self, time: float) -> np.ndarray:
        """Send where the hand is at ``time`` (s); return it."""
        point = START + 0.5 * self.acceleration * time * time
        message = PoseStamped()
        set_stamp(message.header.stamp, round(time * 1e9))
        p = message.pose.position
        p.x, p.y, p.z = point
        message.pose.orientation.w = 1.0
        self.publisher.publish(message)
        self.sent.append(point)
        return point


def replayed_forces(points) -> np.ndarray:
    """Return the felt force of each tick of the preset's body with ``points`` as its targets."""
    config = node_config({**DEFAULTS, **PRESET})
    simulation = MouseSimulation(config.settings, config.initial_state)
    forces = []
    for point in points:
        simulation.target = tuple(point)
        simulation.step(T)
        forces.append(felt_force(simulation.tick_impulse))
    return np.array(forces)


@pytest.mark.ros
@pytest.mark.parametrize('acceleration', [(0.0, 0.0, 3.0), (0.0, 0.0, -4.0)])
def test_each_pose_runs_one_tick_and_gets_its_force_m_g_minus_a_on_every_tick(acceleration):
    """
    1000 poses, each answered by exactly one force, of the tick that pose ran (no tick between).

    The state's stamps go one period a tick, the force carries the stamp of the pose it answers.

    The forces are those of the body stepped with each pose as the target of its own tick, to
    1e-9 N (d = 0: the loop the stability analysis has), so no tick's force carries another
    tick's error. Each is within 1 % of m (g - a) on every tick once the coupling's own
    transient has decayed: the lift's start asks the spring k, damper c coupling for m a more,
    and that step response dies as exp(-c t / (2 m)), below 1 % of m g after
    ln(a / (0.01 g)) 2 m / c (0.46 s and 0.49 s here). The harness only drains: no tick runs
    but the poses'.
    """
    with SimulatedBody(**PRESET) as body:
        listener = body.add_node(StateListener(context=body.context))
        hand = body.add_node(Hand(context=body.context, acceleration=acceleration))
        body.step(0)
        stamps = []
        for tick in range(1000):
            hand.send(tick * T)
            body.step(0)
            stamps.append(round(body.time * 1e9))
            assert len(listener.forces) == tick + 1
        assert body.node.ticker.device_clock.ticks == 1000
    assert [stamp for stamp, _ in listener.poses] == stamps
    assert np.all(np.diff(stamps) == round(T * 1e9))
    assert [stamp for stamp, _ in listener.forces] == [round(k * T * 1e9) for k in range(1000)]
    forces = np.array([force for _, force in listener.forces])
    np.testing.assert_allclose(forces, replayed_forces(hand.sent), rtol=0.0, atol=1e-9)
    expected = PRESET['mass'] * (np.array([0.0, 0.0, -G]) - acceleration)
    settled = math.log(np.linalg.norm(acceleration) / (0.01 * G)) * 2.0 * PRESET['mass'] \
        / PRESET['coupling_damping']
    late = forces[math.ceil(settled / T):]
    assert np.all(np.abs(late - expected).max(axis=1) <= 0.01 * PRESET['mass'] * G)


@pytest.mark.ros
def test_poses_that_come_together_each_run_their_own_tick():
    """
    Three poses sent before the node spins (a stall of the node's process): three ticks.

    A device's poses that queue up while the node is busy each run their tick in order, each
    force the reaction of its own pose.
    """
    with SimulatedBody(**PRESET) as body:
        listener = body.add_node(StateListener(context=body.context))
        hand = body.add_node(Hand(context=body.context, acceleration=(0.0, 0.0, 3.0)))
        body.step(0)
        for burst in range(20):
            for tick in range(3):
                hand.send((3 * burst + tick) * T)
            body.step(0)
            assert len(listener.forces) == 3 * (burst + 1)
        assert body.node.ticker.device_clock.ticks == 60
    forces = np.array([force for _, force in listener.forces])
    np.testing.assert_allclose(forces, replayed_forces(hand.sent), rtol=0.0, atol=1e-9)


@pytest.mark.ros
def test_a_burst_of_poses_of_a_tenth_of_a_second_each_runs_its_own_tick():
    """
    A stall of the node of 0.1 s (device_timeout, the catch-up bound): every pose runs its tick.

    The poses are sent before the node spins, as a device's loop goes on while the node's
    process is held up; each gets its own force, the reaction of its own tick, in order.
    """
    depth = round(0.1 / T)
    with SimulatedBody(**PRESET) as body:
        listener = body.add_node(StateListener(context=body.context))
        hand = body.add_node(Hand(context=body.context, acceleration=(0.0, 0.0, 3.0)))
        body.step(0)
        for tick in range(depth):
            hand.send(tick * T)
        body.step(0)
        assert body.node.ticker.device_clock.ticks == depth and len(listener.forces) == depth
        assert body.node._target.device.lost == 0
    forces = np.array([force for _, force in listener.forces])
    np.testing.assert_allclose(forces, replayed_forces(hand.sent), rtol=0.0, atol=1e-9)


@pytest.mark.ros
def test_poses_lost_are_counted_from_the_gaps_in_their_stamps_and_echoed(capfd):
    """
    A device at the node's rate whose poses 10-12 and 40 never come: 4 lost, said on /diagnostics.

    ``mouse_ctl echo inputs`` prints the count; the node logs one line when the device falls
    silent and one when it comes back (a silence is no poses lost).
    """
    with SimulatedBody(diagnostics_rate_hz=100.0, **PRESET) as body:
        node = Node('mouse_ctl', context=body.context)
        lines = []
        ctl.create_echo(node, 'inputs', lines.append, print_rate=0.0)
        body.add_node(node)
        hand = body.add_node(Hand(context=body.context, acceleration=(0.0, 0.0, 0.0)))
        body.step(1)
        for tick in range(60):
            if tick not in (10, 11, 12, 40):
                hand.send(tick * T)
            body.step(0)
        assert body.node._target.device.lost == 4
        lines.clear()
        body.step_until(lambda: any('device poses lost: 4' in line for line in lines),
                        max_ticks=100_000)
        body.step(150)
        assert body.node.ticker.device_clock.silent
        for tick in range(500, 510):
            hand.send(tick * T)
            body.step(0)
        assert not body.node.ticker.device_clock.silent and body.node._target.device.lost == 4
    err = capfd.readouterr().err
    assert err.count('device silent: no valid pose on target_pose for more than '
                     'device_timeout 0.1 s') == 1
    assert err.count('device back on target_pose') == 1


@pytest.mark.ros
def test_a_device_that_stops_hands_the_ticks_back_to_the_node_s_clock_after_the_timeout():
    """
    Without poses, the node's own clock runs the ticks again after device_timeout.

    The harness's steps (the node's own clock) are held back while poses come, each counting
    dt of silence; 101 of them after the last pose (more than device_timeout 0.1 s, the one
    in that pose's step included) run no tick, then the node's ticks hold the last target,
    each with a zero force (the device is silent).
    """
    with SimulatedBody(**PRESET) as body:
        listener = body.add_node(StateListener(context=body.context))
        hand = body.add_node(Hand(context=body.context, acceleration=(0.0, 0.0, 0.0)))
        for tick in range(50):
            hand.send(tick * T)
            body.step()
        assert len(listener.forces) == 50 and body.time == pytest.approx(0.050)
        body.step(100)
        assert len(listener.forces) == 50
        body.step(200)
        assert len(listener.forces) == 250
        assert not np.any([force for _, force in listener.forces[50:]])
        np.testing.assert_allclose(body.node.simulation.target, START, rtol=0, atol=1e-15)


class HeldPoses:
    """Stands in for a device node's pose publisher: keeps each pose until ``send``."""

    def __init__(self, publisher) -> None:
        """Hold nothing yet."""
        self._publisher = publisher
        self._message = None

    def publish(self, message: PoseStamped) -> None:
        """Keep a copy of ``message``."""
        self._message = copy.deepcopy(message)

    def send(self) -> None:
        """Publish the pose kept."""
        self._publisher.publish(self._message)


def device_loop_forces(stiffness: float, tick_source: str):
    """Return the simulated device's forces over a trial, the node ticking on ``tick_source``."""
    device = Device(0.045, 0.05, **HAND)
    with SimulatedBody(coupling_stiffness=stiffness, coupling_damping=0.5,
                       tick_source=tick_source, **LOOP_BODY) as body:
        node = body.add_node(DeviceNode(context=body.context, device=device, period=PERIOD,
                                        origin=ORIGIN, reference=lambda _: 0.01))
        if tick_source == 'clock':
            body.step(TRIAL_TICKS)
        else:
            held = node._publisher = HeldPoses(node._publisher)
            body.step(1)  # the first tick, before any pose: the node's own
            for _ in range(TRIAL_TICKS - 1):
                held.send()
                body.step(0)
            assert body.node.ticker.device_clock.ticks == TRIAL_TICKS - 1
        return np.array(node.forces)


@pytest.mark.ros
@pytest.mark.parametrize('share', [0.8, 1.2])
def test_the_device_clocked_loop_is_the_lockstep_loop_the_stability_analysis_has(share):
    """
    A device whose every pose runs a tick feels the forces of the lockstep loop, bit for bit.

    That is the loop of the stability analysis with d = 0: stable at 0.8 of its predicted
    largest stable stiffness, unstable at 1.2.
    """
    bound = largest_stable_stiffness(**loop(Device(0.045, 0.05, **HAND), 0.5, 0))
    stiffness = share * bound
    clocked = device_loop_forces(stiffness, 'target_pose')
    assert len(clocked) == TRIAL_TICKS
    np.testing.assert_array_equal(clocked, device_loop_forces(stiffness, 'clock'))
    change = np.abs(np.diff(clocked, 2))
    growth = change[-WINDOW:].max() / change[-2 * WINDOW:-WINDOW].max()
    assert (growth < 1.0) == (share < 1.0)


@pytest.mark.ros
def test_a_device_clocking_in_the_wrong_frame_runs_no_tick_and_feels_nothing_after_the_timeout():
    """Every pose refused: the node's own ticks run, the held weight until 0.1 s, then zero."""
    with SimulatedBody(**PRESET) as body:
        listener = body.add_node(StateListener(context=body.context))
        device = Node('device', context=body.context, start_parameter_services=False)
        publisher = device.create_publisher(PoseStamped, TARGET_POSE_TOPIC, TARGET_QOS)
        body.add_node(device)
        message = PoseStamped()
        message.header.frame_id = 'geotouch'
        message.pose.position.z = float(START[2])
        for _ in range(300):
            publisher.publish(message)
            body.step()
        assert body.node.ticker.device_clock.ticks == 0
        assert body.node.refusals[0] == 300
    norms = np.linalg.norm([force for _, force in listener.forces], axis=1)
    assert len(norms) == 300
    assert np.all(norms[:100] > 0.9 * PRESET['mass'] * G) and np.all(norms[101:] == 0.0)


@pytest.mark.ros
def test_on_the_node_s_clock_device_ticks_are_stamped_on_its_grid_and_forces_with_their_pose(ros):
    """
    Poses sent three at a time at the pace of their forces' return, on the node's own clock.

    Each pose runs one tick stamped on the node's grid, one period after the tick before, so
    every gap between published stamps is a whole number of periods; the force of each pose
    carries that pose's stamp (off the grid, as a device's clock stamps), so the device knows it.
    The poses come faster than one a period: the device's ticks run ahead of the clock, and
    once it is silent the node's own ticks go on after them.
    """
    period = round(T * 1e9)
    ros.add(MouseConstraintNode(context=ros.context, parameter_overrides=[
        Parameter(name, value=value) for name, value in PRESET.items()]))
    poses, forces = [], []
    ros.probe.create_subscription(PoseStamped, POSE_TOPIC, poses.append, STATE_QOS)
    ros.probe.create_subscription(WrenchStamped, FORCE_TOPIC, forces.append, FORCE_QOS)
    publisher = ros.probe.create_publisher(PoseStamped, TARGET_POSE_TOPIC, TARGET_QOS)
    assert ros.spin_until(lambda: forces and publisher.get_subscription_count() > 0)
    sent = []
    message = PoseStamped()
    message.pose.position.x, message.pose.position.y, message.pose.position.z = START
    message.pose.orientation.w = 1.0
    for burst in range(100):
        for k in range(3 * burst, 3 * burst + 3):
            stamp = 1_700_000_000_123_456_789 + k * 1_000_321
            set_stamp(message.header.stamp, stamp)
            publisher.publish(message)
            sent.append(stamp)
        assert ros.spin_until(lambda: stamp_nanoseconds(forces[-1].header.stamp) == stamp)
    # Silent: the node's own ticks run again, after the device's (which may have run ahead of
    # the clock), none repeating or going back on one of them.
    published = len(poses)
    assert ros.spin_until(lambda: len(poses) > published + 50)
    force_stamps = [stamp_nanoseconds(force.header.stamp) for force in forces]
    assert [s for s in force_stamps if s in set(sent)] == sent
    steps = np.diff([stamp_nanoseconds(pose.header.stamp) for pose in poses])
    assert np.all(steps > 0) and np.all(steps % period == 0), sorted(set(steps % period))
