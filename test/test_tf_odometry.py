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
TF and odometry: what the node broadcasts and publishes, and when TF is off and why.

The broadcaster is a test double that records copies of what it is given, as
``tf2_ros.TransformBroadcaster`` would send them (tf2_ros is not among the wheels here). The node
is stepped in lockstep: every tick's pose, transform and odometry are there to compare.
"""

from diagnostic_msgs.msg import DiagnosticArray
from geometry_msgs.msg import PoseStamped, TwistStamped
from nav_msgs.msg import Odometry
import numpy as np
import pytest
from rclpy.node import Node
from scipy.spatial.transform import Rotation

from mouse_constraint_ros.node.mouse_constraint_node import MouseConstraintNode
from mouse_constraint_ros.wire.messages import odometry_message, state_from_messages
from mouse_constraint_ros.wire.state_publishers import TF_UNAVAILABLE
from test_support.ros_harness import RecordingBroadcaster, stamp_of


def start(factory, broadcaster=None, **overrides):
    """Return a simulated body with ``overrides``, markers off, TF to ``broadcaster`` if given."""
    values = dict(marker_rate_hz=0.0, **overrides)
    if broadcaster is not None:
        values['transform_broadcaster'] = broadcaster.factory
    return factory(**values)


def collect(body, message_type, topic: str) -> list:
    """Return the list that a reader node of ``topic`` in ``body``'s context fills."""
    reader = Node('reader_' + topic.strip('/').replace('/', '_'), context=body.context)
    received = []
    reader.create_subscription(message_type, topic, received.append, 1000)
    body.add_node(reader)
    return received


def by_stamp(messages) -> dict:
    """Return ``messages`` keyed by their header stamp (ns)."""
    return {stamp_of(m): m for m in messages}


def values(status) -> dict:
    """Return a status's key-values as a dict."""
    return {kv.key: kv.value for kv in status.values}


def test_tf_carries_the_pose_from_frame_id_to_body_frame_id(simulated_body_factory):
    """Every published pose has its transform, same stamp, translation and rotation."""
    broadcaster = RecordingBroadcaster()
    body = start(simulated_body_factory, broadcaster, rate_hz=200.0,
                 initial_orientation=[0.0, 0.0, 0.3826834323650898, 0.9238795325112867])
    node = body.node
    assert broadcaster.nodes == [node]
    poses = collect(body, PoseStamped, 'pose')
    body.step(50)
    assert len(poses) == len(broadcaster.sent) == 50
    transforms = by_stamp(broadcaster.sent)
    for pose in poses:
        transform = transforms[stamp_of(pose)]
        assert (transform.header.frame_id, transform.child_frame_id) == ('world', 'body')
        t, r = transform.transform.translation, transform.transform.rotation
        p, q = pose.pose.position, pose.pose.orientation
        assert (t.x, t.y, t.z, r.x, r.y, r.z, r.w) == (p.x, p.y, p.z, q.x, q.y, q.z, q.w)
    # body_frame_id and frame_id changes reach the transform from the next tick on.
    body.set_parameters(body_frame_id='base_link', frame_id='map')
    body.step(5)
    assert {(t.header.frame_id, t.child_frame_id) for t in broadcaster.sent[50:]} == {
        ('map', 'base_link')}
    assert broadcaster.nodes == [node]


def test_tf_off_by_parameter_and_on_again_at_run_time(simulated_body_factory):
    """publish_tf false: nothing is sent, /diagnostics says so; true: it is sent."""
    broadcaster = RecordingBroadcaster()
    body = start(simulated_body_factory, broadcaster, rate_hz=200.0, publish_tf=False,
                 diagnostics_rate_hz=20.0)
    arrays = collect(body, DiagnosticArray, '/diagnostics')
    # Diagnostics come on their own steady timer: step until two came.
    body.step_until(lambda: len(arrays) >= 2, max_ticks=100_000)
    assert broadcaster.sent == [] and broadcaster.nodes == []
    assert values(arrays[-1].status[0])['tf'] == 'off: publish_tf is false'
    body.set_parameters(publish_tf=True)
    body.step(20)
    assert len(broadcaster.sent) == 20
    assert broadcaster.nodes == [body.node]
    count = len(arrays)
    body.step_until(lambda: len(arrays) > count + 1, max_ticks=100_000)
    assert values(arrays[-1].status[0])['tf'] == 'world -> body'


@pytest.mark.skipif(TF_UNAVAILABLE is None, reason='tf2_ros is importable here')
def test_without_tf2_ros_tf_is_off_said_once_at_start_and_in_diagnostics(
        simulated_body_factory, capfd):
    """The default broadcaster without tf2_ros: one info line, and the diagnostics tf line."""
    body = start(simulated_body_factory, rate_hz=100.0, diagnostics_rate_hz=20.0)
    arrays = collect(body, DiagnosticArray, '/diagnostics')
    body.step_until(lambda: len(arrays) >= 2, max_ticks=100_000)
    status = arrays[-1].status[0]
    assert values(status)['tf'] == f'off: {TF_UNAVAILABLE}'
    assert 'tf2_ros is not importable' in TF_UNAVAILABLE
    lines = [line for line in capfd.readouterr().err.splitlines() if 'TF off' in line]
    assert len(lines) == 1 and 'INFO' in lines[0] and TF_UNAVAILABLE in lines[0]
    assert values(status)['publish rate (Hz)'] == 'every tick'
    assert values(status)['odometry'] == 'off'


def test_no_broadcaster_given_means_no_tf(ros):
    """transform_broadcaster=None: TF off, with that reason."""
    node = ros.add(MouseConstraintNode(context=ros.context, transform_broadcaster=None))
    assert not node._state_publishers.tf_on
    assert node._state_publishers.tf_status == 'off: no transform broadcaster was given'


def test_odometry_is_the_pose_with_the_twist_in_the_body_frame(simulated_body_factory):
    """
    publish_odometry: odom carries the pose in frame_id and the twist rotated into the body.

    Each odometry message equals ``odometry_message`` of the pose and twist of its stamp, and
    its twist is R^T of the world twist (checked with scipy, independently).
    """
    body = start(simulated_body_factory, rate_hz=200.0, publish_odometry=True,
                 body_frame_id='base_link',
                 initial_orientation=[0.0, 0.0, 0.3826834323650898, 0.9238795325112867])
    poses, twists = collect(body, PoseStamped, 'pose'), collect(body, TwistStamped, 'twist')
    odometry = collect(body, Odometry, 'odom')
    body.step(100)
    assert len(odometry) == len(poses) == len(twists) == 100
    swinging = 0
    for message, pose, twist in zip(odometry, poses, twists):
        assert stamp_of(message) == stamp_of(pose) == stamp_of(twist)
        state = state_from_messages(pose, twist)
        assert message == odometry_message(state, frame_id='world', body_frame_id='base_link',
                                           nanoseconds=stamp_of(message))
        inverse = Rotation.from_quat(state.orientation).inv()
        w = message.twist.twist.angular
        np.testing.assert_allclose([w.x, w.y, w.z], inverse.apply(state.angular_velocity),
                                   atol=1e-12)
        v = message.twist.twist.linear
        np.testing.assert_allclose([v.x, v.y, v.z], inverse.apply(state.linear_velocity),
                                   atol=1e-12)
        swinging += np.linalg.norm(state.angular_velocity) > 1e-3
    assert swinging > 10
    body.set_parameters(publish_odometry=False)
    assert body.node.count_publishers('odom') == 0


def test_odometry_is_off_by_default_and_on_at_run_time(simulated_body_factory):
    """No odom publisher by default; publish_odometry true at run time creates it."""
    body = start(simulated_body_factory, rate_hz=200.0)
    assert body.node.count_publishers('odom') == 0
    odometry = collect(body, Odometry, 'odom')
    body.set_parameters(publish_odometry=True)
    body.step(10)
    assert len(odometry) == 10
    assert {(m.header.frame_id, m.child_frame_id) for m in odometry} == {('world', 'body')}


def test_tf_and_odometry_follow_the_publish_rate(simulated_body_factory):
    """100 Hz at 1 kHz: TF, odometry and pose share stamps 10 ms apart, every 10th tick."""
    broadcaster = RecordingBroadcaster()
    body = start(simulated_body_factory, broadcaster, rate_hz=1000.0, publish_rate_hz=100.0,
                 publish_odometry=True, diagnostics_rate_hz=0.0)
    poses, odometry = collect(body, PoseStamped, 'pose'), collect(body, Odometry, 'odom')
    body.step(200)
    expected = [k * 10_000_000 for k in range(1, 21)]
    assert [stamp_of(m) for m in poses] == expected
    assert [stamp_of(m) for m in odometry] == expected
    assert [stamp_of(t) for t in broadcaster.sent] == expected
    assert body.node.ticker.record.ticks_run == 200
