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

"""What ``SimulatedBody`` reads of the node's output: the pose, the twist, the anchor's point."""

from typing import NamedTuple, Optional, Sequence

from geometry_msgs.msg import PoseStamped, TwistStamped
import numpy as np

from ..physics import BodyState
from ..wire.messages import stamp_nanoseconds


class BodyPose(NamedTuple):
    """The latest ``pose``: COM (m), orientation (x, y, z, w), stamp (s), and the message."""

    position: np.ndarray
    orientation: np.ndarray
    time: float
    message: PoseStamped


class BodyTwist(NamedTuple):
    """The latest ``twist``: COM velocity (m/s), angular velocity (rad/s), stamp, message."""

    linear: np.ndarray
    angular: np.ndarray
    time: float
    message: TwistStamped


def body_pose(message: Optional[PoseStamped]) -> Optional[BodyPose]:
    """Return a ``pose`` message as a ``BodyPose``; None for None."""
    if message is None:
        return None
    p, q = message.pose.position, message.pose.orientation
    return BodyPose(np.array([p.x, p.y, p.z]), np.array([q.x, q.y, q.z, q.w]),
                    stamp_nanoseconds(message.header.stamp) * 1e-9, message)


def body_twist(message: Optional[TwistStamped]) -> Optional[BodyTwist]:
    """Return a ``twist`` message as a ``BodyTwist``; None for None."""
    if message is None:
        return None
    v, w = message.twist.linear, message.twist.angular
    return BodyTwist(np.array([v.x, v.y, v.z]), np.array([w.x, w.y, w.z]),
                     stamp_nanoseconds(message.header.stamp) * 1e-9, message)


def world_point(message: Optional[PoseStamped], local: Sequence[float]) -> Optional[np.ndarray]:
    """Return the body-frame point ``local`` placed by a ``pose`` message (m); None for None."""
    if message is None:
        return None
    p, q = message.pose.position, message.pose.orientation
    state = BodyState((p.x, p.y, p.z), (q.x, q.y, q.z, q.w))
    return np.array(state.world_point(tuple(float(c) for c in local)))
