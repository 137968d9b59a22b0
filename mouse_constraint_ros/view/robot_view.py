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
The view's part for a whole robot: its joints as the node publishes them, and what a press meets.

``RobotView`` holds the robot of the node's parameters (``pointer.robot_shape``), takes the
newest ``joint_states`` when the view wants it (``NewestMessage``, as the pose), and places every
link from it (``link_poses``: decoded once per message and pose). A press on a link carries the
pressed point from the link's pose as drawn to its pose now (the link's frame pose pair, for
``Gestures.start``); a click's ray is met with every link's collision pieces. The anchor is on
the link of the last grab the view heard on ``grab`` (its own or another client's), found as the
node lands it (``nearest_link``); before any, on the tracked link, where the node keeps it.
"""

from typing import Dict, Optional, Sequence, Tuple

from rclpy.node import Node
from rclpy.qos import QoSProfile
from rclpy.serialization import deserialize_message
from sensor_msgs.msg import JointState

from ..physics.algebra import Vector3
from ..pointer.geometry import Pose, world_point
from ..pointer.newest_message import NewestMessage
from ..pointer.node_readouts import ViewParameters
from ..pointer.robot_shape import nearest_link, ray_robot_hit, RobotShape
from ..wire.interface import JOINT_STATES_TOPIC

# A grab heard this much farther off its link than grab_margin still moves the anchor there
# (m): the rounding of a point taken into a link's frame.
GRAB_ROUNDING = 1e-9


class RobotView:
    """
    A robot's shape, joints and anchor, as the view knows them.

    :param reader: the view's node that no executor spins (``joint_states`` is taken there).
    :param qos: the ``joint_states`` subscription's QoS (depth 1: the newest).
    """

    def __init__(self, reader: Node, qos: QoSProfile) -> None:
        """Subscribe to ``joint_states``; no robot until the parameters say so."""
        self.shape = RobotShape()
        self.joints = NewestMessage(reader, JointState, JOINT_STATES_TOPIC, qos)
        self.anchor_link = ''
        self._raw: Optional[bytes] = None
        self._poses: Optional[Dict[str, Pose]] = None
        self._placed_by: Optional[Tuple[bytes, Pose]] = None

    @property
    def active(self) -> bool:
        """Return whether the node serves a robot that this view has loaded."""
        return self.shape.robot is not None

    def update(self, parameters: ViewParameters) -> bool:
        """Take the robot of the node's ``parameters``; return whether it changed."""
        if not self.shape.update(parameters):
            return False
        self.anchor_link = self.shape.tracked_link
        self._poses = self._placed_by = None
        return True

    def take(self) -> Optional[bytes]:
        """Return the newest ``joint_states`` that came since the last call (None: none came)."""
        raw = self.joints.take()
        if raw is not None:
            self._raw = raw
        return raw

    def link_poses(self, tracked: Pose) -> Optional[Dict[str, Pose]]:
        """
        Return every link's pose at the newest ``joint_states``, or None before one.

        :param tracked: the tracked link's newest pose (where a floating base is placed from).
        """
        raw = self._raw
        if not self.active or raw is None:
            return None
        if self._placed_by != (raw, tracked):
            try:
                message = deserialize_message(raw, JointState)
                self._poses = self.shape.link_poses(message.name, message.position,
                                                    tracked=tracked)
            except Exception:  # A malformed message is passed over.
                self._raw, self._poses = None, None
                return None
            self._placed_by = (raw, tracked)
        return self._poses

    def anchor_point(self, poses: Dict[str, Pose], anchor: Sequence[float]) -> Vector3:
        """Return the anchor's world point: ``anchor`` in its link's frame, at ``poses``."""
        pose = poses.get(self.anchor_link) or poses[self.shape.tracked_link]
        return world_point(pose, anchor)

    def heard_grab(self, point: Sequence[float], margin: float,
                   tracked: Optional[Pose]) -> None:
        """Put the anchor on the link a grab at ``point`` (world) lands on, if it lands."""
        poses = None if tracked is None else self.link_poses(tracked)
        if poses is None:
            return
        link, distance = nearest_link(point, poses=poses, geometries=self.shape.geometries)
        if distance <= margin + GRAB_ROUNDING:
            self.anchor_link = link

    def pressed(self, pressed: Sequence[float], link: Optional[str],
                shown: Optional[Dict[str, Pose]],
                tracked: Pose) -> Optional[Tuple[Pose, Pose]]:
        """
        Return the pressed link's pose as drawn and now, to carry the pressed point between.

        :param pressed: the pressed point (world, m) on the robot as drawn.
        :param link: the link whose scene node was pressed; None: the one nearest the point.
        :param shown: every link's pose as drawn.
        :param tracked: the tracked link's newest pose.
        :returns: None before the robot is drawn or placed.
        """
        now = self.link_poses(tracked)
        if now is None or shown is None:
            return None
        if link is None:
            link, _ = nearest_link(pressed, poses=shown, geometries=self.shape.geometries)
        if link not in shown or link not in now:
            return None
        return shown[link], now[link]

    def ray_hit(self, origin: Sequence[float], direction: Sequence[float],
                tracked: Pose) -> Optional[Vector3]:
        """Return where a click's ray first meets the robot at its newest poses, or None."""
        poses = self.link_poses(tracked)
        if poses is None:
            return None
        hit = ray_robot_hit(origin, direction, poses=poses, geometries=self.shape.geometries)
        return None if hit is None else hit[1]
