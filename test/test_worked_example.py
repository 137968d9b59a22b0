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

"""A downstream package's test: a proportional controller brings the box's anchor to a goal."""

from geometry_msgs.msg import PointStamped, PoseStamped
import numpy as np
import pytest
from rclpy.node import Node
from rclpy.parameter import Parameter

ANCHOR = np.array([0.2, 0.1, 0.05])  # the body's dragged point, body frame (the default)
GOAL = np.array([0.6, -0.2, 1.3])


def rotate(q, v):
    """Rotate ``v`` by the unit quaternion ``q`` = (x, y, z, w)."""
    u, w = np.array(q[:3]), q[3]
    return v + 2.0 * w * np.cross(u, v) + 2.0 * np.cross(u, np.cross(u, v))


class AnchorController(Node):
    """Every 20 ms of ROS time, sends the anchor a fifth of its way to the goal."""

    def __init__(self, *, context, goal, gain=10.0, period=0.02):
        super().__init__('anchor_controller', context=context,
                         parameter_overrides=[Parameter('use_sim_time', value=True)])
        self.goal, self.fraction, self.anchor = goal, gain * period, None
        self.create_subscription(PoseStamped, 'pose', self.on_pose, 10)
        self.publisher = self.create_publisher(PointStamped, 'target', 10)
        self.create_timer(period, self.on_timer)  # on ROS time: the body's simulated clock

    def on_pose(self, message):
        p, q = message.pose.position, message.pose.orientation
        self.anchor = np.array([p.x, p.y, p.z]) + rotate([q.x, q.y, q.z, q.w], ANCHOR)

    def on_timer(self):
        if self.anchor is None:
            return
        message = PointStamped()
        message.header.stamp = self.get_clock().now().to_msg()
        target = self.anchor + self.fraction * (self.goal - self.anchor)
        message.point.x, message.point.y, message.point.z = target
        self.publisher.publish(message)


# A controller closing its own loop on the pose is no pointer: the node's feed-forward, which
# runs a dragged stream ahead, would run ahead of the controller too.
@pytest.mark.parametrize('simulated_body', [{'target_feed_forward': False}], indirect=True)
def test_the_controller_brings_the_anchor_to_the_goal(simulated_body):
    body = simulated_body
    controller = body.add_node(AnchorController(context=body.context, goal=GOAL))

    def error():
        return np.inf if controller.anchor is None else np.linalg.norm(controller.anchor - GOAL)

    # Within 1 mm after 906 ticks (0.906 s at 1 kHz), found by running it: the same every run.
    assert body.step_until(lambda: error() < 1e-3, max_ticks=2000) == 906
    errors = []
    body.add_tick_callback(lambda _: errors.append(error()))
    body.step(1000)
    # The box swings on below its anchor: the rigid joint holds the anchor to some 20 um.
    assert max(errors) < 1e-3 and errors[-1] < 5e-5
