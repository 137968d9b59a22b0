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

"""RViz markers: what ``marker_array`` builds, and the node's ``~/markers`` at its own rate."""

import math
import time

import numpy as np
import pytest
from rclpy.parameter import Parameter
from visualization_msgs.msg import Marker
from visualization_msgs.msg import MarkerArray

from mouse_constraint_ros.monitoring.markers import force_color
from mouse_constraint_ros.monitoring.markers import marker_array
from mouse_constraint_ros.monitoring.markers import reference_force
from mouse_constraint_ros.monitoring.markers import SPHERE_FRACTION
from mouse_constraint_ros.node.mouse_constraint_node import MouseConstraintNode
from mouse_constraint_ros.physics import BodyState
from mouse_constraint_ros.physics import MouseConstraint
from mouse_constraint_ros.physics import RigidBody
from mouse_constraint_ros.physics import Settings
from mouse_constraint_ros.physics import STANDARD_GRAVITY
from mouse_constraint_ros.wire.messages import stamp_nanoseconds
from test_support.marker_viewer import marker_viewer

BOX = (0.3, 0.2, 0.1)
STATE = BodyState((0.1, 0.2, 0.9), (0.0, 0.0, math.sin(0.3), math.cos(0.3)), (1.0, 0.0, 0.0),
                  (0.0, 0.0, 2.0))


def by_namespace(array: MarkerArray) -> dict:
    """Return the markers of ``array`` keyed by namespace (one marker each)."""
    markers = {m.ns: m for m in array.markers}
    assert len(markers) == len(array.markers)
    # The node adds its wrench arrow (test_wrench.py) and its floor and contacts
    # (test_floor_ros.py); a call without them has none.
    assert set(markers) - {'wrench', 'floor', 'contacts'} == {'body', 'anchor', 'target',
                                                              'constraint'}
    return markers


def xyz(vector) -> tuple:
    """Return the x, y, z of a Point or Vector3 message."""
    return (vector.x, vector.y, vector.z)


def test_markers_show_body_anchor_target_and_a_force_coloured_line():
    """The box at the pose with box_size, spheres at anchor and target, the line between."""
    anchor, target = (0.3, 0.25, 0.95), (0.5, 0.25, 1.0)
    array = marker_array(frame_id='map', stamp_ns=1_500_000_123, box_size=BOX, state=STATE,
                         anchor=anchor, target=target, force=(0.0, 0.0, 19.6), reference=39.2)
    markers = by_namespace(array)
    for marker in array.markers:
        assert marker.header.frame_id == 'map'
        assert stamp_nanoseconds(marker.header.stamp) == 1_500_000_123
        assert marker.action == Marker.ADD and marker.color.a > 0.0
    body = markers['body']
    assert body.type == Marker.CUBE
    assert xyz(body.scale) == BOX
    assert xyz(body.pose.position) == STATE.position
    o = body.pose.orientation
    assert (o.x, o.y, o.z, o.w) == STATE.orientation
    diameter = SPHERE_FRACTION * 0.3
    for name, center in (('anchor', anchor), ('target', target)):
        sphere = markers[name]
        assert sphere.type == Marker.SPHERE
        assert xyz(sphere.pose.position) == center
        assert xyz(sphere.scale) == pytest.approx((diameter,) * 3)
        assert sphere.pose.orientation.w == 1.0
    line = markers['constraint']
    assert line.type == Marker.LINE_LIST
    assert [xyz(p) for p in line.points] == [anchor, target]
    assert 0.0 < line.scale.x < diameter
    # Half the reference force: yellow.
    assert (line.color.r, line.color.g, line.color.b) == pytest.approx((1.0, 1.0, 0.0))


def test_a_free_body_deletes_target_and_line():
    """Without a target the body and anchor stay; target and line markers are deleted."""
    markers = by_namespace(marker_array(frame_id='world', stamp_ns=0, box_size=BOX, state=STATE,
                                        anchor=(0.0, 0.0, 1.0), target=None,
                                        force=(0.0, 0.0, 0.0), reference=10.0))
    assert markers['body'].action == markers['anchor'].action == Marker.ADD
    assert markers['target'].action == markers['constraint'].action == Marker.DELETE


def test_marker_array_takes_keyword_arguments_only():
    """Anchor, target and force are all 3-vectors: passed by position they could be swapped."""
    with pytest.raises(TypeError, match='positional'):
        marker_array('world', 0, BOX, STATE, (0.0, 0.0, 1.0), None, (0.0, 0.0, 0.0), 10.0)


@pytest.mark.parametrize('force, rgb', [
    (0.0, (0.0, 1.0, 0.0)),
    (2.5, (0.5, 1.0, 0.0)),
    (5.0, (1.0, 1.0, 0.0)),
    (7.5, (1.0, 0.5, 0.0)),
    (10.0, (1.0, 0.0, 0.0)),
    (1e9, (1.0, 0.0, 0.0)),
    (math.inf, (1.0, 0.0, 0.0)),
    (math.nan, (1.0, 0.0, 0.0)),
])
def test_force_colour_runs_green_yellow_red(force, rgb):
    """Green at no force, yellow at half the reference, red from the reference on."""
    assert force_color(force, 10.0) == pytest.approx((*rgb, 1.0))


def test_reference_force_is_the_joint_force_bound_or_twice_the_weight():
    """
    The red end is the bound the joint enforces: the smaller of max_force and k m |g|.

    Without either bound it is twice the weight under standard gravity.
    """
    body = RigidBody.solid_box(2.0, BOX)
    gravity = (0.0, 3.0, -4.0)
    per_weight = 3.0 * body.mass * math.hypot(*gravity)
    assert reference_force(Settings(body, MouseConstraint(max_force=15.0))) == 15.0
    assert reference_force(Settings(body, MouseConstraint(max_force_per_weight=3.0),
                                    gravity=gravity)) == pytest.approx(per_weight)
    assert reference_force(Settings(body, MouseConstraint(
        max_force=per_weight + 1.0, max_force_per_weight=3.0),
        gravity=gravity)) == pytest.approx(per_weight)
    assert reference_force(Settings(body, MouseConstraint(
        max_force=per_weight - 1.0, max_force_per_weight=3.0),
        gravity=gravity)) == per_weight - 1.0
    assert reference_force(Settings(body, gravity=(0.0, 0.0, 0.0))) == pytest.approx(
        2.0 * 2.0 * -STANDARD_GRAVITY[2])


def test_node_publishes_the_markers_of_the_latest_tick_in_its_frame(simulated_body_factory):
    """~/markers in frame_id, stamped like the latest pose; the drawn box is the body."""
    body = simulated_body_factory(rate_hz=200.0, marker_rate_hz=20.0, frame_id='map',
                                  box_size=list(BOX), mass=3.0)
    node = body.node
    # The box drawn is the box whose inertia the body has (inertia all zeros: a solid box).
    assert node.simulation.settings.body == RigidBody.solid_box(3.0, BOX)
    arrays, poses = marker_viewer(body)
    target = (0.3, 0.1, 1.1)
    body.target(target, frame_id='map')
    body.step(200)
    # Markers come on their own timer (wall time): step until two more came.
    count = len(arrays)
    body.step_until(lambda: len(arrays) > count + 1, max_ticks=100_000)
    markers = by_namespace(arrays[-1])
    assert {m.header.frame_id for m in arrays[-1].markers} == {'map'}
    drawn = markers['body']
    pose = poses[stamp_nanoseconds(drawn.header.stamp)]
    assert xyz(drawn.pose.position) == xyz(pose.pose.position)
    assert xyz(drawn.scale) == BOX
    assert xyz(markers['target'].pose.position) == target
    assert [xyz(p) for p in markers['constraint'].points][1] == target
    np.testing.assert_allclose(xyz(markers['anchor'].pose.position), target, atol=0.05)


def test_node_publishes_markers_at_their_rate(ros):
    """On the node's clock, ~/markers come at marker_rate_hz of wall time."""
    ros.add(MouseConstraintNode(context=ros.context, parameter_overrides=[
        Parameter('rate_hz', value=200.0), Parameter('marker_rate_hz', value=20.0)]))
    arrays = ros.collect(MarkerArray, '/mouse_constraint/markers')
    assert ros.spin_until(lambda: arrays)
    count, started = len(arrays), time.monotonic()
    ros.spin_for(1.0)
    wall = time.monotonic() - started
    # A timer may run late on a loaded machine, never early.
    assert 0.5 * 20.0 * wall <= len(arrays) - count <= 20.0 * wall + 1


def test_marker_rate_zero_publishes_none_until_set(ros):
    """marker_rate_hz 0 turns the markers off; setting it at run time turns them on."""
    node = ros.add(MouseConstraintNode(context=ros.context, parameter_overrides=[
        Parameter('rate_hz', value=100.0), Parameter('marker_rate_hz', value=0.0)]))
    arrays = ros.collect(MarkerArray, '/mouse_constraint/markers')
    ros.spin_for(0.5)
    assert arrays == []
    assert node.set_parameters([Parameter('marker_rate_hz', value=50.0)])[0].successful
    assert ros.spin_until(lambda: len(arrays) > 5, timeout=5.0)
    assert not node.set_parameters([Parameter('marker_rate_hz', value=-1.0)])[0].successful


def test_no_marker_array_is_built_while_nothing_subscribes(ros, monkeypatch):
    """Without a subscription the timer builds nothing; a subscriber gets arrays at once."""
    built = []

    def counted(**kwargs):
        built.append(kwargs['stamp_ns'])
        return marker_array(**kwargs)

    monkeypatch.setattr('mouse_constraint_ros.node.monitors.marker_array', counted)
    ros.add(MouseConstraintNode(context=ros.context, parameter_overrides=[
        Parameter('rate_hz', value=200.0), Parameter('marker_rate_hz', value=50.0)]))
    ros.spin_for(0.5)
    assert built == []
    arrays = ros.collect(MarkerArray, '/mouse_constraint/markers')
    assert ros.spin_until(lambda: len(arrays) > 2, timeout=5.0)
    assert len(built) >= len(arrays)
