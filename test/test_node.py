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
The node in lockstep: targets, bad input, parameters, services, timeout, pose and twist.

Each test steps the node on simulated time (``mouse_constraint_ros.testing``), so the numbers
are exact and the same on every run; the node's own timer is tested in test_node_clock.py.
"""

import math

from geometry_msgs.msg import PoseStamped
import numpy as np
import pytest
from rcl_interfaces.msg import Parameter as ParameterMessage, ParameterType, ParameterValue
from rcl_interfaces.srv import SetParameters
from rclpy.node import Node
from rclpy.parameter import Parameter
from scipy.spatial.transform import Rotation

from mouse_constraint_ros.node.mouse_constraint_node import MouseConstraintNode
from mouse_constraint_ros.node.parameters import PARAMETERS
from mouse_constraint_ros.node.startup import refusal_reason
from mouse_constraint_ros.testing import InputRefused
from mouse_constraint_ros.wire.messages import state_from_messages

ANCHOR = np.array([0.2, 0.1, 0.05])


def anchor_of(pose: PoseStamped) -> np.ndarray:
    """Return the world position of the default anchor for a published pose."""
    p, q = pose.pose.position, pose.pose.orientation
    return np.array([p.x, p.y, p.z]) + Rotation.from_quat([q.x, q.y, q.z, q.w]).apply(ANCHOR)


def start_node(ros, **overrides) -> MouseConstraintNode:
    """Start the node on its own clock in ``ros``'s context, for what needs no tick."""
    return ros.add(MouseConstraintNode(context=ros.context, parameter_overrides=[
        Parameter(name, value=value) for name, value in overrides.items()]))


def recorded(body) -> list:
    """Return the list that each tick appends (pose message, twist message) to."""
    ticks = []
    body.add_tick_callback(lambda b: ticks.append((b.pose.message, b.twist.message)))
    return ticks


def test_every_tick_publishes_pose_and_twist_with_its_simulated_stamp(simulated_body_factory):
    """Tick n is stamped n / rate_hz exactly, pose and twist alike, in frame_id."""
    body = simulated_body_factory(rate_hz=200.0)
    ticks = recorded(body)
    body.step(400)
    stamps = [(p.header.stamp.sec * 10 ** 9 + p.header.stamp.nanosec,
               t.header.stamp.sec * 10 ** 9 + t.header.stamp.nanosec) for p, t in ticks]
    assert stamps == [(n * 5_000_000, n * 5_000_000) for n in range(1, 401)]
    assert {m.header.frame_id for pair in ticks for m in pair} == {'world'}
    assert body.time == 2.0 and body.node.ticker.record.ticks_run == 400


def test_pose_and_twist_agree(simulated_body_factory):
    """
    Finite differences of the pose equal the twist (world frame) of the later tick.

    With one substep per tick the published velocity is the one that carried the pose from one
    tick to the next (symplectic Euler's half-step velocity), so they agree to rounding.
    """
    body = simulated_body_factory(rate_hz=500.0, substeps=1, initial_orientation=[
        0.0, 0.0, 0.3826834323650898, 0.9238795325112867])
    ticks = recorded(body)
    body.step(500)
    states = [state_from_messages(p, t) for p, t in ticks]
    dt = 1.0 / 500.0
    speeds = []
    for before, after in zip(states, states[1:]):
        velocity = (np.array(after.position) - np.array(before.position)) / dt
        np.testing.assert_allclose(velocity, after.linear_velocity, atol=1e-9)
        turn = (Rotation.from_quat(after.orientation) *
                Rotation.from_quat(before.orientation).inv()).as_rotvec() / dt
        np.testing.assert_allclose(turn, after.angular_velocity, atol=1e-6)
        speeds.append(np.linalg.norm(after.angular_velocity))
    assert max(speeds) > 0.5  # it really swings


def test_a_target_is_reached_and_held(simulated_body_factory):
    """
    The anchor goes to a target and stays there while the body swings.

    A jump of the target sets the body swinging and spinning about the anchor; damping lets that
    die down, as a user dragging a body would set it.
    """
    body = simulated_body_factory(rate_hz=500.0, linear_damping=2.0, angular_damping=2.0)
    body.step()
    start = anchor_of(body.pose.message)
    target = (0.4, -0.3, 1.2)
    body.target(target)
    ticks = recorded(body)
    body.step(1750)
    errors = [np.linalg.norm(anchor_of(pose) - target) for pose, _ in ticks[-100:]]
    assert max(errors) < 1e-4
    # And the body moved there: its anchor is far from where it started.
    assert np.linalg.norm(anchor_of(ticks[-1][0]) - start) > 0.3


@pytest.mark.parametrize('point, frame_id, key', [
    ((math.nan, 0.0, 1.0), 'world', 'finite'),
    ((0.0, math.inf, 1.0), 'world', 'finite'),
    ((0.0, 0.0, -math.inf), 'world', 'finite'),
    ((1e300, 0.0, 0.0), 'world', 'workspace'),
    ((0.0, 7.1e3, 7.1e3), 'world', 'workspace'),
    ((0.5, 0.5, 0.5), 'map', 'frame'),
])
def test_bad_targets_are_ignored(simulated_body_factory, point, frame_id, key):
    """Non-finite or too far points and foreign frames change nothing; outputs stay finite."""
    body = simulated_body_factory(rate_hz=200.0)
    body.step(10)
    held = body.node.simulation.target
    with pytest.raises(InputRefused) as refused:
        body.target(point, frame_id=frame_id)
    assert refused.value.key == key
    body.step(60)
    assert body.node.simulation.target == held
    assert np.isfinite(anchor_of(body.pose.message)).all()
    # An empty frame_id is taken as frame_id.
    body.target((0.1, 0.2, 0.3), frame_id='')
    assert body.node.simulation.target == (0.1, 0.2, 0.3)


def test_parameter_updates_apply_and_invalid_ones_are_rejected(simulated_body_factory):
    """Valid values reach the simulation at once; invalid ones fail with a reason."""
    body = simulated_body_factory(rate_hz=200.0)
    body.set_parameters(mass=3.0, frequency_hz=4.0)
    simulation = body.node.simulation
    assert simulation.settings.body.mass == 3.0
    assert simulation.settings.constraint.frequency_hz == 4.0
    before = simulation.settings
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
        with pytest.raises(ValueError, match=reason):
            body.set_parameters(**{name: value})
    assert simulation.settings is before
    assert body.node.get_parameter('mass').value == 3.0


@pytest.mark.parametrize('name, value', [
    ('mass', -1.0), ('mass', math.nan), ('mass', 1e200), ('substeps', 2.5),
    ('substeps', 0), ('rate_hz', 0.5), ('grab_margin', -1.0), ('max_force', math.nan),
])
def test_a_change_rclpy_refuses_reads_as_the_same_value_refused_at_start(
        simulated_body_factory, name, value):
    """
    A type or a declared range refused at run time: the start-up's reason, never rclpy's text.

    rclpy checks the type and the range before the node's callback; its words ("Wrong parameter
    type", "out of range Min: 0.0, Max: 1.797e308") are replaced by the node's own.
    """
    body = simulated_body_factory(rate_hz=200.0)
    with pytest.raises(ValueError) as refused:
        body.set_parameters(**{name: value})
    given = (value, Parameter.Type.from_parameter_value(value).name)
    spec = next(p for p in PARAMETERS if p.name == name)
    assert str(refused.value) == refusal_reason(spec, '', given)
    assert 'Min:' not in str(refused.value) and 'Type.' not in str(refused.value)


def test_parameter_service_like_ros2_param_set(simulated_body_factory):
    """The same through the SetParameters service that `ros2 param set` calls."""
    body = simulated_body_factory(rate_hz=200.0)
    caller = body.add_node(Node('caller', context=body.context))
    client = caller.create_client(SetParameters, '/mouse_constraint/set_parameters')
    body.step()
    assert client.service_is_ready()
    future = client.call_async(SetParameters.Request(parameters=[
        ParameterMessage(name='gravity', value=ParameterValue(
            type=ParameterType.PARAMETER_DOUBLE_ARRAY, double_array_value=[0.0, 0.0, -1.0])),
        ParameterMessage(name='max_force', value=ParameterValue(
            type=ParameterType.PARAMETER_DOUBLE, double_value=-5.0)),
    ]))
    body.step()
    results = future.result().results
    assert [r.successful for r in results] == [True, False]
    assert 'max_force' in results[1].reason
    assert body.node.simulation.settings.gravity == (0.0, 0.0, -1.0)


def test_rate_can_change_between_steps(simulated_body_factory):
    """A new rate_hz goes on from the simulated time reached, at the new period."""
    body = simulated_body_factory(rate_hz=100.0)
    body.step(30)
    assert body.time == pytest.approx(0.3, abs=1e-12)
    body.set_parameters(rate_hz=400.0)
    ticks = recorded(body)
    body.step(300)
    stamps = np.array([p.header.stamp.sec * 10 ** 9 + p.header.stamp.nanosec
                       for p, _ in ticks])
    np.testing.assert_array_equal(stamps, 300_000_000 + 2_500_000 * np.arange(1, 301))


def test_reset_and_release_services(simulated_body_factory):
    """~/release frees the body (it falls); ~/reset restores the initial state and the hold."""
    body = simulated_body_factory(rate_hz=200.0)
    # A target where the anchor already is: the body hangs there at rest.
    body.target((0.2, 0.1, 1.05))
    assert body.release() == 'released'
    assert body.node.simulation.target is None
    body.step(60)
    # Free fall from rest for 0.3 s (the held body was still): the published velocity is the
    # one of the last half substep (h = 2.5 ms), symplectic Euler's.
    assert body.twist.linear[2] == pytest.approx(-9.80665 * (0.3 - 0.00125), rel=1e-12)
    assert body.reset() == 'back to the initial state, anchor held where it starts'
    assert body.node.simulation.target == pytest.approx(tuple(np.array([0.0, 0.0, 1.0]) + ANCHOR))
    assert body.node.simulation.state.position == (0.0, 0.0, 1.0)


def test_target_timeout_releases_the_body(simulated_body_factory):
    """With target_timeout > 0 the body is released at the first tick past the timeout."""
    body = simulated_body_factory(rate_hz=200.0, target_timeout=0.3)
    body.step(10)
    body.target((0.2, 0.0, 1.0))
    given = body.time
    body.step_until(lambda: body.node.simulation.target is None, max_ticks=100)
    # 0.3 s after it came, the first tick later than that lets go.
    assert body.time == pytest.approx(given + 0.3 + 0.005, abs=1e-12)


def test_no_hold_starts_a_free_body(simulated_body_factory):
    """hold_initial_anchor false: no target until one is sent."""
    body = simulated_body_factory(rate_hz=200.0, hold_initial_anchor=False)
    assert body.node.simulation.target is None
    body.step(20)
    assert body.twist.linear[2] == pytest.approx(-9.80665 * (0.1 - 0.00125), rel=1e-12)


def test_atomic_parameter_sets_change_nothing_when_one_value_is_invalid(simulated_body_factory):
    """
    set_parameters_atomically: all or nothing; set_parameters: one by one.

    ``ros2 param load`` takes the second path (a valid ``mass`` lands before an invalid
    ``inertia`` fails); SetParametersAtomically is the all-or-nothing one.
    """
    body = simulated_body_factory(rate_hz=200.0)
    node = body.node
    mass = node.get_parameter('mass').value
    before = node.simulation.settings
    with pytest.raises(ValueError, match='triangle'):
        body.set_parameters(mass=mass + 1.0, inertia=[1.0, 0.0, 0.0, 1.0, 0.0, 3.0])
    assert node.get_parameter('mass').value == mass
    assert node.simulation.settings is before
    results = node.set_parameters([Parameter('mass', value=mass + 1.0),
                                   Parameter('inertia', value=[1.0, 0.0, 0.0, 1.0, 0.0, 3.0])])
    assert [r.successful for r in results] == [True, False]
    assert node.get_parameter('mass').value == mass + 1.0
    assert node.simulation.settings.body.mass == mass + 1.0


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
    string 'inf'. Rewritten by docs/reliability.md's sed command (``.inf`` quoted), all land.
    """
    import math
    from pathlib import Path
    import re

    from rclpy.parameter import parameter_dict_from_yaml_file

    page = (Path(__file__).parent.parent / 'docs' / 'reliability.md').read_text()
    assert r"""sed "s/: \.inf\b/: '.inf'/" config/params.yaml > params_load.yaml""" in page
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
