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

"""A stream of PoseStamped on target_pose drives the body as the same PointStamped stream does."""

import math

from geometry_msgs.msg import PointStamped, PoseStamped
import numpy as np
import pytest
from rclpy.node import Node

from mouse_constraint_ros.testing import SimulatedBody
from mouse_constraint_ros.wire.interface import TARGET_POSE_TOPIC, TARGET_QOS, TARGET_TOPIC
from mouse_constraint_ros.wire.messages import point_from_pose, point_message, set_stamp


def pose_message(point, frame_id: str, nanoseconds: int) -> PoseStamped:
    """Return a PoseStamped at ``point``, turned (its orientation is not the target's)."""
    message = PoseStamped()
    message.header.frame_id = frame_id
    set_stamp(message.header.stamp, nanoseconds)
    p, q = message.pose.position, message.pose.orientation
    p.x, p.y, p.z = (float(c) for c in point)
    q.x, q.y, q.z, q.w = 0.0, math.sin(0.4), 0.0, math.cos(0.4)
    return message


def test_a_pose_s_position_is_its_target():
    assert point_from_pose(pose_message((1.0, -2.0, 0.5), 'world', 0)) == (1.0, -2.0, 0.5)


def drag(as_pose: bool, frame_id: str = ''):
    """Drag the default body along a circle streamed every 4 ms; poses, refusals, target."""
    with SimulatedBody() as body:
        device = Node('device', context=body.context, start_parameter_services=False)
        if as_pose:
            publisher = device.create_publisher(PoseStamped, TARGET_POSE_TOPIC, TARGET_QOS)
            message = pose_message
        else:
            publisher = device.create_publisher(PointStamped, TARGET_TOPIC, TARGET_QOS)
            message = point_message
        body.add_node(device)
        start = np.array([0.2, 0.1, 1.05])
        positions = []
        for tick in range(600):
            if tick % 4 == 0:
                angle = 2.0 * math.pi * tick / 600
                point = start + 0.2 * np.array([math.cos(angle) - 1.0, math.sin(angle), 0.0])
                publisher.publish(message(point, frame_id, round(body.time * 1e9)))
            body.step()
            positions.append(body.pose.position)
        return np.array(positions), body.node.refusals, body.node.simulation.target


@pytest.mark.ros
def test_a_pose_stream_drives_the_body_as_the_point_stream_does():
    """Same points, same stamps: the same motion to the bit, timed by the stamps both ways."""
    by_pose, refusals, _ = drag(True)
    by_point, _, _ = drag(False)
    assert refusals == (0, None)
    assert np.array_equal(by_pose, by_point)
    assert np.ptp(by_pose[:, 1]) > 0.3


@pytest.mark.ros
def test_a_pose_in_another_frame_is_refused_as_a_point_is():
    _, (count, refusal), target = drag(True, frame_id='map')
    assert count == 150 and refusal.key == 'frame'
    np.testing.assert_allclose(target, (0.2, 0.1, 1.05), rtol=0.0, atol=1e-15)
