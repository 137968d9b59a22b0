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

The anchor columns are the body-frame anchor placed by the pose (``BodyState.world_point``). A
row's target and body-frame anchor are the node's when it ran that tick (``NodeView``): the
latest target received, the grab the node took (its ``anchor`` change on ``/parameter_events``
that puts the new anchor at the grab point: the grab is then the target and the anchor),
a ``~/reset`` (the configured anchor; the target the initial anchor's world position when
``hold_initial_anchor``, else none) and a ``~/release`` (no target). A change applies from the
first pose received after it, and from any pose stamped later than the node's stamp of the
change (a tick stamped after it ran after it, whatever the order of arrival on two topics).
A grab the node took is marked on the row from which it holds; one it ignored on the row after
it came.
"""

import csv
import math
from pathlib import Path
from typing import Dict, List, Mapping, NamedTuple, Optional, Sequence, Tuple

from geometry_msgs.msg import PoseStamped
from rclpy.serialization import deserialize_message
from service_msgs.msg import ServiceEventInfo

from .received import (MESSAGE_TYPES, parameter_changes, PARAMETER_EVENTS_TOPIC, Received,
                       RELEASE_EVENTS, RESET_EVENTS)
from ..physics import BodyState
from ..physics.algebra import Vector3
from ..wire.interface import GRAB_TOPIC, POSE_TOPIC, TARGET_TOPIC, TWIST_TOPIC
from ..wire.messages import point_from_message, stamp_nanoseconds, state_from_messages

COLUMNS = ('time', 'stamp_ns', 'x', 'y', 'z', 'qx', 'qy', 'qz', 'qw', 'vx', 'vy', 'vz', 'wx', 'wy',
           'wz', 'anchor_x', 'anchor_y', 'anchor_z', 'target_x', 'target_y', 'target_z',
           'anchor_error', 'speed', 'angular_speed', 'body_anchor_x', 'body_anchor_y',
           'body_anchor_z', 'grab_x', 'grab_y', 'grab_z', 'grab_taken')
# How far (m) a taken grab's new anchor may lie from the grab point, placed by the pose received
# before the change, beyond the motion of the anchor since that pose's stamp.
GRAB_MATCH = 1e-6
# A node's stamp of a change is used when it is this close (ns) to the stamp of the pose
# received before it: then pose stamps and change stamps are on one clock (with publish_clock
# the poses are stamped with simulated time and the node's events with its system clock).
SAME_CLOCK_NS = 1_000_000_000


class Row(NamedTuple):
    """
    One tick of the CSV, see ``COLUMNS``; the target fields are None without a target.

    ``body_anchor`` is the anchor in the body frame in effect at this tick, ``grab`` a grab
    point marked on this tick (None on the ticks without one), ``grab_taken`` whether the node
    took it.
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
    grab_taken: Optional[bool] = None

    def fields(self) -> list:
        """Return the row's values in ``COLUMNS`` order; '' where there is no target or grab."""
        target = self.target if self.target is not None else ('', '', '')
        error = '' if self.anchor_error is None else self.anchor_error
        grab = self.grab if self.grab is not None else ('', '', '')
        taken = '' if self.grab_taken is None else int(self.grab_taken)
        return [self.time, self.stamp_ns, *self.position, *self.orientation,
                *self.linear_velocity, *self.angular_velocity, *self.anchor, *target, error,
                self.speed, self.angular_speed, *self.body_anchor, *grab, taken]


class NodeView:
    """
    The recorded node's target and anchor as the messages received so far make them.

    :param parameters: the node's parameters of ``received.NODE_PARAMETERS`` at the start;
        ``anchor`` at least. Without the others a reset leaves no target (it is not known).
    """

    def __init__(self, parameters: Mapping[str, object]) -> None:
        """Start from ``parameters``, no target (none was received), no grab pending."""
        self.parameters: Dict[str, object] = dict(parameters)
        self.anchor: Vector3 = tuple(parameters['anchor'])
        self.configured: Vector3 = self.anchor
        self.target: Optional[Vector3] = None
        self.pose: Optional[BodyState] = None
        self.pose_stamp: Optional[int] = None
        # Grabs received and not yet taken: (point, the row after it came).
        self.pending: List[Tuple[Vector3, int]] = []
        # Grabs to mark: row -> (point, taken).
        self.marks: Dict[int, Tuple[Vector3, bool]] = {}

    def take(self, topic: str, message, row: int) -> None:
        """Apply one received message; ``row`` is the row that the next pose makes."""
        if topic == TARGET_TOPIC:
            self.target = point_from_message(message)
        elif topic == GRAB_TOPIC:
            self.pending.append((point_from_message(message), row))
        elif topic == PARAMETER_EVENTS_TOPIC:
            self._parameters_changed(parameter_changes(message), row)
        elif topic in (RESET_EVENTS, RELEASE_EVENTS) and _succeeded(message):
            if topic == RELEASE_EVENTS:
                self.target = None
            else:
                self.anchor = self.configured
                self.target = self._reset_target()

    def _parameters_changed(self, changes: Mapping[str, object], row: int) -> None:
        self.parameters.update(changes)
        anchor = changes.get('anchor')
        if anchor is None:
            return
        self.anchor = anchor
        grabbed = self._grab_for(anchor)
        if grabbed is None:
            self.configured = anchor  # ros2 param set, or ~/reset restoring it
            return
        point, index = grabbed
        for refused, after in self.pending[:index]:
            self.marks.setdefault(after, (refused, False))
        del self.pending[:index + 1]
        self.marks[row] = (point, True)
        self.target = point

    def _grab_for(self, anchor: Vector3) -> Optional[Tuple[Vector3, int]]:
        """Return the pending grab (point, its index) that puts ``anchor`` where it is."""
        if self.pose is None:
            return None
        placed = self.pose.world_point(anchor)
        reach = math.hypot(*anchor) * math.hypot(*self.pose.angular_velocity) + math.hypot(
            *self.pose.linear_velocity)
        for index, (point, _) in enumerate(self.pending):
            # The node placed it with its state of the latest tick, at most a tick or two after
            # the pose received (publish_rate_hz may skip some): allow 0.1 s of motion.
            if math.dist(placed, point) <= GRAB_MATCH + 0.1 * reach:
                return point, index
        return None

    def _reset_target(self) -> Optional[Vector3]:
        p = self.parameters
        if not p.get('hold_initial_anchor') or 'initial_position' not in p \
                or 'initial_orientation' not in p:
            return None
        start = BodyState(p['initial_position'], p['initial_orientation']).validated(
            prefix='initial_')
        return start.world_point(self.configured)

    def refused_marks(self) -> Dict[int, Tuple[Vector3, bool]]:
        """Return the marks, with every grab still pending marked as ignored."""
        marks = dict(self.marks)
        for point, after in self.pending:
            marks.setdefault(after, (point, False))
        return marks


def _succeeded(event) -> bool:
    """Return whether a service event is a sent response that says success."""
    return (event.info.event_type == ServiceEventInfo.RESPONSE_SENT and len(event.response) == 1
            and event.response[0].success)


def _change_stamp(topic: str, message) -> Optional[int]:
    """Return the node's stamp (ns) of a change, or None for a message without one."""
    if topic == PARAMETER_EVENTS_TOPIC:
        stamp = stamp_nanoseconds(message.stamp)
    elif topic in (RESET_EVENTS, RELEASE_EVENTS):
        stamp = stamp_nanoseconds(message.info.stamp)
    else:
        return None
    return stamp or None


def tick_rows(received: Sequence[Received], parameters: Mapping[str, object]) -> List[Row]:
    """
    Return one row per stamp that has both a pose and a twist, in the order the poses came.

    :param received: the messages as received, in order.
    :param parameters: the node's parameters at the start (``NodeView``): ``anchor``, the
        anchor in the body frame (m), at least.
    """
    decoded = [(m.topic, deserialize_message(m.data, MESSAGE_TYPES[m.topic])) for m in received]
    twists = {}
    for topic, message in decoded:
        if topic == TWIST_TOPIC:
            twists.setdefault(stamp_nanoseconds(message.header.stamp), message)
    stamps = _usable_stamps(decoded)
    view = NodeView(parameters)
    taken, seen, rows = 0, set(), []
    for index, (topic, message) in enumerate(decoded):
        if topic != POSE_TOPIC:
            continue
        stamp = stamp_nanoseconds(message.header.stamp)
        if stamp in seen or stamp not in twists:
            continue
        seen.add(stamp)
        # Everything received before this pose, and the changes the node made before its tick.
        until = max([index] + [j + 1 for j, s in stamps.items() if j >= index and s < stamp])
        while taken < until:
            kind, item = decoded[taken]
            if kind == POSE_TOPIC:
                view.pose = _pose_state(item, twists)
            else:
                view.take(kind, item, len(rows))
            taken += 1
        rows.append(_row(message, twists[stamp], view.target, view.anchor,
                         rows[0].stamp_ns if rows else stamp))
    for row, (point, was_taken) in view.refused_marks().items():
        if row < len(rows):
            rows[row] = rows[row]._replace(grab=point, grab_taken=was_taken)
    return rows


def _usable_stamps(decoded) -> Dict[int, int]:
    """Return the node's stamp of each change, by index, where it is on the poses' clock."""
    stamps, latest = {}, None
    for index, (topic, message) in enumerate(decoded):
        if topic == POSE_TOPIC:
            latest = stamp_nanoseconds(message.header.stamp)
            continue
        stamp = _change_stamp(topic, message)
        if stamp is not None and latest is not None and abs(stamp - latest) <= SAME_CLOCK_NS:
            stamps[index] = stamp
    return stamps


def _pose_state(pose: PoseStamped, twists) -> BodyState:
    twist = twists.get(stamp_nanoseconds(pose.header.stamp))
    if twist is None:
        return BodyState(*_pose_tuple(pose))
    return state_from_messages(pose, twist)


def _pose_tuple(pose: PoseStamped):
    p, q = pose.pose.position, pose.pose.orientation
    return (p.x, p.y, p.z), (q.x, q.y, q.z, q.w)


def _row(pose: PoseStamped, twist, target: Optional[Vector3], body_anchor: Vector3,
         start: int) -> Row:
    stamp = stamp_nanoseconds(pose.header.stamp)
    state = state_from_messages(pose, twist)
    world_anchor = state.world_point(body_anchor)
    return Row(
        time=(stamp - start) * 1e-9, stamp_ns=stamp, position=state.position,
        orientation=state.orientation, linear_velocity=state.linear_velocity,
        angular_velocity=state.angular_velocity, anchor=world_anchor, target=target,
        anchor_error=None if target is None else math.dist(world_anchor, target),
        speed=math.hypot(*state.linear_velocity),
        angular_speed=math.hypot(*state.angular_velocity), body_anchor=body_anchor)


def write_csv(path: Path, rows: Sequence[Row], metadata: Sequence[str] = ()) -> None:
    """
    Write ``rows`` under a ``COLUMNS`` header; floats keep every digit (repr).

    :param metadata: lines written first, each after ``# `` (what the recording lacks).
    """
    with open(path, 'w', newline='') as stream:
        for line in metadata:
            stream.write(f'# {line}\n')
        writer = csv.writer(stream)
        writer.writerow(COLUMNS)
        writer.writerows(row.fields() for row in rows)


def frame_of(received: Sequence[Received]) -> str:
    """Return the frame_id of the first pose, or '' without one."""
    for message in received:
        if message.topic == POSE_TOPIC:
            return deserialize_message(message.data, PoseStamped).header.frame_id
    return ''
