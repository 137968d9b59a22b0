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

"""A node that records every pose, twist and force the body publishes, as a haptic loop reads."""

from typing import List, Tuple

from geometry_msgs.msg import PoseStamped, TwistStamped, WrenchStamped
import numpy as np
from rclpy.node import Node

from mouse_constraint_ros.wire.interface import (FORCE_QOS, FORCE_TOPIC, POSE_TOPIC, STATE_QOS,
                                                 TWIST_TOPIC)
from mouse_constraint_ros.wire.messages import stamp_nanoseconds

Stamped = Tuple[int, np.ndarray]


def xyz(vector) -> np.ndarray:
    """Return a message's x, y, z as an array."""
    return np.array([vector.x, vector.y, vector.z])


class StateListener(Node):
    """Records (stamp ns, vector) of each pose position, twist linear velocity and force."""

    def __init__(self, *, context, name: str = 'state_listener') -> None:
        """Subscribe to pose, twist and force with the node's QoS."""
        super().__init__(name, context=context, start_parameter_services=False)
        self.poses: List[Stamped] = []
        self.twists: List[Stamped] = []
        self.forces: List[Stamped] = []
        self.torques: List[Stamped] = []
        self.create_subscription(PoseStamped, POSE_TOPIC, self._on_pose, STATE_QOS)
        self.create_subscription(TwistStamped, TWIST_TOPIC, self._on_twist, STATE_QOS)
        self.create_subscription(WrenchStamped, FORCE_TOPIC, self._on_force, FORCE_QOS)

    def _on_pose(self, message: PoseStamped) -> None:
        self.poses.append((stamp_nanoseconds(message.header.stamp),
                           xyz(message.pose.position)))

    def _on_twist(self, message: TwistStamped) -> None:
        self.twists.append((stamp_nanoseconds(message.header.stamp),
                            xyz(message.twist.linear)))

    def _on_force(self, message: WrenchStamped) -> None:
        stamp = stamp_nanoseconds(message.header.stamp)
        self.forces.append((stamp, xyz(message.wrench.force)))
        self.torques.append((stamp, xyz(message.wrench.torque)))

    @property
    def force(self) -> np.ndarray:
        """Return the newest felt force, in newtons."""
        return self.forces[-1][1]
