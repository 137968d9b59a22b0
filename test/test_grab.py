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

The node is stepped in lockstep (``mouse_constraint_ros.testing``): a grab sent before the first
tick meets the body exactly at its initial pose. The parameter service and markers are checked
on a body at rest (no gravity, nothing held).
"""

import itertools
import math
import re
import time

import numpy as np
import pytest
from rcl_interfaces.srv import GetParameters
from rclpy.node import Node
from scipy.spatial.transform import Rotation
from visualization_msgs.msg import MarkerArray

from mouse_constraint_ros.description import BodyGeometry
from mouse_constraint_ros.inputs.grab import box_distance, grab, to_body_frame
from mouse_constraint_ros.inputs.target_gate import TargetGate
from mouse_constraint_ros.node.mouse_constraint_node import WARN_PERIOD
from mouse_constraint_ros.node.parameters import DEFAULTS
from mouse_constraint_ros.physics import BodyState
from mouse_constraint_ros.testing import InputRefused

BOX = (0.4, 0.2, 0.1)
BOX_SHAPE = BodyGeometry.box(BOX)
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


def make_body(factory, **overrides):
    """Return a simulated body with the box posed at STATE, anchor CONFIGURED, monitors off."""
    values = {'box_size': list(BOX), 'anchor': CONFIGURED, 'initial_position': list(POSITION),
              'initial_orientation': list(ORIENTATION), 'marker_rate_hz': 0.0,
              'diagnostics_rate_hz': 0.0, 'rate_hz': 100.0}
    values.update(overrides)
    return factory(**values)


def anchor_parameter(node) -> list:
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
        assert grab(STATE, BOX_SHAPE, world(local)).taken(MARGIN), local
    for local in OFF_BODY:
        landed = grab(STATE, BOX_SHAPE, world(local))
        assert not landed.taken(MARGIN), local
        assert landed.taken(landed.distance)


# The node, stepped in lockstep: it has not ticked when a grab comes, so the body is at STATE.

@pytest.mark.parametrize('local', ON_BODY)
def test_a_point_on_the_body_becomes_the_anchor_and_the_target(simulated_body_factory, local):
    """Anchor (parameter and settings) = the point in the body frame; the target is the point."""
    body = make_body(simulated_body_factory)
    node = body.node
    point = world(local)
    anchor = body.grab(point)
    np.testing.assert_allclose(anchor, local, rtol=0.0, atol=1e-9)
    assert anchor_parameter(node) == list(anchor)
    assert node.simulation.settings.constraint.anchor == anchor
    assert node.simulation.target == point
    # Nothing jumps: the anchor is where the target is.
    assert np.linalg.norm(node.simulation.anchor_error()) < 1e-12
    assert node.refusals == (0, None)


@pytest.mark.parametrize('local', OFF_BODY)
def test_a_point_off_the_body_changes_nothing_and_says_how_far_off(simulated_body_factory,
                                                                   local):
    """Settings, target, state and parameter are the very same; the refusal gives the distance."""
    body = make_body(simulated_body_factory)
    node = body.node
    before = (node.simulation.settings, node.simulation.target, node.simulation.state,
              anchor_parameter(node))
    with pytest.raises(InputRefused) as refused:
        body.grab(world(local))
    after = (node.simulation.settings, node.simulation.target, node.simulation.state,
             anchor_parameter(node))
    assert after == before and after[0] is before[0]
    assert refused.value.key == 'grab off body'
    assert f'{expected_distance(local):.6g} m off the body' in str(refused.value)
    assert f'grab_margin {MARGIN:g} m' in str(refused.value)
    assert node.refusals[0] == 1


@pytest.mark.parametrize('point, frame, key', [
    ((0.3, -0.2, 1.1), 'map', 'frame'),
    ((math.nan, -0.2, 1.1), 'world', 'finite'),
    ((0.3, math.inf, 1.1), '', 'finite'),
    ((1e9, 0.0, 0.0), 'world', 'workspace'),
])
def test_grabs_the_target_gate_refuses_change_nothing(simulated_body_factory, point, frame, key):
    """Frame, finiteness and workspace as for targets, under the gate's key after 'grab '."""
    body = make_body(simulated_body_factory)
    node = body.node
    before = (node.simulation.settings, node.simulation.target, anchor_parameter(node))
    with pytest.raises(InputRefused) as refused:
        body.grab(point, frame_id=frame)
    assert (node.simulation.settings, node.simulation.target, anchor_parameter(node)) == before
    refusal = TargetGate('world', DEFAULTS['workspace_radius']).refusal(frame, point)
    assert refused.value.key == 'grab ' + key == 'grab ' + refusal.key
    assert str(refused.value) == refusal.reason


def test_an_anchor_the_configuration_refuses_is_not_grabbed(simulated_body_factory):
    """A corner too far out for a body of tiny inertia: the reason of node_config, no change."""
    body = make_body(simulated_body_factory, anchor=[0.0, 0.0, 0.0],
                     inertia=[1e-13, 0.0, 0.0, 1e-13, 0.0, 1e-13])
    node = body.node
    before = (node.simulation.settings, node.simulation.target, anchor_parameter(node))
    with pytest.raises(InputRefused, match='too ill-conditioned') as refused:
        body.grab(world(CORNERS[0]))
    assert refused.value.key == 'grab anchor'
    assert (node.simulation.settings, node.simulation.target, anchor_parameter(node)) == before
    # A face centre nearer the COM is within reach.
    body.grab(world(FACES[4]))
    np.testing.assert_allclose(anchor_parameter(node), FACES[4], atol=1e-9)


def test_the_grab_margin_is_a_run_time_parameter(simulated_body_factory):
    """A point refused at the default margin is taken once grab_margin covers it."""
    body = make_body(simulated_body_factory)
    local = OFF_BODY[0]
    with pytest.raises(InputRefused):
        body.grab(world(local))
    body.set_parameters(grab_margin=4.0 * MARGIN)
    body.grab(world(local))
    np.testing.assert_allclose(anchor_parameter(body.node), local, atol=1e-9)
    with pytest.raises(ValueError, match='grab_margin'):
        body.set_parameters(grab_margin=-1.0)


def test_the_gate_follows_frame_id_and_workspace_radius(simulated_body_factory):
    """Changed at run time, both gate targets and grabs at once."""
    body = make_body(simulated_body_factory)
    point = world(FACES[0])
    body.set_parameters(frame_id='odom')
    keys = []
    for send in (lambda: body.target((0.0, 0.0, 1.0), frame_id='world'),
                 lambda: body.grab(point, frame_id='world')):
        with pytest.raises(InputRefused) as refused:
            send()
        keys.append(refused.value.key)
    assert keys == ['frame', 'grab frame']
    body.grab(point, frame_id='odom')
    assert body.node.simulation.target == point
    body.set_parameters(workspace_radius=0.5)
    with pytest.raises(InputRefused) as refused:
        body.target((0.0, 0.0, 1.0), frame_id='odom')
    assert refused.value.key == 'workspace' and body.node.simulation.target == point


def test_other_parameter_changes_keep_the_grabbed_anchor(simulated_body_factory):
    """The configuration is rebuilt from the parameters, which hold the grabbed point."""
    body = make_body(simulated_body_factory)
    grabbed = body.grab(world(CORNERS[0]))
    body.set_parameters(mass=3.0)
    assert body.node.simulation.settings.body.mass == 3.0
    assert body.node.simulation.settings.constraint.anchor == grabbed


def test_reset_restores_the_configured_anchor_and_release_keeps_the_grabbed_one(
        simulated_body_factory):
    """~/release lets go (the grabbed point stays the anchor); ~/reset restores the start's."""
    body = make_body(simulated_body_factory, gravity=[0.0, 0.0, 0.0], hold_initial_anchor=True)
    node = body.node
    local = EDGES[1]
    body.grab(world(local))
    assert body.release() == 'released'
    assert node.simulation.target is None
    np.testing.assert_allclose(anchor_parameter(node), local, atol=1e-9)
    # A target after the release drags the grabbed point again.
    body.target((0.5, 0.0, 1.0))
    assert node.simulation.target == (0.5, 0.0, 1.0)
    body.step(10)
    body.reset()
    assert anchor_parameter(node) == CONFIGURED
    assert node.simulation.settings.constraint.anchor == tuple(CONFIGURED)
    assert node.simulation.state == STATE.validated()
    np.testing.assert_allclose(node.simulation.target, world(CONFIGURED), atol=1e-12)


def test_an_anchor_set_through_the_parameters_is_the_one_reset_restores(simulated_body_factory):
    """ros2 param set anchor configures it; a grab afterwards does not; reset gives it back."""
    body = make_body(simulated_body_factory)
    configured = [-0.1, 0.05, 0.0]
    body.set_parameters(anchor=configured)
    body.grab(world(CORNERS[3]))
    assert anchor_parameter(body.node) != configured
    body.reset()
    assert anchor_parameter(body.node) == configured


def test_reset_says_when_the_configured_anchor_no_longer_fits(simulated_body_factory):
    """Inertia made tiny while a near point is grabbed: the start's corner is refused."""
    body = make_body(simulated_body_factory)
    node = body.node
    body.grab(world(INSIDE[0]))
    body.set_parameters(inertia=[1e-13, 0.0, 0.0, 1e-13, 0.0, 1e-13])
    state, target = node.simulation.state, node.simulation.target
    with pytest.raises(RuntimeError, match='cannot restore the configured anchor') as refused:
        body.reset()
    assert 'too ill-conditioned' in str(refused.value)
    assert node.simulation.state is state and node.simulation.target == target


def test_grab_topic_parameter_service_and_markers_show_the_grabbed_point(simulated_body_factory):
    """
    Through the topic: ros2 param get shows the point, the markers' anchor is it, targets drag it.

    The body rests at STATE (no gravity, free): the point is on the body when it arrives.
    """
    body = make_body(simulated_body_factory, gravity=[0.0, 0.0, 0.0], hold_initial_anchor=False,
                     marker_rate_hz=50.0, linear_damping=5.0, angular_damping=5.0)
    node = body.node
    viewer = body.add_node(Node('viewer', context=body.context))
    arrays = []
    viewer.create_subscription(MarkerArray, '/mouse_constraint/markers', arrays.append, 10)
    parameters = viewer.create_client(GetParameters, '/mouse_constraint/get_parameters')
    body.step()
    local = EDGES[0]
    point = world(local)
    body.grab(point)
    assert node.simulation.target == point
    future = parameters.call_async(GetParameters.Request(names=['anchor']))
    body.drain()
    np.testing.assert_allclose(future.result().values[0].double_array_value, local, atol=1e-9)
    # Markers come on their own timer (wall time): step until two more have come.
    count = len(arrays)
    body.step_until(lambda: len(arrays) > count + 2, max_ticks=100_000)
    markers = {m.ns: m for m in arrays[-1].markers}
    pose = markers['body'].pose
    state = BodyState((pose.position.x, pose.position.y, pose.position.z),
                      (pose.orientation.x, pose.orientation.y, pose.orientation.z,
                       pose.orientation.w))
    sphere = markers['anchor'].pose.position
    np.testing.assert_allclose((sphere.x, sphere.y, sphere.z), world(local, state), atol=1e-9)
    np.testing.assert_allclose((sphere.x, sphere.y, sphere.z), point, atol=1e-9)
    # A later target drags the grabbed point there (the damping stops the swing it starts).
    target = (point[0] + 0.1, point[1], point[2] + 0.05)
    body.target(target)
    assert node.simulation.target == target
    body.step_until(lambda: np.linalg.norm(node.simulation.anchor_error()) < 1e-4,
                    max_ticks=1000)
    np.testing.assert_allclose(anchor_parameter(node), local, atol=1e-9)


def test_a_flood_of_grabs_logs_short_throttled_lines(simulated_body_factory, capfd):
    """
    500 grabs in a burst: each one is taken, and the log has at most a short line per period.

    A grab sets the node's own anchor parameter; that change used to log the whole summary
    (some 450 characters) every time. The period is on the steady clock, so the lines a flood
    may log depend on how long it lasts (seconds on a busy machine): at most one, then one per
    ``WARN_PERIOD`` of it, each later line counting the grabs it stands for.
    """
    body = make_body(simulated_body_factory)
    # A throttled warning first: the notes must not share its call site (rclpy refuses one
    # call site at two severities).
    with pytest.raises(InputRefused):
        body.grab((50.0, 50.0, 50.0))
    capfd.readouterr()
    local = ON_BODY[0]
    started = time.monotonic()
    for _ in range(500):
        body.grab(world(local))
    lasted = time.monotonic() - started
    np.testing.assert_allclose(anchor_parameter(body.node), local, rtol=0.0, atol=1e-9)
    lines = [line for line in capfd.readouterr().err.splitlines() if line.strip()]
    assert 'parameters changed' not in ''.join(lines)
    assert 1 <= len(lines) <= 1 + lasted // WARN_PERIOD, (lasted, lines)
    assert all(len(line) < 160 and 'set by the node' in line for line in lines), lines
    held_back = [re.search(r'\((\d+) more since the last one\)$', line) for line in lines[1:]]
    assert all(held_back) and len(lines) + sum(int(m.group(1)) for m in held_back) <= 500
    # A change through the parameters still logs the summary.
    body.set_parameters(mass=3.0)
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
            assert grab(state, BOX_SHAPE, state.world_point(corner)).taken(0.0), (state, corner)
            out = tuple(c + 1e-3 * s for c, s in zip(corner, signs))
            assert not grab(state, BOX_SHAPE, state.world_point(out)).taken(0.0)


def test_a_refusal_shows_the_digits_that_tell_value_and_bound_apart(simulated_body_factory):
    """|torque| just over 100 is not '100 exceeds 100'; a grab just beyond the margin neither."""
    from mouse_constraint_ros.inputs.target_gate import apart
    from mouse_constraint_ros.inputs.wrench_gate import WrenchGate

    assert apart(100.00000000000001, 100.0) == ('100.00000000000001', '100.0')
    assert apart(150.0, 100.0) == ('150', '100')
    gate = WrenchGate('world', 1000.0, 100.0)
    refusal = gate.refusal('', (0.0, 0.0, 0.0), (100.00000000000001, 0.0, 0.0))
    assert '|torque| 100.00000000000001 N m exceeds max_wrench_torque 100.0 N m' in refusal.reason
    body = make_body(simulated_body_factory, grab_margin=0.01)
    with pytest.raises(InputRefused) as refused:
        body.grab(world((HALF[0] + 0.010000001, 0.0, 0.0)))
    text = str(refused.value)
    assert 'm off the body, farther than grab_margin 0.01 m' in text
    assert ' 0.01 m off' not in text
