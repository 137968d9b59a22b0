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

"""The external wrench: its dynamics in the core, the node's policy, timeout and markers."""

import copy
import math
import signal
import subprocess
import sys
import time

from geometry_msgs.msg import WrenchStamped
import numpy as np
import pytest
from rclpy.node import Node
from rclpy.parameter import Parameter
from scipy.spatial.transform import Rotation
from visualization_msgs.msg import Marker, MarkerArray

from mouse_constraint_ros.inputs.wrench_gate import (effective_time, HeldWrench, NO_WRENCH,
                                                     STAMP_WINDOW_NS, WrenchGate)
from mouse_constraint_ros.monitoring.markers import marker_array, wrench_reference
from mouse_constraint_ros.node.mouse_constraint_node import MouseConstraintNode
from mouse_constraint_ros.physics import BodyState, MouseSimulation, RigidBody, Settings
from mouse_constraint_ros.testing import InputRefused
from mouse_constraint_ros.wire import messages
from test_support.ros_harness import spin_until

MASS = 2.0
BOX = (0.4, 0.2, 0.1)
FREE = {'hold_initial_anchor': False, 'gravity': [0.0, 0.0, 0.0]}


def free_simulation(orientation=(0.0, 0.0, 0.0, 1.0), substeps=2) -> MouseSimulation:
    """Return a free body at rest, without gravity, in ``orientation``."""
    settings = Settings(RigidBody.solid_box(MASS, BOX), gravity=(0.0, 0.0, 0.0),
                        substeps=substeps)
    return MouseSimulation(settings, BodyState((0.0, 0.0, 1.0), orientation))


def test_a_force_gains_velocity_f_t_over_m():
    """A free body of mass m under F for t gains v = F t / m, and moves F t^2 / (2 m)."""
    simulation = free_simulation()
    force = (3.0, -1.5, 6.0)
    simulation.wrench = (force, (0.0, 0.0, 0.0))
    dt, steps = 0.001, 1000
    for _ in range(steps):
        state = simulation.step(dt)
    t = dt * steps
    expected = np.array(force) * t / MASS
    np.testing.assert_allclose(state.linear_velocity, expected, rtol=0.005)
    np.testing.assert_allclose(np.array(state.position) - (0.0, 0.0, 1.0),
                               np.array(force) * t * t / (2.0 * MASS), rtol=0.005)
    assert state.angular_velocity == (0.0, 0.0, 0.0)


@pytest.mark.parametrize('axis', [0, 1, 2])
def test_a_torque_about_a_principal_axis_gives_tau_over_i(axis):
    """
    A pure torque about a principal axis of a turned body: alpha = tau / I about that axis.

    The body is turned, so the world axis of the torque is a body axis only through the
    rotation: the frame conversion of the torque is part of what is checked.
    """
    half = 0.35
    orientation = (math.sin(half) / math.sqrt(3.0),) * 3 + (math.cos(half),)
    simulation = free_simulation(orientation)
    body = simulation.settings.body
    # The body's principal axis ``axis`` in the world frame (solid box: the body axes).
    direction = Rotation.from_quat(orientation).as_matrix()[:, axis]
    torque = 0.01 * direction
    simulation.wrench = ((0.0, 0.0, 0.0), tuple(torque))
    moment = (body.inertia[0], body.inertia[3], body.inertia[5])[axis]
    dt, steps = 0.001, 500
    for _ in range(steps):
        state = simulation.step(dt)
    np.testing.assert_allclose(state.angular_velocity, torque / moment * dt * steps,
                               rtol=0.005, atol=1e-12)
    assert state.linear_velocity == (0.0, 0.0, 0.0)


def test_a_torque_about_any_axis_changes_the_angular_momentum_by_tau_t():
    """Off the principal axes the body tumbles, but dL/dt = tau still holds (world frame)."""
    simulation = free_simulation((0.1, 0.2, 0.3, math.sqrt(1.0 - 0.14)))
    torque = (0.004, -0.002, 0.003)
    simulation.wrench = ((0.0, 0.0, 0.0), torque)
    dt, steps = 0.001, 1000
    for _ in range(steps):
        simulation.step(dt)
    np.testing.assert_allclose(simulation.angular_momentum(), np.array(torque) * dt * steps,
                               rtol=0.005)


def test_a_zero_wrench_changes_nothing_bit_for_bit():
    """Without a wrench and with a zero one the step is the same to the bit."""
    plain, zero = free_simulation(), free_simulation()
    zero.wrench = NO_WRENCH
    plain.target = zero.target = (0.3, 0.1, 1.2)
    for _ in range(200):
        assert plain.step(0.001) == zero.step(0.001)


@pytest.mark.parametrize('wrench', [
    ((math.nan, 0.0, 0.0), (0.0, 0.0, 0.0)),
    ((0.0, 0.0, 0.0), (0.0, math.inf, 0.0)),
])
def test_the_core_refuses_a_non_finite_wrench(wrench):
    """A non-finite wrench raises ValueError naming it and leaves the wrench as it was."""
    simulation = free_simulation()
    with pytest.raises(ValueError, match='wrench'):
        simulation.wrench = wrench
    assert simulation.wrench == NO_WRENCH


GATE = WrenchGate('world', max_force=100.0, max_torque=10.0)


@pytest.mark.parametrize('frame, force, torque, key', [
    ('map', (1.0, 0.0, 0.0), (0.0, 0.0, 0.0), 'wrench frame'),
    ('', (math.nan, 0.0, 0.0), (0.0, 0.0, 0.0), 'wrench finite'),
    ('world', (0.0, 0.0, 0.0), (-math.inf, 0.0, 0.0), 'wrench finite'),
    ('world', (60.0, 80.0, 0.1), (0.0, 0.0, 0.0), 'wrench force'),
    ('', (0.0, 0.0, 0.0), (6.0, 0.0, 8.01), 'wrench torque'),
])
def test_the_gate_refuses_foreign_non_finite_and_oversized_wrenches(frame, force, torque, key):
    """Each refusal names its reason; the bounds are on the magnitudes, inclusive."""
    assert GATE.refusal(frame, force, torque).key == key


def test_the_gate_takes_wrenches_up_to_the_bounds():
    """|F| = max_force and |tau| = max_torque are taken, in the node's frame or none."""
    assert GATE.refusal('', (60.0, 80.0, 0.0), (6.0, 0.0, 8.0)) is None
    assert GATE.refusal('world', (0.0, 0.0, 0.0), (0.0, 0.0, 0.0)) is None


def test_a_held_wrench_times_out_and_zero_holds_it():
    """The wrench goes when timeout seconds pass after it; a timeout of 0 keeps it."""
    held = HeldWrench()
    held.take((1.0, 2.0, 3.0), (0.0, 0.0, 1.0), 1_000_000_000)
    assert held.wrench == ((1.0, 2.0, 3.0), (0.0, 0.0, 1.0))
    assert not held.expired(1_500_000_000, 0.5)
    assert not held.expired(10**15, 0.0)
    assert held.expired(1_500_000_001, 0.5)
    assert held.wrench == NO_WRENCH and held.applied is None


def test_a_scheduled_wrench_takes_effect_at_its_stamp_and_zero_ends_it():
    """Wrenches take effect in order from their times; a zero one clears; far off is arrival."""
    held = HeldWrench()
    held.schedule((1.0, 0.0, 0.0), (0.0, 0.0, 0.0), 100)
    held.schedule((0.0, 0.0, 0.0), (0.0, 0.0, 0.0), 300)
    assert not held.advance(99) and held.wrench == NO_WRENCH
    assert held.advance(100) and held.wrench == ((1.0, 0.0, 0.0), ZERO3)
    assert held.applied.since_ns == 100
    assert not held.advance(299) and held.advance(300) and held.applied is None
    held.schedule((1.0, 0.0, 0.0), (0.0, 0.0, 0.0), 400)
    held.clear()
    assert not held.advance(500)
    now = 5 * STAMP_WINDOW_NS
    assert effective_time(now - STAMP_WINDOW_NS, now) == now - STAMP_WINDOW_NS
    assert effective_time(now + 7, now) == now + 7
    assert effective_time(0, now) == now and effective_time(now - STAMP_WINDOW_NS - 1, now) == now
    # Zero is no stamp, also on a simulated clock that started at zero less than a window ago.
    assert effective_time(0, 50_000_000) == 50_000_000


ZERO3 = (0.0, 0.0, 0.0)


def test_the_marker_arrow_shows_the_force_from_the_com():
    """The arrow starts at the COM along F, one longest box edge per body weight; 0 deletes."""
    simulation = free_simulation()
    reference = wrench_reference(simulation.settings)
    assert reference == pytest.approx(MASS * 9.80665)
    state = simulation.state
    force = (0.0, 0.5 * reference, 0.0)
    arrays = [marker_array(frame_id='world', stamp_ns=0, box_size=BOX, state=state,
                           anchor=(0.0, 0.0, 1.0), target=None, force=(0.0, 0.0, 0.0),
                           reference=1.0, wrench_force=f, wrench_reference=reference)
              for f in (force, (0.0, 0.0, 0.0))]
    arrow = {m.ns: m for m in arrays[0].markers}['wrench']
    assert arrow.type == Marker.ARROW and arrow.action == Marker.ADD
    start, end = ((p.x, p.y, p.z) for p in arrow.points)
    assert start == state.position
    np.testing.assert_allclose(np.subtract(end, start), (0.0, 0.5 * max(BOX), 0.0))
    assert {m.ns: m for m in arrays[1].markers}['wrench'].action == Marker.DELETE


# The node.

def start_node(ros, namespace='', **overrides) -> MouseConstraintNode:
    """Start the node in ``ros``'s context, in ``namespace``, with parameter ``overrides``."""
    return ros.add(MouseConstraintNode(context=ros.context, namespace=namespace,
                                       parameter_overrides=[
                                           Parameter(name, value=value)
                                           for name, value in overrides.items()]))


def wrench_message(force, torque, frame_id='world') -> WrenchStamped:
    """Return a WrenchStamped of ``force`` and ``torque`` in ``frame_id`` (world by default)."""
    return messages.wrench_message(force, torque, frame_id)


def test_the_node_applies_a_wrench_and_drops_it_after_the_timeout(simulated_body_factory):
    """A wrench pushes the free body; wrench_timeout after the last one it is removed."""
    body = simulated_body_factory(namespace='/pushed', rate_hz=200.0, wrench_timeout=0.3,
                                  **FREE)
    node = body.node
    body.step(10)
    force, torque = (4.0, 0.0, 0.0), (0.0, 0.0, 0.1)
    given = body.time
    body.wrench(force, torque)
    assert node.simulation.wrench == NO_WRENCH  # from the next tick on
    body.step()
    assert node.simulation.wrench == (force, torque)
    body.step_until(lambda: node.simulation.wrench == NO_WRENCH, max_ticks=100)
    # Applied on the ticks stamped within wrench_timeout of its arrival, then removed at the
    # first tick past it: pushed for exactly 60 ticks of 5 ms, at F / m.
    assert body.time == pytest.approx(given + 0.3 + 0.005, abs=1e-12)
    speed = node.simulation.state.linear_velocity[0]
    assert speed == pytest.approx(force[0] / MASS * 0.3, rel=1e-12)
    body.step(40)
    assert node.simulation.state.linear_velocity[0] == speed


def test_a_stamped_push_lasts_its_duration_to_the_tick(simulated_body_factory):
    """
    A push stamped t0 and its zero wrench stamped t1: the ticks stamped in [t0, t1) push.

    Both messages arrive before any of those ticks runs: taken at their arrival, they would
    cancel; taken at their stamps, the body gains exactly F (t1 - t0) / m.
    """
    body = simulated_body_factory(rate_hz=100.0, wrench_timeout=0.0, **FREE)
    body.step(10)
    start = body.time
    force = 3.0
    body.wrench((force, 0.0, 0.0), stamp=start + 0.05)
    body.wrench((0.0, 0.0, 0.0), stamp=start + 0.25)
    assert body.node.simulation.wrench == NO_WRENCH
    body.step(50)
    assert body.node.simulation.wrench == NO_WRENCH
    assert body.node.simulation.state.linear_velocity[0] == pytest.approx(force / MASS * 0.2,
                                                                          rel=1e-12)


def test_hostile_wrenches_change_nothing_bit_for_bit(simulated_body_factory, capfd):
    """
    Non-finite, foreign-frame and oversized wrenches are refused, each with its reason.

    After them, the simulation steps exactly as a copy taken before them does.
    """
    body = simulated_body_factory(max_wrench_force=50.0, max_wrench_torque=5.0, **FREE)
    node = body.node
    valid = ((1.0, 2.0, 3.0), (0.01, 0.0, 0.0))
    body.wrench(*valid)
    body.step()
    assert node.simulation.wrench == valid
    reference = copy.deepcopy(node.simulation)
    hostile = [((math.nan, 0.0, 0.0), ZERO3, '', 'wrench finite'),
               (ZERO3, (0.0, 0.0, math.inf), '', 'wrench finite'),
               ((1.0, 0.0, 0.0), ZERO3, 'map', 'wrench frame'),
               ((50.1, 0.0, 0.0), ZERO3, '', 'wrench force'),
               (ZERO3, (0.0, 5.1, 0.0), '', 'wrench torque')]
    for force, torque, frame, key in hostile:
        with pytest.raises(InputRefused) as refused:
            body.wrench(force, torque, frame_id=frame)
        assert refused.value.key == key
    for _ in range(5):
        body.step()
        reference.step(1.0 / 1000.0)
    assert node.simulation.wrench == valid
    assert node.simulation.state == reference.state
    err = capfd.readouterr().err
    for reason in ('not finite', "in frame 'map'", 'max_wrench_force', 'max_wrench_torque'):
        assert 'ignoring wrench' in err and reason in err, reason


def test_markers_show_the_applied_force(simulated_body_factory):
    """The node's wrench arrow appears with a force and is deleted after the timeout."""
    body = simulated_body_factory(rate_hz=200.0, marker_rate_hz=50.0, wrench_timeout=0.2, **FREE)
    viewer = Node('viewer', context=body.context)
    arrays = []
    viewer.create_subscription(MarkerArray, '/mouse_constraint/markers', arrays.append, 10)
    body.add_node(viewer)

    def arrow():
        return {m.ns: m for m in arrays[-1].markers}['wrench'] if arrays else None

    body.wrench((0.0, 0.0, 9.0))
    body.step()
    # Markers come on their own timer (wall time): wait for two more without stepping, so that
    # the wrench cannot time out meanwhile however slow the timer is.
    count = len(arrays)
    assert spin_until(body.executor, lambda: len(arrays) > count + 1)
    assert arrow().action == Marker.ADD
    start, end = ((p.x, p.y, p.z) for p in arrow().points)
    length = max(BOX) * 9.0 / wrench_reference(body.node.simulation.settings)
    assert end[2] - start[2] == pytest.approx(length)
    body.step_until(lambda: body.node.simulation.wrench == NO_WRENCH, max_ticks=100)
    count = len(arrays)
    assert spin_until(body.executor, lambda: len(arrays) > count + 1)
    assert arrow().action == Marker.DELETE


def run_wrench_cli(ros, arguments, *, signal_after=None, timeout=20.0):
    """
    Run ``mouse_wrench`` with ``arguments`` while ``ros`` spins; return (status, stdout, stderr).

    :param signal_after: send SIGINT this many seconds after the push began (its first line).
    """
    process = subprocess.Popen([sys.executable, '-m', 'mouse_constraint_ros.cli.wrench',
                                *arguments], stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                               text=True)
    started = None

    def done() -> bool:
        nonlocal started
        if signal_after is not None and started is None and any(
                node.simulation.wrench != NO_WRENCH for node in ros.nodes[1:]):
            started = time.monotonic()
        if started is not None and time.monotonic() - started > signal_after:
            process.send_signal(signal.SIGINT)
            started = math.inf
        return process.poll() is not None

    try:
        assert ros.spin_until(done, timeout=timeout), 'mouse_wrench did not end'
    finally:
        if process.poll() is None:
            process.kill()
    stdout, stderr = process.communicate(timeout=5.0)
    return process.returncode, stdout, stderr


def record_pushed_ticks(node) -> list:
    """Return the list that gets, for each step of ``node``, (wrench applied, dropped ticks)."""
    simulation, ticks = node.simulation, []
    step = simulation.step

    def recording_step(dt):
        ticks.append((simulation.wrench != NO_WRENCH, node.ticker.record.dropped_ticks))
        return step(dt)

    simulation.step = recording_step
    return ticks


@pytest.mark.system
@pytest.mark.alone
@pytest.mark.parametrize('duration', [0.05, 0.3])
def test_the_wrench_cli_pushes_for_its_duration_then_stops(ros, duration):
    """
    mouse_wrench: the push lasts its duration within a few ticks, not a polling period.

    A free 2 kg body, no timeout: the zero wrench alone ends the push. The ticks stepped with
    the wrench are the push (the command's own rate, 20 Hz, would show as 50 ms too long), and
    the velocity gained is F t / m over them. A push during which this loaded machine made the
    node drop ticks (its simulated time is then shorter than the wall time) is tried again, at
    most three times.
    """
    node = start_node(ros, rate_hz=500.0, wrench_timeout=0.0, **FREE)
    ticks = record_pushed_ticks(node)
    force = 2.0
    for _ in range(3):
        speed = node.simulation.state.linear_velocity[0]
        del ticks[:]
        status, stdout, stderr = run_wrench_cli(
            ros, ['--force', str(force), '0', '0', '--duration', str(duration)])
        ros.spin_for(0.2)
        assert status == 0, stderr
        assert node.simulation.wrench == NO_WRENCH
        pushed = [k for k, (applied, _) in enumerate(ticks) if applied]
        dropped = {ticks[k][1] for k in range(pushed[0], pushed[-1] + 2)}
        if len(dropped) == 1:
            break
    assert len(dropped) == 1, 'the node dropped ticks in each of three pushes'
    assert pushed == list(range(pushed[0], pushed[-1] + 1))
    assert abs(len(pushed) / 500.0 - duration) <= 0.01, len(pushed)
    gained = (node.simulation.state.linear_velocity[0] - speed) * MASS / force
    assert gained == pytest.approx(len(pushed) / 500.0, rel=1e-9)
    assert f'for {duration:g} s' in stdout
    assert 'Traceback' not in stderr and 'Exception ignored' not in stderr


@pytest.mark.system
@pytest.mark.alone
def test_an_endless_push_ends_with_the_zero_wrench_on_ctrl_c(ros):
    """--duration inf pushes until SIGINT; then the zero wrench ends it (no timeout here)."""
    node = start_node(ros, rate_hz=200.0, wrench_timeout=0.0, **FREE)
    status, stdout, stderr = run_wrench_cli(
        ros, ['--force', '1', '0', '0', '--duration', 'inf'], signal_after=0.5)
    ros.spin_for(0.2)
    assert status == 0, stderr
    assert 'Traceback' not in stderr and 'until Ctrl-C' in stderr
    assert node.simulation.wrench == NO_WRENCH
    speed = node.simulation.state.linear_velocity[0]
    ros.spin_for(0.2)
    assert node.simulation.state.linear_velocity[0] == speed > 0.4 * 1.0 / MASS
    assert 'pushed with force' in stdout


@pytest.mark.parametrize('arguments', [
    ['--rate', 'inf'], ['--rate', '1e-300'], ['--rate', '0'], ['--rate', 'nan'],
    ['--rate', '1e6'], ['--duration', 'nan'], ['--duration', '-1'], ['--duration', '1e300'],
    ['--timeout', '0'],
])
def test_the_wrench_cli_refuses_rates_and_durations_that_do_not_run(arguments, capsys):
    """A rate, duration or timeout whose timer cannot run is a usage error (exit 2)."""
    from mouse_constraint_ros.cli.wrench import build_parser
    with pytest.raises(SystemExit) as exit_info:
        build_parser().parse_args(arguments)
    assert exit_info.value.code == 2
    assert 'must be in' in capsys.readouterr().err


@pytest.mark.system
@pytest.mark.parametrize('arguments, reason', [
    (['--force', '60', '0', '0'], 'max_wrench_force 50 N'),
    (['--torque', '0', '0', '6'], 'max_wrench_torque 5 N m'),
    (['--force', '1', '0', '0', '--frame', 'map'], "in frame 'map'"),
    (['--force', '1', '0', '0', '--rate', '1', '--duration', '2'], 'wrench_timeout 0.5 s'),
])
def test_the_wrench_cli_refuses_what_the_running_node_would_ignore(ros, arguments, reason):
    """Checked against the node's own bounds, frame and timeout: exit 1, nothing sent."""
    node = start_node(ros, rate_hz=200.0, max_wrench_force=50.0, max_wrench_torque=5.0, **FREE)
    seen = []
    ros.probe.create_timer(0.01, lambda: seen.append(node.simulation.wrench))
    status, stdout, stderr = run_wrench_cli(ros, arguments)
    assert status == 1 and reason in stderr and 'nothing published' in stderr, stderr
    assert set(seen) == {NO_WRENCH} and 'pushed' not in stdout


@pytest.mark.system
def test_the_wrench_cli_refuses_a_non_finite_wrench_at_once():
    """A non-finite force is refused before anything starts: exit 1, no node needed."""
    result = subprocess.run(
        [sys.executable, '-m', 'mouse_constraint_ros.cli.wrench', '--force', 'nan', '0', '0'],
        capture_output=True, text=True, timeout=20.0)
    assert result.returncode == 1 and 'not finite' in result.stderr


@pytest.mark.system
def test_the_wrench_cli_interrupted_before_a_subscriber_sends_nothing(ros):
    """SIGINT while it waits for a subscriber: exit 130 at once, no traceback, nothing sent."""
    process = subprocess.Popen(
        [sys.executable, '-m', 'mouse_constraint_ros.cli.wrench', '--force', '1', '0', '0',
         '--duration', '5'], stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    try:
        # It waits for a subscriber once its publisher is there.
        assert ros.spin_until(lambda: ros.probe.count_publishers('/wrench') > 0, timeout=20.0)
        process.send_signal(signal.SIGINT)
        stdout, stderr = process.communicate(timeout=10.0)
    finally:
        if process.poll() is None:
            process.kill()
    assert process.returncode == 130, stderr
    assert 'Traceback' not in stderr and 'pushed' not in stdout
