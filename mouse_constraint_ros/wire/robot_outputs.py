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
What a robot publishes beside the tracked link's pose and twist: joint_states and every link's TF.

``joint_states`` (sensor_msgs/JointState, as CDR bytes: ``cdr.joint_state``) carries each moving
joint's position, velocity and effort, the torque (N m, or N for a prismatic joint) that the
constraint rows applied in the tick (the mouse, the position limits, joint friction, the speed
limits, the mimic joints), stamped as the tick's pose. TF carries ``frame_id`` -> each link (the
tracked link's own transform is the state publishers'), when a broadcaster is there.
"""

from typing import Callable, Dict, Optional, Sequence, Tuple

from geometry_msgs.msg import TransformStamped
from rclpy.node import Node
from sensor_msgs.msg import JointState

from .cdr.joint_state import JointStateLayout
from .interface import JOINT_STATES_QOS, JOINT_STATES_TOPIC
from .messages import set_stamp

# A link's placement: (position (x, y, z), orientation (x, y, z, w)), world frame.
Placements = Dict[str, Tuple[Sequence[float], Sequence[float]]]


class RobotOutputs:
    """
    joint_states and the links' TF of one tick.

    :param node: the node that publishes.
    :param joint_names: the moving joints, in the order the values come.
    :param frame_id: TF's parent frame.
    :param tracked_link: the link whose TF the state publishers send (skipped here).
    :param send_transform: a TF broadcaster's ``sendTransform``, or None without TF.
    """

    def __init__(self, node: Node, *, joint_names: Sequence[str], frame_id: str,
                 tracked_link: str,
                 send_transform: Optional[Callable[[TransformStamped], None]]) -> None:
        """Create the joint_states publisher."""
        self._publisher = node.create_publisher(JointState, JOINT_STATES_TOPIC,
                                                JOINT_STATES_QOS)
        self._layout = JointStateLayout(joint_names)
        self._frame_id = frame_id
        self._tracked = tracked_link
        self._send_transform = send_transform
        self._transform = TransformStamped()
        self._transform.header.frame_id = frame_id

    def publish(self, stamp_ns: int, positions: Sequence[float], velocities: Sequence[float],
                efforts: Sequence[float], placements: Optional[Placements] = None) -> None:
        """Publish one tick's joint_states, and each link's transform when TF is on."""
        self._publisher.publish(self._layout.pack(stamp_ns, positions, velocities, efforts))
        if self._send_transform is None or placements is None:
            return
        transform = self._transform
        set_stamp(transform.header.stamp, stamp_ns)
        for link, (position, orientation) in placements.items():
            if link == self._tracked or link == self._frame_id:
                continue
            transform.child_frame_id = link
            translation = transform.transform.translation
            translation.x, translation.y, translation.z = (float(x) for x in position)
            rotation_message = transform.transform.rotation
            (rotation_message.x, rotation_message.y, rotation_message.z,
             rotation_message.w) = (float(x) for x in orientation)
            self._send_transform(transform)

    @property
    def tf_on(self) -> bool:
        """Return whether the links' transforms are sent."""
        return self._send_transform is not None
