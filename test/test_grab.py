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
Grabbing the body where it is clicked: the pure box test, and the node's ``grab`` topic.

The node's callbacks are called directly where the test needs the body's pose exactly (no tick
runs between building a message and its use); the topic, parameter service and markers are
checked with the node spinning on a body at rest (no gravity, nothing held).
"""

import itertools
import math

from geometry_msgs.msg import PointStamped
import numpy as np
import pytest
from rcl_interfaces.srv import GetParameters
from rclpy.parameter import Parameter
from scipy.spatial.transform import Rotation
from std_srvs.srv import Trigger
from visualization_msgs.msg import MarkerArray

from mouse_constraint_ros.inputs.grab import box_distance, grab, to_body_frame
from mouse_constraint_ros.node.mouse_constraint_node import MouseConstraintNode
from mouse_constraint_ros.node.parameters import DEFAULTS
from mouse_constraint_ros.physics import BodyState
from mouse_constraint_ros.wire.messages import point_message

BOX = (0.4, 0.2, 0.1)
HALF = np.array(BOX) / 2.0
MARGIN = DEFAULTS['grab_margin']
CONFIGURED = [0.2, 0.1, 0.05]
POSITION = (0.3, -0.2, 1.1)
ORIENTATION = tuple(Rotation.from_euler('xyz', [0.4, -0.7, 1.9]).as_quat())
STATE = BodyState(POSITION, ORIENTATION)
# On the box: the centres of the six faces, points on edges, the eight corners, inside; and
# just outside, within the margin.
FACES = [tuple(s * HALF[i] if j == i else 0.0 for j in range(3))
         for i in range(3) for s in (-1.0, 1.0)]
EDGES = [(HALF[0], -HALF[1], 0.03), (-0.05, HALF[1], HALF[2]), (-HALF[0], 0.07, -HALF[2])]
CORNERS = [tuple(s * HALF) for s in itertools.product((-1.0, 1.0), repeat=3)]
INSIDE = [(0.0, 0.0, 0.0), (0.13, -0.04, 0.01), tuple(0.999 * HALF)]
NEAR = [(HALF[0] + 0.9 * MARGIN, 0.0, 0.0), tuple(HALF + 0.5 * MARGIN / math.sqrt(3.0))]
ON_BODY = FACES + EDGES + CORNERS + INSIDE + NEAR
# Off the box by more than the margin: along a face normal, off an edge (each coordinate is
# within the margin, the distance is not), off a corner, and far away.
OFF_BODY = [(HALF[0] + 3.0 * MARGIN, 0.0, 0.0), (0.0, -HALF[1] - 2.0 * MARGIN, 0.0),
            (HALF[0] + 0.8 * MARGIN, HALF[1] + 0.8 * MARGIN, 0.0), tuple(HALF + MARGIN),
            (5.0, 0.0, 0.0)]


def world(local, state=STATE) -> tuple:
    """Return the world position of a body-frame point of ``state`` (scipy's rotation)."""
    rotation = Rotation.from_quat(state.orientation)
    return tuple(float(c) for c in np.array(state.position) + rotation.apply(local))


def expected_distance(local) -> float:
    """Return the distance of a body-frame point from BOX, from its excess over the halves."""
    return float(np.linalg.norm(np.maximum(np.abs(local) - HALF, 0.0)))


def grab_message(point, frame_id='world') -> PointStamped:
    """Return a grab message for ``point``."""
    return point_message(point, frame_id, 0)


def start_node(ros, **overrides) -> MouseConstraintNode:
    """Start the node with the box posed at STATE, anchor CONFIGURED, monitors off."""
    values = {'box_size': list(BOX), 'anchor': CONFIGURED, 'initial_position': list(POSITION),
              'initial_orientation': list(ORIENTATION), 'marker_rate_hz': 0.0,
              'diagnostics_rate_hz': 0.0, 'rate_hz': 100.0}
    values.update(overrides)
    return ros.add(MouseConstraintNode(context=ros.context, parameter_overrides=[
        Parameter(name, value=value) for name, value in values.items()]))


def warnings_of(node: MouseConstraintNode) -> list:
    """Replace the node's throttled warnings by a list of (reason, text); return the list."""
    warnings = []
    node._warn = lambda reason, message: warnings.append((reason, message()))
    return warnings


def anchor_parameter(node: MouseConstraintNode) -> list:
    """Return the node's anchor parameter as a list of floats."""
    return list(node.get_parameter('anchor').value)


# The pure part.

@pytest.mark.parametrize('local', ON_BODY + OFF_BODY)
def test_box_distance_is_the_norm_of_the_excess_over_the_half_edges(local):
    """0 on and inside the box; outside, the Euclidean distance to the nearest box point."""
    distance = box_distance(local, BOX)
    nearest = np.clip(local, -HALF, HALF)
    assert distance == pytest.approx(float(np.linalg.norm(np.array(local) - nearest)),
                                     abs=1e-15)
    if local in FACES + EDGES + CORNERS + INSIDE:
        assert distance == 0.0


def test_body_frame_inverts_the_pose():
    """to_body_frame(x + R r) = r, with R from scipy, for points on and off the box."""
    for local in ON_BODY + OFF_BODY:
        np.testing.assert_allclose(to_body_frame(STATE, world(local)), local, atol=1e-12)


def test_grab_is_taken_exactly_within_the_margin():
    """A point taken or not depending on whether its distance is at most the margin."""
    for local in ON_BODY:
        assert grab(STATE, BOX, world(local)).taken(MARGIN), local
    for local in OFF_BODY:
        landed = grab(STATE, BOX, world(local))
        assert not landed.taken(MARGIN), local
        assert landed.taken(landed.distance)


# The node.

@pytest.mark.parametrize('local', ON_BODY)
def test_a_point_on_the_body_becomes_the_anchor_and_the_target(ros, local):
    """Anchor (parameter and settings) = the point in the body frame; the target is the point."""
    node = start_node(ros)
    warnings = warnings_of(node)
    point = world(local)
    node._on_grab(grab_message(point))
    assert warnings == []
    np.testing.assert_allclose(anchor_parameter(node), local, rtol=0.0, atol=1e-9)
    assert node.simulation.settings.constraint.anchor == tuple(anchor_parameter(node))
    assert node.simulation.target == point
    # Nothing jumps: the anchor is where the target is.
    assert np.linalg.norm(node.simulation.anchor_error()) < 1e-12


@pytest.mark.parametrize('local', OFF_BODY)
def test_a_point_off_the_body_changes_nothing_and_says_how_far_off(ros, local):
    """Settings, target, state and parameter are the very same; one warning with the distance."""
    node = start_node(ros)
    warnings = warnings_of(node)
    before = (node.simulation.settings, node.simulation.target, node.simulation.state,
              anchor_parameter(node), node._config)
    node._on_grab(grab_message(world(local)))
    after = (node.simulation.settings, node.simulation.target, node.simulation.state,
             anchor_parameter(node), node._config)
    assert after == before and after[0] is before[0] and after[4] is before[4]
    [(reason, text)] = warnings
    assert reason == 'grab off body'
    assert f'{expected_distance(local):.6g} m off the body' in text
    assert f'grab_margin {MARGIN:g} m' in text


@pytest.mark.parametrize('point, frame, key', [
    ((0.3, -0.2, 1.1), 'map', 'frame'),
    ((math.nan, -0.2, 1.1), 'world', 'finite'),
    ((0.3, math.inf, 1.1), '', 'finite'),
    ((1e9, 0.0, 0.0), 'world', 'workspace'),
])
def test_grabs_the_target_gate_refuses_change_nothing(ros, point, frame, key):
    """Frame, finiteness and workspace as for targets, under the gate's key after 'grab '."""
    node = start_node(ros)
    warnings = warnings_of(node)
    before = (node.simulation.settings, node.simulation.target, anchor_parameter(node))
    node._on_grab(grab_message(point, frame))
    assert (node.simulation.settings, node.simulation.target, anchor_parameter(node)) == before
    [(reason, text)] = warnings
    refusal = node._gate.refusal(frame, point)
    assert reason == 'grab ' + key == 'grab ' + refusal.key
    assert text == f'ignoring grab {refusal.reason}'


def test_an_anchor_the_configuration_refuses_is_not_grabbed(ros):
    """A corner too far out for a body of tiny inertia: the reason of node_config, no change."""
    node = start_node(ros, anchor=[0.0, 0.0, 0.0], inertia=[1e-13, 0.0, 0.0, 1e-13, 0.0, 1e-13])
    warnings = warnings_of(node)
    before = (node.simulation.settings, node.simulation.target, anchor_parameter(node))
    node._on_grab(grab_message(world(CORNERS[0])))
    assert (node.simulation.settings, node.simulation.target, anchor_parameter(node)) == before
    [(reason, text)] = warnings
    assert reason == 'grab anchor' and 'too ill-conditioned' in text
    # A face centre nearer the COM is within reach.
    node._on_grab(grab_message(world(FACES[4])))
    np.testing.assert_allclose(anchor_parameter(node), FACES[4], atol=1e-9)


def test_the_grab_margin_is_a_run_time_parameter(ros):
    """A point refused at the default margin is taken once grab_margin covers it."""
    node = start_node(ros)
    warnings = warnings_of(node)
    local = OFF_BODY[0]
    node._on_grab(grab_message(world(local)))
    assert len(warnings) == 1
    assert node.set_parameters([Parameter('grab_margin', value=4.0 * MARGIN)])[0].successful
    node._on_grab(grab_message(world(local)))
    np.testing.assert_allclose(anchor_parameter(node), local, atol=1e-9)
    [result] = node.set_parameters([Parameter('grab_margin', value=-1.0)])
    assert not result.successful and 'grab_margin' in result.reason


def test_the_gate_follows_frame_id_and_workspace_radius(ros):
    """Changed at run time, both gate targets and grabs at once."""
    node = start_node(ros)
    warnings = warnings_of(node)
    point = world(FACES[0])
    assert node.set_parameters([Parameter('frame_id', value='odom')])[0].successful
    node._on_target(grab_message((0.0, 0.0, 1.0), 'world'))
    node._on_grab(grab_message(point, 'world'))
    assert [reason for reason, _ in warnings] == ['frame', 'grab frame']
    node._on_grab(grab_message(point, 'odom'))
    assert node.simulation.target == point
    assert node.set_parameters([Parameter('workspace_radius', value=0.5)])[0].successful
    node._on_target(grab_message((0.0, 0.0, 1.0), 'odom'))
    assert warnings[-1][0] == 'workspace' and node.simulation.target == point


def test_other_parameter_changes_keep_the_grabbed_anchor(ros):
    """The configuration is rebuilt from the parameters, which hold the grabbed point."""
    node = start_node(ros)
    node._on_grab(grab_message(world(CORNERS[0])))
    grabbed = anchor_parameter(node)
    assert node.set_parameters([Parameter('mass', value=3.0)])[0].successful
    assert node.simulation.settings.body.mass == 3.0
    assert node.simulation.settings.constraint.anchor == tuple(grabbed)


def test_reset_restores_the_configured_anchor_and_release_keeps_the_grabbed_one(ros):
    """~/release lets go (the grabbed point stays the anchor); ~/reset restores the start's."""
    node = start_node(ros, gravity=[0.0, 0.0, 0.0], hold_initial_anchor=True)
    local = EDGES[1]
    node._on_grab(grab_message(world(local)))
    response = ros.call(Trigger, '/mouse_constraint/release', Trigger.Request())
    assert response.success and response.message == 'released'
    assert node.simulation.target is None
    np.testing.assert_allclose(anchor_parameter(node), local, atol=1e-9)
    # A target after the release drags the grabbed point again.
    node._on_target(grab_message((0.5, 0.0, 1.0)))
    assert node.simulation.target == (0.5, 0.0, 1.0)
    response = ros.call(Trigger, '/mouse_constraint/reset', Trigger.Request())
    assert response.success
    assert anchor_parameter(node) == CONFIGURED
    assert node.simulation.settings.constraint.anchor == tuple(CONFIGURED)
    assert node.simulation.state.position == pytest.approx(POSITION, abs=1e-3)
    np.testing.assert_allclose(node.simulation.target, world(CONFIGURED), atol=1e-12)


def test_an_anchor_set_through_the_parameters_is_the_one_reset_restores(ros):
    """ros2 param set anchor configures it; a grab afterwards does not; reset gives it back."""
    node = start_node(ros)
    configured = [-0.1, 0.05, 0.0]
    assert node.set_parameters([Parameter('anchor', value=configured)])[0].successful
    node._on_grab(grab_message(world(CORNERS[3])))
    assert anchor_parameter(node) != configured
    node._on_reset(Trigger.Request(), Trigger.Response())
    assert anchor_parameter(node) == configured


def test_reset_says_when_the_configured_anchor_no_longer_fits(ros):
    """Inertia made tiny while a near point is grabbed: the start's corner is refused."""
    node = start_node(ros)
    node._on_grab(grab_message(world(INSIDE[0])))
    assert node.set_parameters([Parameter(
        'inertia', value=[1e-13, 0.0, 0.0, 1e-13, 0.0, 1e-13])])[0].successful
    state, target = node.simulation.state, node.simulation.target
    response = node._on_reset(Trigger.Request(), Trigger.Response())
    assert not response.success
    assert 'cannot restore the configured anchor' in response.message
    assert 'too ill-conditioned' in response.message
    assert node.simulation.state is state and node.simulation.target == target


def test_grab_topic_parameter_service_and_markers_show_the_grabbed_point(ros):
    """
    Through the topic: ros2 param get shows the point, the markers' anchor is it, targets drag it.

    The body rests at STATE (no gravity, free): the point is on the body when it arrives.
    """
    node = start_node(ros, gravity=[0.0, 0.0, 0.0], hold_initial_anchor=False,
                      marker_rate_hz=50.0, linear_damping=5.0, angular_damping=5.0)
    arrays = ros.collect(MarkerArray, '/mouse_constraint/markers')
    publisher = ros.probe.create_publisher(PointStamped, 'grab', 10)
    assert ros.spin_until(lambda: publisher.get_subscription_count() > 0)
    local = EDGES[0]
    point = world(local)
    publisher.publish(grab_message(point, ''))
    assert ros.spin_until(lambda: node.simulation.target == point)
    response = ros.call(GetParameters, '/mouse_constraint/get_parameters',
                        GetParameters.Request(names=['anchor']))
    np.testing.assert_allclose(response.values[0].double_array_value, local, atol=1e-9)
    count = len(arrays)
    assert ros.spin_until(lambda: len(arrays) > count + 2)
    markers = {m.ns: m for m in arrays[-1].markers}
    body = markers['body'].pose
    state = BodyState((body.position.x, body.position.y, body.position.z),
                      (body.orientation.x, body.orientation.y, body.orientation.z,
                       body.orientation.w))
    sphere = markers['anchor'].pose.position
    np.testing.assert_allclose((sphere.x, sphere.y, sphere.z), world(local, state), atol=1e-9)
    np.testing.assert_allclose((sphere.x, sphere.y, sphere.z), point, atol=1e-9)
    # A later target drags the grabbed point there (the damping stops the swing it starts).
    target = (point[0] + 0.1, point[1], point[2] + 0.05)
    targets = ros.probe.create_publisher(PointStamped, 'target', 10)
    assert ros.spin_until(lambda: targets.get_subscription_count() > 0)
    targets.publish(grab_message(target))
    assert ros.spin_until(lambda: node.simulation.target == target)
    assert ros.spin_until(lambda: np.linalg.norm(node.simulation.anchor_error()) < 1e-4)
    np.testing.assert_allclose(anchor_parameter(node), local, atol=1e-9)


def test_a_flood_of_grabs_logs_short_throttled_lines(ros, capfd):
    """
    500 grabs in a burst: each one is taken, and the log has at most a short line per period.

    A grab sets the node's own anchor parameter; that change used to log the whole summary
    (some 450 characters) every time.
    """
    node = start_node(ros)
    # A throttled warning first: the notes must not share its call site (rclpy refuses one
    # call site at two severities).
    node._on_grab(grab_message((50.0, 50.0, 50.0)))
    capfd.readouterr()
    local = ON_BODY[0]
    for _ in range(500):
        node._on_grab(grab_message(world(local)))
    np.testing.assert_allclose(anchor_parameter(node), local, rtol=0.0, atol=1e-9)
    lines = [line for line in capfd.readouterr().err.splitlines() if line.strip()]
    assert 'parameters changed' not in ''.join(lines)
    assert 1 <= len(lines) <= 2 and all(len(line) < 160 for line in lines), lines
    assert 'set by the node' in lines[0]
    # A change through the parameters still logs the summary.
    assert node.set_parameters([Parameter('mass', value=3.0)])[0].successful
    assert 'parameters changed' in capfd.readouterr().err


def test_a_corner_exactly_on_the_box_is_taken_at_margin_zero():
    """
    Every corner of boxes resting in many poses, placed by the pose, is taken at margin 0.

    Turned into the body frame it lands a few 1e-17 m off the box: rounding, not distance.
    A point a whole millimetre out is still refused at margin 0.
    """
    rng = np.random.default_rng(7)
    for _ in range(200):
        orientation = tuple(Rotation.random(random_state=rng).as_quat())
        state = BodyState(tuple(rng.uniform(-5.0, 5.0, 3)), orientation).validated()
        for signs in itertools.product((-1.0, 1.0), repeat=3):
            corner = tuple(float(s * h) for s, h in zip(signs, HALF))
            assert grab(state, BOX, state.world_point(corner)).taken(0.0), (state, corner)
            out = tuple(c + 1e-3 * s for c, s in zip(corner, signs))
            assert not grab(state, BOX, state.world_point(out)).taken(0.0)


def test_a_refusal_shows_the_digits_that_tell_value_and_bound_apart(ros):
    """|torque| just over 100 is not '100 exceeds 100'; a grab just beyond the margin neither."""
    from mouse_constraint_ros.inputs.target_gate import apart
    from mouse_constraint_ros.inputs.wrench_gate import WrenchGate

    assert apart(100.00000000000001, 100.0) == ('100.00000000000001', '100.0')
    assert apart(150.0, 100.0) == ('150', '100')
    gate = WrenchGate('world', 1000.0, 100.0)
    refusal = gate.refusal('', (0.0, 0.0, 0.0), (100.00000000000001, 0.0, 0.0))
    assert '|torque| 100.00000000000001 N m exceeds max_wrench_torque 100.0 N m' in refusal.reason
    node = start_node(ros, grab_margin=0.01)
    warnings = warnings_of(node)
    node._on_grab(grab_message(world((HALF[0] + 0.010000001, 0.0, 0.0))))
    [(_, text)] = warnings
    assert 'm off the body, farther than grab_margin 0.01 m' in text
    assert ' 0.01 m off' not in text
