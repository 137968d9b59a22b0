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

"""A click through ROS with config/params.yaml as shipped: the body is carried, not flung."""

import math

from geometry_msgs.msg import PointStamped, PoseStamped, TwistStamped
import numpy as np
from rclpy.parameter import Parameter
from scipy.spatial.transform import Rotation

from mouse_constraint_ros.node.mouse_constraint_node import MouseConstraintNode
from mouse_constraint_ros.wire.messages import point_message
from test_support.mouse_feel import SETTLE, shipped_parameters


def stamp_of(message) -> float:
    """Return a message's header stamp in seconds."""
    return message.header.stamp.sec + message.header.stamp.nanosec * 1e-9


def test_a_half_metre_click_with_the_shipped_parameters(ros):
    """Peak COM speed <= 5 m/s, spin <= 30 rad/s, anchor within 5 mm from 1.5 s on."""
    parameters = shipped_parameters()
    anchor = np.array(parameters['anchor'])
    node = ros.add(MouseConstraintNode(context=ros.context, parameter_overrides=[
        Parameter(name, value=value) for name, value in parameters.items()]))
    poses = ros.collect(PoseStamped, 'pose', depth=10000)
    twists = ros.collect(TwistStamped, 'twist', depth=10000)
    publisher = ros.probe.create_publisher(PointStamped, 'target', 10)
    assert ros.spin_until(lambda: publisher.get_subscription_count() > 0)
    ros.spin_for(0.5)  # the body hangs from its corner and swings

    def anchor_of(pose: PoseStamped) -> np.ndarray:
        p, q = pose.pose.position, pose.pose.orientation
        return np.array([p.x, p.y, p.z]) + Rotation.from_quat(
            [q.x, q.y, q.z, q.w]).apply(anchor)

    target = tuple(anchor_of(poses[-1]) + (0.5, 0.0, 0.0))
    publisher.publish(point_message(target, parameters['frame_id'], 0))
    assert ros.spin_until(lambda: node.simulation.target == target)
    clicked = len(poses), len(twists)
    ros.spin_for(SETTLE + 1.5)
    after = poses[clicked[0]:]
    click_stamp = stamp_of(after[0])
    speeds = [math.hypot(t.twist.linear.x, t.twist.linear.y, t.twist.linear.z)
              for t in twists[clicked[1]:]]
    spins = [math.hypot(t.twist.angular.x, t.twist.angular.y, t.twist.angular.z)
             for t in twists[clicked[1]:]]
    settled = [np.linalg.norm(anchor_of(p) - target) for p in after
               if stamp_of(p) >= click_stamp + SETTLE]
    assert len(speeds) > 100 and len(settled) > 100
    assert max(speeds) <= 5.0
    assert max(spins) <= 30.0
    assert max(settled) <= 0.005
    # The body really moved over, and hangs from the corner still swinging a little or at rest.
    assert np.linalg.norm(anchor_of(after[-1]) - anchor_of(after[0])) > 0.45
