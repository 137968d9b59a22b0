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

"""The node in-process: rate and stamps, targets, bad input, parameters, services, timeout."""

import math

from diagnostic_msgs.msg import DiagnosticArray, DiagnosticStatus
from geometry_msgs.msg import PointStamped, PoseStamped, TwistStamped
import numpy as np
import pytest
from rcl_interfaces.msg import Parameter as ParameterMessage, ParameterType, ParameterValue
from rcl_interfaces.srv import SetParameters
from rclpy.parameter import Parameter
from rosgraph_msgs.msg import Clock
from scipy.spatial.transform import Rotation
from std_srvs.srv import Trigger

from mouse_constraint_ros.node.mouse_constraint_node import MouseConstraintNode
from mouse_constraint_ros.wire.messages import point_message, state_from_messages

ANCHOR = np.array([0.2, 0.1, 0.05])


def start_node(ros, **overrides) -> MouseConstraintNode:
    """Start the node in ``ros``'s context with parameter ``overrides``."""
    node = MouseConstraintNode(context=ros.context, parameter_overrides=[
        Parameter(name, value=value) for name, value in overrides.items()])
    return ros.add(node)


def anchor_of(pose: PoseStamped) -> np.ndarray:
    """Return the world position of the default anchor for a published pose."""
    p, q = pose.pose.position, pose.pose.orientation
    return np.array([p.x, p.y, p.z]) + Rotation.from_quat([q.x, q.y, q.z, q.w]).apply(ANCHOR)


def publish_target(ros, publisher, point, frame_id='world') -> None:
    """Publish one target and let it arrive."""
    publisher.publish(point_message(point, frame_id, 0))
    ros.spin_for(0.05)


def target_publisher(ros):
    """Return a publisher on ``target`` that matches the node, once matched."""
    publisher = ros.probe.create_publisher(PointStamped, 'target', 10)
    assert ros.spin_until(lambda: publisher.get_subscription_count() > 0)
    return publisher


def stamp_ns(message) -> int:
    """Return a message's header stamp in nanoseconds."""
    return message.header.stamp.sec * 1_000_000_000 + message.header.stamp.nanosec


def test_messages_arrive_at_the_rate_with_grid_stamps(ros):
    """Pose and twist come every tick, stamped t0 + n / rate_hz, pose and twist alike."""
    start_node(ros, rate_hz=200.0)
    poses = ros.collect(PoseStamped, 'pose')
    twists = ros.collect(TwistStamped, 'twist')
    assert ros.spin_until(lambda: len(poses) > 0)
    ros.spin_for(2.0)
    stamps = np.array([stamp_ns(m) for m in poses])
    # Every message and no gap: consecutive stamps exactly one period apart.
    np.testing.assert_array_equal(np.diff(stamps), 5_000_000)
    assert len(poses) == pytest.approx(400, rel=0.1)
    assert [stamp_ns(m) for m in twists[:len(poses)]] == list(stamps[:len(twists)])
    assert {m.header.frame_id for m in poses + twists} == {'world'}


def test_pose_and_twist_agree(ros):
    """
    Finite differences of the pose equal the twist (world frame) of the later tick.

    With one substep per tick the published velocity is the one that carried the pose from one
    tick to the next (symplectic Euler's half-step velocity), so they agree to rounding.
    """
    node = start_node(ros, rate_hz=500.0, substeps=1,
                      initial_orientation=[0.0, 0.0, 0.3826834323650898, 0.9238795325112867])
    poses = ros.collect(PoseStamped, 'pose')
    twists = ros.collect(TwistStamped, 'twist')
    ros.spin_for(1.0)
    count = min(len(poses), len(twists))
    assert count > 100
    dt = 1.0 / 500.0
    states = [state_from_messages(p, t) for p, t in zip(poses[:count], twists[:count])]
    speeds = []
    for before, after in zip(states, states[1:]):
        velocity = (np.array(after.position) - np.array(before.position)) / dt
        np.testing.assert_allclose(velocity, after.linear_velocity, atol=1e-9)
        turn = (Rotation.from_quat(after.orientation) *
                Rotation.from_quat(before.orientation).inv()).as_rotvec() / dt
        np.testing.assert_allclose(turn, after.angular_velocity, atol=1e-6)
        speeds.append(np.linalg.norm(after.angular_velocity))
    assert max(speeds) > 0.5  # it really swings
    assert node.simulation.settings.substeps == 1


def test_a_target_is_reached_and_held(ros):
    """
    The anchor goes to a published target and stays there while the body swings.

    A jump of the target sets the body swinging and spinning about the anchor; damping lets that
    die down, as a user dragging a body would set it (a spinning body's anchor drifts by
    O(h^2 |w|^2 |r| / delta), see README).
    """
    start_node(ros, rate_hz=500.0, linear_damping=2.0, angular_damping=2.0)
    poses = ros.collect(PoseStamped, 'pose')
    publisher = target_publisher(ros)
    target = (0.4, -0.3, 1.2)
    publish_target(ros, publisher, target)
    ros.spin_for(3.5)
    errors = [np.linalg.norm(anchor_of(p) - target) for p in poses[-100:]]
    assert max(errors) < 1e-4
    # And the body moved there: its anchor is far from where it started.
    assert np.linalg.norm(anchor_of(poses[-1]) - anchor_of(poses[0])) > 0.3


@pytest.mark.parametrize('point, frame_id', [
    ((math.nan, 0.0, 1.0), 'world'),
    ((0.0, math.inf, 1.0), 'world'),
    ((0.0, 0.0, -math.inf), 'world'),
    ((1e300, 0.0, 0.0), 'world'),
    ((0.0, 7.1e3, 7.1e3), 'world'),
    ((0.5, 0.5, 0.5), 'map'),
])
def test_bad_targets_are_ignored(ros, point, frame_id):
    """Non-finite or too far points and foreign frames change nothing; outputs stay finite."""
    node = start_node(ros, rate_hz=200.0)
    poses = ros.collect(PoseStamped, 'pose')
    publisher = target_publisher(ros)
    held = node.simulation.target
    publish_target(ros, publisher, point, frame_id)
    ros.spin_for(0.3)
    assert node.simulation.target == held
    assert all(np.isfinite(anchor_of(p)).all() for p in poses)
    # An empty frame_id is taken as frame_id.
    publish_target(ros, publisher, (0.1, 0.2, 0.3), '')
    assert ros.spin_until(lambda: node.simulation.target == (0.1, 0.2, 0.3))


def test_parameter_updates_apply_and_invalid_ones_are_rejected(ros):
    """Valid values reach the simulation at once; invalid ones fail with a reason."""
    node = start_node(ros, rate_hz=200.0)
    result = node.set_parameters([Parameter('mass', value=3.0),
                                  Parameter('frequency_hz', value=4.0)])
    assert all(r.successful for r in result)
    assert node.simulation.settings.body.mass == 3.0
    assert node.simulation.settings.constraint.frequency_hz == 4.0
    before = node.simulation.settings
    rejected = {
        'mass': (-1.0, 'mass'),
        'inertia': ([1.0, 0.0, 0.0, 1.0, 0.0, 3.0], 'triangle'),
        'initial_orientation': ([0.0, 0.0, 0.0, 2.0], 'unit quaternion'),
        'baumgarte': (math.nan, 'baumgarte'),
        'anchor': ([0.0, 0.0], 'anchor'),
        'substeps': (0, 'substeps'),
        'frame_id': ('', 'frame_id'),
    }
    for name, (value, reason) in rejected.items():
        [result] = node.set_parameters([Parameter(name, value=value)])
        assert not result.successful, name
        assert reason in result.reason, (name, result.reason)
    assert node.simulation.settings is before
    assert node.get_parameter('mass').value == 3.0


def test_parameter_service_like_ros2_param_set(ros):
    """The same through the SetParameters service that `ros2 param set` calls."""
    node = start_node(ros, rate_hz=200.0)
    request = SetParameters.Request(parameters=[
        ParameterMessage(name='gravity', value=ParameterValue(
            type=ParameterType.PARAMETER_DOUBLE_ARRAY, double_array_value=[0.0, 0.0, -1.0])),
        ParameterMessage(name='max_force', value=ParameterValue(
            type=ParameterType.PARAMETER_DOUBLE, double_value=-5.0)),
    ])
    response = ros.call(SetParameters, '/mouse_constraint/set_parameters', request)
    assert [r.successful for r in response.results] == [True, False]
    assert 'max_force' in response.results[1].reason
    assert node.simulation.settings.gravity == (0.0, 0.0, -1.0)


def test_rate_can_change_at_run_time(ros):
    """A new rate_hz restarts the grid at the new period."""
    node = start_node(ros, rate_hz=100.0)
    poses = ros.collect(PoseStamped, 'pose')
    ros.spin_for(0.3)
    assert node.set_parameters([Parameter('rate_hz', value=400.0)])[0].successful
    count = len(poses)
    ros.spin_for(1.0)
    # The last 300 poses (0.75 s) all come after the restart, whatever was in flight.
    assert len(poses) - count > 300
    stamps = np.array([stamp_ns(m) for m in poses[-300:]])
    np.testing.assert_array_equal(np.diff(stamps), 2_500_000)


def test_reset_and_release_services(ros):
    """~/release frees the body (it falls); ~/reset restores the initial state and the hold."""
    node = start_node(ros, rate_hz=200.0)
    publisher = target_publisher(ros)
    # A target where the anchor already is: the body hangs there at rest, nearly.
    publish_target(ros, publisher, (0.2, 0.1, 1.05))
    assert ros.spin_until(lambda: node.simulation.target == (0.2, 0.1, 1.05))
    response = ros.call(Trigger, '/mouse_constraint/release', Trigger.Request())
    assert response.success and node.simulation.target is None
    ros.spin_for(0.3)
    assert node.simulation.state.linear_velocity[2] < -1.0
    response = ros.call(Trigger, '/mouse_constraint/reset', Trigger.Request())
    assert response.success
    assert node.simulation.target == pytest.approx(
        tuple(np.array([0.0, 0.0, 1.0]) + ANCHOR))
    assert node.simulation.state.position == pytest.approx((0.0, 0.0, 1.0), abs=0.05)


def test_target_timeout_releases_the_body(ros):
    """With target_timeout > 0 the body is released when targets stop coming."""
    node = start_node(ros, rate_hz=200.0, target_timeout=0.3)
    publisher = target_publisher(ros)
    publish_target(ros, publisher, (0.2, 0.0, 1.0))
    assert ros.spin_until(lambda: node.simulation.target == (0.2, 0.0, 1.0))
    ros.spin_for(0.15)
    assert node.simulation.target is not None
    assert ros.spin_until(lambda: node.simulation.target is None, timeout=1.0)


def test_no_hold_starts_a_free_body(ros):
    """hold_initial_anchor false: no target until one is published."""
    node = start_node(ros, rate_hz=200.0, hold_initial_anchor=False)
    assert node.simulation.target is None


def test_sim_time_driven_by_clock(ros):
    """With use_sim_time the ticks follow /clock: grid stamps, catch-up, and a jump back."""
    node = start_node(ros, rate_hz=100.0, use_sim_time=True)
    poses = ros.collect(PoseStamped, 'pose')
    clock = ros.probe.create_publisher(Clock, '/clock', 10)
    assert ros.spin_until(lambda: clock.get_subscription_count() > 0)

    def advance_to(ns: int) -> None:
        message = Clock()
        message.clock.sec, message.clock.nanosec = divmod(ns, 1_000_000_000)
        clock.publish(message)
        ros.spin_until(lambda: node.get_clock().now().nanoseconds == ns, timeout=2.0)
        ros.spin_for(0.03)

    start = 1_000_000_000_000
    for k in range(50):
        advance_to(start + k * 10_000_000)
    stamps = np.array([stamp_ns(m) for m in poses])
    assert len(stamps) >= 45
    np.testing.assert_array_equal(np.diff(stamps), 10_000_000)
    assert (stamps - start) .min() >= 0 and stamps.max() <= start + 49 * 10_000_000
    # A late clock: the missed ticks are all run, on the grid.
    count = len(poses)
    advance_to(start + 57 * 10_000_000)
    stamps = np.array([stamp_ns(m) for m in poses])
    assert len(stamps) - count == 8
    np.testing.assert_array_equal(np.diff(stamps), 10_000_000)
    # Later than the catch-up bound (0.1 s = 10 ticks): the older ticks are dropped.
    count = len(poses)
    advance_to(start + 100 * 10_000_000)
    stamps = np.array([stamp_ns(m) for m in poses[count:]])
    assert len(stamps) == 10 and node.dropped_ticks == 33
    np.testing.assert_array_equal(stamps, start + np.arange(91, 101) * 10_000_000)
    # The clock jumps back (a replay restarts): no burst, the grid restarts there.
    count = len(poses)
    advance_to(start)
    advance_to(start + 10_000_000)
    new = [stamp_ns(m) for m in poses[count:]]
    # rclpy may or may not fire the timer on the backward jump itself; either way one tick each.
    assert new in ([start, start + 10_000_000], [start + 10_000_000])
    assert node.clock_restarts == 1


def test_yaml_lists_exactly_the_declared_parameters(ros):
    """config/params.yaml and the node's declarations are the same set, with matching types."""
    from pathlib import Path
    import yaml
    path = Path(__file__).resolve().parent.parent / 'config' / 'params.yaml'
    values = yaml.safe_load(path.read_text())['/**']['ros__parameters']
    node = start_node(ros)
    rclpy_own = {'use_sim_time', 'start_type_description_service'}
    declared = set(node._parameters) - rclpy_own
    assert set(values) == declared
    for name, value in values.items():
        assert type(value) is type(node.get_parameter(name).value) or (
            isinstance(value, list) and isinstance(node.get_parameter(name).value, list)), name


def test_each_warning_reason_has_its_own_throttle(ros, capfd):
    """A foreign-frame target, then the clock jumps 0.5 s: 'cannot keep' is logged too."""
    node = start_node(ros, use_sim_time=True, rate_hz=100.0)
    target = ros.probe.create_publisher(PointStamped, '/target', 10)
    clock = ros.probe.create_publisher(Clock, '/clock', 10)
    assert ros.spin_until(lambda: clock.get_subscription_count() and
                          target.get_subscription_count())

    def advance(ns):
        message = Clock()
        message.clock.sec, message.clock.nanosec = divmod(ns, 10 ** 9)
        clock.publish(message)
        assert ros.spin_until(lambda: node.get_clock().now().nanoseconds == ns)
        ros.spin_for(0.05)

    advance(10 ** 12)
    target.publish(point_message((0.1, 0.2, 1.0), 'map', 0))
    ros.spin_for(0.1)
    advance(10 ** 12 + 500_000_000)  # 50 ticks due, 10 run, 40 dropped
    assert node.dropped_ticks == 40
    err = capfd.readouterr().err
    assert "ignoring target in frame 'map'" in err
    assert 'cannot keep 100 Hz: dropped 40 ticks' in err, err


def test_atomic_parameter_sets_change_nothing_when_one_value_is_invalid(ros):
    """
    set_parameters_atomically: all or nothing; set_parameters: one by one.

    ``ros2 param load`` takes the second path (a valid ``mass`` lands before an invalid
    ``inertia`` fails); SetParametersAtomically is the all-or-nothing one.
    """
    node = start_node(ros, rate_hz=200.0)
    mass = node.get_parameter('mass').value
    changes = [Parameter('mass', value=mass + 1.0),
               Parameter('inertia', value=[1.0, 0.0, 0.0, 1.0, 0.0, 3.0])]
    before = node.simulation.settings
    result = node.set_parameters_atomically(changes)
    assert not result.successful and 'triangle' in result.reason
    assert node.get_parameter('mass').value == mass
    assert node.simulation.settings is before
    results = node.set_parameters(changes)
    assert [r.successful for r in results] == [True, False]
    assert node.get_parameter('mass').value == mass + 1.0
    assert node.simulation.settings.body.mass == mass + 1.0


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
    assert ros.spin_until(lambda: len(arrays) >= 5, timeout=10.0)
    topic = node.resolve_topic_name('/clock')
    status = rate_of(arrays)
    assert status.level == DiagnosticStatus.WARN
    assert f'waiting for /clock on {topic}' in status.message
    assert {stamp_ns(a) for a in arrays} == {0}
    assert poses == [] and node.ticks_run == 0
    assert ros.spin_until(lambda: f'waiting for /clock on {topic}' in capfd.readouterr().err,
                          timeout=5.0)
    clock = ros.probe.create_publisher(Clock, '/clock', 10)
    assert ros.spin_until(lambda: clock.get_subscription_count() > 0)
    start = 7_000_000_000
    for k in range(30):
        message = Clock()
        message.clock.sec, message.clock.nanosec = divmod(start + k * 10_000_000, 10 ** 9)
        clock.publish(message)
        ros.spin_for(0.02)
    assert poses and stamp_ns(poses[0]) >= start
    count = len(arrays)
    assert ros.spin_until(lambda: len(arrays) > count + 1, timeout=5.0)
    assert 'waiting' not in rate_of(arrays).message
    assert stamp_ns(arrays[-1]) >= start


def test_switching_use_sim_time_off_restarts_the_grid_without_drops(ros, capfd):
    """From simulated to system time the clock leaps forwards: a restart, no ticks dropped."""
    node = start_node(ros, rate_hz=100.0, use_sim_time=True, diagnostics_rate_hz=10.0)
    poses = ros.collect(PoseStamped, 'pose')
    arrays = ros.collect(DiagnosticArray, '/diagnostics')
    clock = ros.probe.create_publisher(Clock, '/clock', 10)
    assert ros.spin_until(lambda: clock.get_subscription_count() > 0)
    for k in range(20):
        message = Clock()
        message.clock.sec, message.clock.nanosec = divmod(5 * 10 ** 9 + k * 10_000_000, 10 ** 9)
        clock.publish(message)
        ros.spin_for(0.02)
    assert node.ticks_run > 0
    assert node.set_parameters([Parameter('use_sim_time', value=False)])[0].successful
    count = len(poses)
    assert ros.spin_until(lambda: len(poses) > count + 20, timeout=5.0)
    assert node.dropped_ticks == 0 and node.clock_restarts == 1
    assert stamp_ns(poses[-1]) > 10 ** 18  # system time now
    count = len(arrays)
    assert ros.spin_until(lambda: len(arrays) > count + 2, timeout=5.0)
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
    clock = ros.probe.create_publisher(Clock, '/clock', 10)
    assert ros.spin_until(lambda: clock.get_subscription_count() > 0)

    def publish(sec: int, nanosec: int = 0) -> None:
        message = Clock()
        message.clock.sec, message.clock.nanosec = sec, nanosec
        clock.publish(message)
        ros.spin_for(0.05)

    publish(5)
    assert node.get_clock().now().nanoseconds == 5 * 10 ** 9
    for _ in range(3):
        publish(-1)
    assert node.get_clock().now().nanoseconds == 5 * 10 ** 9
    publish(5, 500_000_000)
    assert ros.spin_until(lambda: poses and stamp_ns(poses[-1]) == 5_500_000_000, timeout=5.0)
    assert node.set_parameters([Parameter('use_sim_time', value=False)])[0].successful
    assert node.set_parameters([Parameter('use_sim_time', value=True)])[0].successful
    publish(-2)
    publish(6)
    assert node.get_clock().now().nanoseconds == 6 * 10 ** 9
    err = capfd.readouterr().err
    assert err.count('ignoring /clock -1 s 0 ns') == 1, err
    assert 'the clock stays where it was' in err and 'Traceback' not in err


def test_each_declared_range_admits_inf_only_where_the_value_is_taken(ros):
    """
    A descriptor's range tops at .inf only for parameters that take .inf (max_force ...).

    The others (angular_friction, mass, the timeouts ...) take every finite value: their range
    tops at the largest float, so that ``ros2 param describe`` does not offer what is refused.
    """
    import math

    from mouse_constraint_ros.node.parameters import DEFAULTS, node_config, PARAMETERS

    node = start_node(ros)
    checked = 0
    for spec in PARAMETERS:
        if spec.bounds is None or not isinstance(spec.default, float):
            continue
        [descriptor] = node.describe_parameters([spec.name])
        [declared] = descriptor.floating_point_range
        try:
            node_config({**DEFAULTS, spec.name: math.inf})
            takes_inf = True
        except ValueError:
            takes_inf = False
        assert (declared.to_value == math.inf) == takes_inf, spec.name
        checked += 1
    assert checked > 20
    refused = node.set_parameters([Parameter('angular_friction', value=math.inf)])[0]
    assert not refused.successful


def test_ros2_param_load_takes_the_shipped_file_with_its_inf_quoted(ros, tmp_path):
    """
    ``ros2 param load``'s path (rclpy's parameter_dict_from_yaml_file, then one set each).

    The shipped file as it is: every value lands but the ``.inf`` ones, which come back as the
    string 'inf'. Rewritten by the README's sed command (``.inf`` quoted), every one lands.
    """
    import math
    from pathlib import Path
    import re

    from rclpy.parameter import parameter_dict_from_yaml_file

    readme = (Path(__file__).parent.parent / 'README.md').read_text()
    assert r"""sed "s/: \.inf\b/: '.inf'/" config/params.yaml > params_load.yaml""" in readme
    shipped = Path(__file__).parent.parent / 'config' / 'params.yaml'
    quoted = tmp_path / 'params_load.yaml'
    quoted.write_text(re.sub(r': \.inf\b', ": '.inf'", shipped.read_text()))
    node = start_node(ros, max_force=5.0)

    def load(path) -> dict:
        values = parameter_dict_from_yaml_file(str(path), use_wildcard=True)
        return {name: node.set_parameters([Parameter.from_parameter_msg(message)])[0]
                for name, message in values.items() if name != 'use_sim_time'}

    refused = {name for name, result in load(shipped).items() if not result.successful}
    assert refused == {'max_force'}
    assert node.get_parameter('max_force').value == 5.0
    assert all(result.successful for result in load(quoted).values())
    assert node.get_parameter('max_force').value == math.inf
