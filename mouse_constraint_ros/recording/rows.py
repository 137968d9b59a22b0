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
Messages to CSV rows: one row per tick, pose and twist of one stamp, and the CSV file.

The anchor columns are the body-frame anchor placed by the pose (``BodyState.world_point``); the
body-frame anchor of a row is the one in effect when its pose came: the anchor read at the start,
then each change the recorded node announced on ``/parameter_events`` (a ``grab`` sets the node's
anchor to the grabbed point), from the first pose received after it. The target of a row is the
latest target received before its pose, and its grab the grab received since the pose before.
"""

import csv
import math
from pathlib import Path
from typing import Dict, List, NamedTuple, Optional, Sequence, Tuple

from geometry_msgs.msg import PoseStamped, TwistStamped
from rcl_interfaces.msg import ParameterEvent
from rclpy.serialization import deserialize_message

from .received import anchor_change, MESSAGE_TYPES, PARAMETER_EVENTS_TOPIC, Received
from ..physics.algebra import Vector3
from ..wire.interface import GRAB_TOPIC, POSE_TOPIC, TARGET_TOPIC, TWIST_TOPIC
from ..wire.messages import point_from_message, stamp_nanoseconds, state_from_messages

COLUMNS = ('time', 'stamp_ns', 'x', 'y', 'z', 'qx', 'qy', 'qz', 'qw', 'vx', 'vy', 'vz', 'wx', 'wy',
           'wz', 'anchor_x', 'anchor_y', 'anchor_z', 'target_x', 'target_y', 'target_z',
           'anchor_error', 'speed', 'angular_speed', 'body_anchor_x', 'body_anchor_y',
           'body_anchor_z', 'grab_x', 'grab_y', 'grab_z')


class Row(NamedTuple):
    """
    One tick of the CSV, see ``COLUMNS``; the target fields are None before any target.

    ``body_anchor`` is the anchor in the body frame in effect at this tick, ``grab`` the grab
    point received since the previous tick (None on the ticks without one).
    """

    time: float
    stamp_ns: int
    position: Vector3
    orientation: Tuple[float, float, float, float]
    linear_velocity: Vector3
    angular_velocity: Vector3
    anchor: Vector3
    target: Optional[Vector3]
    anchor_error: Optional[float]
    speed: float
    angular_speed: float
    body_anchor: Vector3
    grab: Optional[Vector3] = None

    def fields(self) -> list:
        """Return the row's values in ``COLUMNS`` order; '' where there is no target or grab."""
        target = self.target if self.target is not None else ('', '', '')
        error = '' if self.anchor_error is None else self.anchor_error
        grab = self.grab if self.grab is not None else ('', '', '')
        return [self.time, self.stamp_ns, *self.position, *self.orientation,
                *self.linear_velocity, *self.angular_velocity, *self.anchor, *target, error,
                self.speed, self.angular_speed, *self.body_anchor, *grab]


def tick_rows(received: Sequence[Received], anchor: Vector3) -> List[Row]:
    """
    Return one row per stamp that has both a pose and a twist, in the order the poses came.

    The target of a row is the latest target received before its pose; there is none (None)
    until the first target, e.g. while the node holds its initial anchor. Its body-frame anchor
    is ``anchor`` until the first anchor change received, then the latest one before its pose.

    :param received: the messages as received, in order.
    :param anchor: the anchor in the body frame (m) at the start of the recording.
    """
    target: Optional[Vector3] = None
    grab: Optional[Vector3] = None
    poses: Dict[int, Tuple[PoseStamped, Optional[Vector3], Vector3, Optional[Vector3]]] = {}
    twists: Dict[int, TwistStamped] = {}
    for message in received:
        decoded = deserialize_message(message.data, MESSAGE_TYPES[message.topic])
        if message.topic == TARGET_TOPIC:
            target = point_from_message(decoded)
        elif message.topic == GRAB_TOPIC:
            grab = point_from_message(decoded)
        elif message.topic == PARAMETER_EVENTS_TOPIC:
            anchor = _changed_anchor(decoded, anchor)
        elif message.topic == POSE_TOPIC:
            stamp = stamp_nanoseconds(decoded.header.stamp)
            if stamp not in poses:
                poses[stamp] = (decoded, target, anchor, grab)
                grab = None
        elif message.topic == TWIST_TOPIC:
            twists.setdefault(stamp_nanoseconds(decoded.header.stamp), decoded)
    rows: List[Row] = []
    for stamp, (pose, pose_target, body_anchor, pose_grab) in poses.items():
        twist = twists.get(stamp)
        if twist is None:
            continue
        state = state_from_messages(pose, twist)
        world_anchor = state.world_point(body_anchor)
        start = rows[0].stamp_ns if rows else stamp
        rows.append(Row(
            time=(stamp - start) * 1e-9, stamp_ns=stamp, position=state.position,
            orientation=state.orientation, linear_velocity=state.linear_velocity,
            angular_velocity=state.angular_velocity, anchor=world_anchor, target=pose_target,
            anchor_error=None if pose_target is None else math.dist(world_anchor, pose_target),
            speed=math.hypot(*state.linear_velocity),
            angular_speed=math.hypot(*state.angular_velocity), body_anchor=body_anchor,
            grab=pose_grab))
    return rows


def _changed_anchor(event: ParameterEvent, anchor: Vector3) -> Vector3:
    """Return the anchor ``event`` sets, or ``anchor`` when it sets none."""
    changed = anchor_change(event)
    return anchor if changed is None else changed


def write_csv(path: Path, rows: Sequence[Row]) -> None:
    """Write ``rows`` under a ``COLUMNS`` header; floats keep every digit (repr)."""
    with open(path, 'w', newline='') as stream:
        writer = csv.writer(stream)
        writer.writerow(COLUMNS)
        writer.writerows(row.fields() for row in rows)


def frame_of(received: Sequence[Received]) -> str:
    """Return the frame_id of the first pose, or '' without one."""
    for message in received:
        if message.topic == POSE_TOPIC:
            return deserialize_message(message.data, PoseStamped).header.frame_id
    return ''
