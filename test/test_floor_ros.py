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

"""The floor through the node: rest, slide and drop, markers, /diagnostics and refusals."""

import math

from diagnostic_msgs.msg import DiagnosticArray
from geometry_msgs.msg import PointStamped, PoseStamped, WrenchStamped
import numpy as np
import pytest
from rclpy.parameter import Parameter
from visualization_msgs.msg import Marker, MarkerArray

from mouse_constraint_ros.node.mouse_constraint_node import MouseConstraintNode
from mouse_constraint_ros.node.startup import StartupRefusal
from mouse_constraint_ros.wire import messages
from test_support import floor_scenarios
from test_support.ros_harness import stamp_of

SHIPPED = floor_scenarios.shipped()
WORLD = floor_scenarios.world()
G = -WORLD.gravity[2]
# As fast as the machine allows, on the node's own clock: the motion is the simulated one.
FAST = {'publish_clock': True, 'real_time_factor': 0.0, 'hold_initial_anchor': False,
        'marker_rate_hz': 0.0, 'diagnostics_rate_hz': 0.0, 'publish_tf': False}


def start(ros, **overrides) -> MouseConstraintNode:
    """Start the node with config/params.yaml (floor on at z = 0) and ``overrides``."""
    values = {**SHIPPED, **FAST, **overrides}
    return ros.add(MouseConstraintNode(context=ros.context, parameter_overrides=[
        Parameter(name, value=value) for name, value in values.items()]))


def run_until(ros, node, seconds: float) -> None:
    """Spin until the node's simulated time reaches ``seconds``."""
    assert ros.spin_until(lambda: node.simulation.time >= seconds, timeout=120.0)


def drain(ros, poses, seconds: float) -> None:
    """Spin until a pose stamped at ``seconds`` or later arrived (some in between may not)."""
    assert ros.spin_until(lambda: poses and 1e-9 * stamp_of(poses[-1]) >= seconds - 0.01,
                          timeout=30.0)


def poses_of(received) -> np.ndarray:
    """Return rows (t, x, y, z) of the received poses."""
    return np.array([(1e-9 * stamp_of(p), p.pose.position.x, p.pose.position.y,
                      p.pose.position.z) for p in received])


def test_a_box_put_on_the_floor_comes_to_rest_and_stays(ros):
    """Put 1 cm above the floor: after 1 s at rest on it, and the poses stay within 0.1 mm."""
    node = start(ros, initial_position=[0.0, 0.0, WORLD.half_height + 0.01])
    poses = ros.collect(PoseStamped, 'pose', depth=10000)
    run_until(ros, node, 1.0)
    state = node.simulation.state
    assert math.hypot(*state.linear_velocity) <= 1e-4
    assert math.hypot(*state.angular_velocity) <= 1e-3
    assert node.simulation.contact_count == 4
    run_until(ros, node, 3.0)
    drain(ros, poses, 3.0)
    path = poses_of(poses)
    settled = path[path[:, 0] >= 1.0]
    assert len(settled) > 100 and settled[-1, 0] - settled[0, 0] >= 1.9
    assert np.max(np.linalg.norm(settled[:, 1:] - settled[0, 1:], axis=1)) <= 1e-4
    assert np.min(settled[:, 3]) >= WORLD.half_height - 1e-3


def test_a_wrench_above_the_friction_bound_slides_the_box_at_f_minus_mu_m_g(ros):
    """A wrench 2 mu m g along x through the COM, on the wrench topic: a = mu g within 2 %."""
    node = start(ros, initial_position=[0.0, 0.0, WORLD.half_height], wrench_timeout=0.0)
    run_until(ros, node, 0.2)
    poses = ros.collect(PoseStamped, 'pose', depth=10000)
    publisher = ros.probe.create_publisher(WrenchStamped, 'wrench', 10)
    assert ros.spin_until(lambda: publisher.get_subscription_count() > 0)
    force = 2.0 * WORLD.floor.friction * WORLD.mass * G
    publisher.publish(messages.wrench_message((force, 0.0, 0.0), (0.0, 0.0, 0.0), ''))
    assert ros.spin_until(lambda: node.simulation.wrench[0][0] == force)
    pushed_at = node.simulation.time
    run_until(ros, node, pushed_at + 1.5)
    drain(ros, poses, pushed_at + 1.5)
    path = poses_of(poses)
    path = path[path[:, 0] > pushed_at + 0.3]
    acceleration = 2.0 * np.polyfit(path[:, 0], path[:, 1], 2)[0]
    expected = (force - WORLD.floor.friction * WORLD.mass * G) / WORLD.mass
    assert acceleration == pytest.approx(expected, rel=0.02)


def test_a_wrench_below_the_friction_bound_does_not_slide_the_box(ros):
    """Half the friction bound, for 2 s: the box moves at most 0.1 mm."""
    node = start(ros, initial_position=[0.0, 0.0, WORLD.half_height], wrench_timeout=0.0)
    run_until(ros, node, 0.2)
    start_x = node.simulation.state.position[0]
    publisher = ros.probe.create_publisher(WrenchStamped, 'wrench', 10)
    assert ros.spin_until(lambda: publisher.get_subscription_count() > 0)
    force = 0.5 * WORLD.floor.friction * WORLD.mass * G
    publisher.publish(messages.wrench_message((force, 0.0, 0.0), (0.0, 0.0, 0.0), ''))
    assert ros.spin_until(lambda: node.simulation.wrench[0][0] == force)
    run_until(ros, node, node.simulation.time + 2.0)
    assert abs(node.simulation.state.position[0] - start_x) <= 1e-4


@pytest.mark.parametrize('restitution, peak', [(0.5, 0.5 ** 2 * 0.5), (0.0, 0.0)])
def test_a_flat_drop_rebounds_to_e_squared_h(ros, restitution, peak):
    """Dropped flat from 0.5 m: the poses rebound to e^2 h within 5 % (e = 0: within 1 mm)."""
    node = start(ros, initial_position=[0.0, 0.0, WORLD.half_height + 0.5],
                 restitution=restitution)
    poses = ros.collect(PoseStamped, 'pose', depth=10000)
    run_until(ros, node, 1.2)
    drain(ros, poses, 1.2)
    path = poses_of(poses)
    bottom = path[:, 3] - WORLD.half_height
    # The first impact and the first rebound's flight, in closed form (some poses may be lost).
    impact = math.sqrt(2.0 * 0.5 / G)
    flight = 2.0 * restitution * impact
    after = (path[:, 0] > impact + 0.02) & (path[:, 0] < impact + max(flight - 0.02, 0.5))
    assert np.count_nonzero(after) > 20
    if restitution == 0.0:
        assert np.max(bottom[after]) <= 1e-3
    else:
        assert np.max(bottom[after]) == pytest.approx(peak, rel=0.05)


def test_the_target_pulling_the_box_into_the_floor_is_held_by_it(ros):
    """A target 0.5 m below the floor, on the target topic: the box goes at most 2 mm in."""
    node = start(ros, initial_position=[0.0, 0.0, WORLD.half_height],
                 hold_initial_anchor=True)
    run_until(ros, node, 0.2)
    publisher = ros.probe.create_publisher(PointStamped, 'target', 10)
    assert ros.spin_until(lambda: publisher.get_subscription_count() > 0)
    anchor = node.simulation.anchor_position()
    goal = (anchor[0], anchor[1], WORLD.floor.height - 0.5)
    publisher.publish(messages.point_message(goal, 'world', 0))
    assert ros.spin_until(lambda: node.simulation.target == goal)
    deepest, end = 0.0, node.simulation.time + 2.0
    while node.simulation.time < end:
        ros.executor.spin_once(timeout_sec=0.01)
        deepest = max(deepest, floor_scenarios.depth(WORLD, node.simulation))
    assert math.hypot(*node.simulation.constraint_force) > 0.5 * WORLD.mass * G
    assert deepest <= 2e-3


def test_markers_draw_the_floor_and_the_contacts_and_diagnostics_count_them(ros):
    """Resting: the floor plate at floor_height, four contact spheres, 'floor contacts' 4."""
    node = start(ros, initial_position=[0.0, 0.0, WORLD.half_height], marker_rate_hz=20.0,
                 diagnostics_rate_hz=10.0, publish_clock=False, real_time_factor=1.0)
    markers = ros.collect(MarkerArray, '/mouse_constraint/markers')
    diagnostics = ros.collect(DiagnosticArray, '/diagnostics')
    assert ros.spin_until(lambda: len(markers) >= 3 and len(diagnostics) >= 3, timeout=20.0)
    by_name = {m.ns: m for m in markers[-1].markers}
    plate, contacts = by_name['floor'], by_name['contacts']
    assert plate.action == Marker.ADD and plate.type == Marker.CUBE
    assert plate.pose.position.z + 0.5 * plate.scale.z == pytest.approx(0.0, abs=1e-12)
    assert contacts.type == Marker.SPHERE_LIST and len(contacts.points) == 4
    for point in contacts.points:
        assert point.z == pytest.approx(0.0, abs=1e-3)
    statuses = {s.name.rpartition(': ')[2]: s for s in diagnostics[-1].status}
    values = {kv.key: kv.value for kv in statuses['constraint'].values}
    assert values['floor contacts'] == '4'
    assert node.simulation.contact_count == 4


@pytest.mark.parametrize('name, value, reason', [
    ('friction', -0.5, 'friction'),
    ('restitution', 1.5, 'restitution'),
    ('floor_height', math.nan, 'floor_height'),
    ('floor_height', 2.0, 'below floor_height'),
])
def test_bad_floor_parameters_are_refused_at_run_time_and_change_nothing(ros, name, value,
                                                                         reason):
    """ros2 param set of a bad value: refused in one line naming it; the settings unchanged."""
    node = start(ros, initial_position=[0.0, 0.0, 1.0])
    before = node.simulation.settings
    [result] = node.set_parameters([Parameter(name, value=value)])
    assert not result.successful
    assert reason in result.reason and '\n' not in result.reason
    assert node.simulation.settings is before


@pytest.mark.parametrize('name, value, reason', [
    ('friction', -0.5, 'friction'),
    ('restitution', 1.5, 'restitution'),
    ('floor_height', math.nan, 'floor_height'),
    ('initial_position', [0.0, 0.0, 0.0], 'below floor_height'),
])
def test_bad_floor_parameters_are_refused_at_start_in_one_line(ros, name, value, reason):
    """At start: StartupRefusal whose one-line reason names the parameter."""
    with pytest.raises(StartupRefusal) as refused:
        start(ros, **{name: value})
    assert reason in str(refused.value) and '\n' not in str(refused.value)


def test_a_run_time_floor_change_takes_effect_and_reset_goes_back_above_it(ros):
    """Raise the floor under a falling box: it lands on the new height; reset goes back up."""
    node = start(ros, initial_position=[0.0, 0.0, 1.0])
    [result] = node.set_parameters([Parameter('floor_height', value=0.3)])
    assert result.successful
    run_until(ros, node, 1.5)
    assert node.simulation.state.position[2] == pytest.approx(0.3 + WORLD.half_height,
                                                              abs=1e-3)
    node.simulation.reset()
    assert node.simulation.state.position == (0.0, 0.0, 1.0)
