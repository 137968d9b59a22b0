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
Messages to CSV rows, one per tick (pose and twist of one stamp), made as the messages come.

The anchor columns are the body-frame anchor placed by the pose (``BodyState.world_point``). A
row's body-frame anchor is the node's when it ran that tick (``NodeView``): a change applies from
the first pose received after it, and from any pose stamped later than the node's stamp of the
change (a tick stamped after it ran after it, whatever the order of arrival on two topics). A
row's target is where the target path is at the tick's time (``TargetPath``): within a stream
of targets the point between the two around it, from its last target on that target, before
its first the target the node holds; the anchor error is the anchor's distance to it. A row's
wrench is the one the node applied at that tick (``WrenchView``): a wrench stamped on the poses'
clock applies from the tick stamped at its stamp, whatever the order of arrival. A robot's row
carries the ``joint_states`` of its stamp (``joints``), paired in the order they came as twists
are; ``joint_names``, the CSV's joint columns, are those of the first message that came with a
twist of its stamp (the node's: another publisher's are stamped off its ticks).

``RowStream`` makes the rows while recording: a row is made once poses stamped ``SETTLE_NS``
after it came (the changes it waits for and the next target of a stream are in by then), and
handed out ``SETTLE_NS`` later, when a grab that came before it and was not taken is known to
be ignored. ``tick_rows`` makes all rows of a finished recording at once.
"""

from collections import deque
import math
from typing import Deque, Dict, List, Mapping, NamedTuple, Optional, Sequence, Tuple

from rclpy.serialization import deserialize_message

from .applied_wrench import received_wrench, WRENCH_DOUBLES, WrenchView
from .joints import JointValues, read_joint_states
from .node_view import change_stamp, NodeView, succeeded
from .received import MESSAGE_TYPES, Received, RESET_EVENTS
from .target_path import SAME_CLOCK_NS, TargetPath
from ..physics import BodyState
from ..physics.algebra import Vector3
from ..wire.cdr.stamped import decode_stamped, POINT, POSE, Refusal, StampedFields, TWIST
from ..wire.interface import (GRAB_TOPIC, JOINT_STATES_TOPIC, POSE_TOPIC, TARGET_TOPIC,
                              TWIST_TOPIC, WRENCH_TOPIC)

COLUMNS = ('time', 'stamp_ns', 'x', 'y', 'z', 'qx', 'qy', 'qz', 'qw', 'vx', 'vy', 'vz', 'wx', 'wy',
           'wz', 'anchor_x', 'anchor_y', 'anchor_z', 'target_x', 'target_y', 'target_z',
           'anchor_error', 'speed', 'angular_speed', 'body_anchor_x', 'body_anchor_y',
           'body_anchor_z', 'grab_x', 'grab_y', 'grab_z', 'grab_taken', 'wrench_fx', 'wrench_fy',
           'wrench_fz', 'wrench_tx', 'wrench_ty', 'wrench_tz')
# A row is made once a pose stamped this much later (ns) came, and handed out as much later.
SETTLE_NS = 250_000_000
# The messages done with are dropped this many at a time.
FORGET_BATCH = 1024
# The topics read raw, and the doubles after their header.
_RAW = {POSE_TOPIC: POSE, TWIST_TOPIC: TWIST, TARGET_TOPIC: POINT, GRAB_TOPIC: POINT,
        WRENCH_TOPIC: WRENCH_DOUBLES}
# No wrench: the force and the torque of a row without one.
_ZERO = (0.0, 0.0, 0.0)


class Row(NamedTuple):
    """
    One tick of the CSV, see ``COLUMNS``; the target fields are None without a target.

    ``body_anchor`` is the anchor in the body frame in effect at this tick, ``grab`` a grab
    point marked on this tick (None on the ticks without one), ``grab_taken`` whether the node
    took it. ``wrench_force`` (N) and ``wrench_torque`` (N m) are the wrench the node applied at
    this tick (``wrench`` topic), zero without one. ``joints`` is a robot's ``joint_states`` of
    this tick, None for a single body (or a tick whose message did not come).
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
    wrench_force: Vector3 = _ZERO
    wrench_torque: Vector3 = _ZERO
    joints: Optional[JointValues] = None

    def fields(self) -> list:
        """Return the row's values in ``COLUMNS`` order; '' where there is no target or grab."""
        target = self.target if self.target is not None else ('', '', '')
        error = '' if self.anchor_error is None else self.anchor_error
        grab = self.grab if self.grab is not None else ('', '', '')
        taken = '' if self.grab_taken is None else int(self.grab_taken)
        return [self.time, self.stamp_ns, *self.position, *self.orientation,
                *self.linear_velocity, *self.angular_velocity, *self.anchor, *target, error,
                self.speed, self.angular_speed, *self.body_anchor, *grab, taken,
                *self.wrench_force, *self.wrench_torque]


class _Message(NamedTuple):
    topic: str
    # A pose's or a twist's StampedFields, a target's or a grab's point, else the message.
    item: object


class RowStream:
    """
    The rows of a recording, made as its messages come (see the module).

    Poses, twists, targets and grabs are read raw (``decode_stamped``: no message objects);
    a message those bytes do not hold is passed over, as a malformed message would be.

    :param parameters: the node's parameters at the start (``NodeView``): ``anchor``, the anchor
        in the body frame (m), at least.
    """

    def __init__(self, parameters: Mapping[str, object]) -> None:
        """Start with no message."""
        self._view = NodeView(parameters)
        self._frame = ''  # the node's frame: the poses'
        self._wrench = WrenchView(self._view.parameters, lambda: self._frame)
        self._path = TargetPath()
        # The messages not yet done with, and the index of the first.
        self._messages: List[_Message] = []
        self._base = 0
        self._applied = 0  # messages applied to the view (index)
        self._scanned = 0  # messages looked at for a row (index)
        # The changes not yet applied whose node stamp is on the poses' clock: (index, stamp).
        self._changes: List[Tuple[int, int]] = []
        self._twists: Dict[int, List[StampedFields]] = {}
        self._joints: Dict[int, List[JointValues]] = {}  # a robot's joint_states, by stamp
        self.joint_names: Tuple[str, ...] = ()  # those of the first tick's joint_states
        self._paired: Dict[int, int] = {}
        self._latest_pose: Optional[int] = None
        self._newest_pose: Optional[int] = None
        self._held: Optional[int] = None  # the index of the target message the node holds
        self._first: Optional[int] = None
        self._last: Optional[int] = None  # the stamp of the latest row made
        self._made = 0
        self._ready: Deque[Row] = deque()

    def add(self, received: Received) -> List[Row]:
        """Take one message as received; return the rows it completes, in order."""
        topic, index = received.topic, self._base + len(self._messages)
        if topic == JOINT_STATES_TOPIC:
            # Kept by stamp for the rows, as twists are; no row waits on one.
            joints = read_joint_states(received.data)
            if joints is not None:
                self._joints.setdefault(joints[0], []).append(joints[1])
                self._name_joints(joints[0])
            return []
        if topic in _RAW:
            item = decode_stamped(received.data, _RAW[topic])
            if isinstance(item, Refusal):
                return []
            if topic == POSE_TOPIC:
                self._latest_pose = item.stamp_ns
                self._newest_pose = max(item.stamp_ns, self._newest_pose or item.stamp_ns)
            elif topic == TWIST_TOPIC:
                self._twists.setdefault(item.stamp_ns, []).append(item)
                self._name_joints(item.stamp_ns)
            elif topic == WRENCH_TOPIC:
                stamp, item = item.stamp_ns, received_wrench(item, self._latest_pose)
                if self._latest_pose is not None and item.at_ns == stamp:
                    # From the tick stamped at its stamp on: a change just before that tick.
                    self._changes.append((index, stamp - 1))
            else:
                if topic == TARGET_TOPIC:
                    self._path.add(index, self._path.time_of(item.stamp_ns, self._latest_pose),
                                   item.values)
                item = item.values
        else:
            item = deserialize_message(received.data, MESSAGE_TYPES[topic])
            self._path.add_break(index)
            stamp = change_stamp(topic, item)
            if stamp is not None and self._latest_pose is not None and \
                    abs(stamp - self._latest_pose) <= SAME_CLOCK_NS:
                self._changes.append((index, stamp))
        self._messages.append(_Message(topic, item))
        if self._newest_pose is None:
            return []
        return self._rows(self._newest_pose - SETTLE_NS, self._newest_pose - 2 * SETTLE_NS)

    def _name_joints(self, stamp: int) -> None:
        """Name the joints after the joint_states of ``stamp`` once a twist of it came too."""
        if not self.joint_names and stamp in self._joints and stamp in self._twists:
            self.joint_names = self._joints[stamp][0].names

    def finish(self) -> List[Row]:
        """Return the rows not handed out yet: the recording is over."""
        return self._rows(None, None)

    def _rows(self, make_until: Optional[int], hand_until: Optional[int]) -> List[Row]:
        self._make(make_until)
        rows = []
        while self._ready and (hand_until is None or self._ready[0].stamp_ns <= hand_until):
            rows.append(self._ready.popleft())
        if rows:
            # The grabs that came before the last row handed out and were not taken by now.
            self._view.expire(self._made - len(self._ready) - 1 if hand_until is not None
                              else self._made)
            marks = self._view.marks
            first = self._made - len(self._ready) - len(rows)
            for offset, row in enumerate(rows):
                mark = marks.pop(first + offset, None)
                if mark is not None:
                    rows[offset] = row._replace(grab=mark[0], grab_taken=mark[1])
        return rows

    def _at(self, index: int) -> _Message:
        return self._messages[index - self._base]

    def _make(self, until: Optional[int]) -> None:
        """Make the rows of the poses stamped up to ``until`` (None: all)."""
        end = self._base + len(self._messages)
        while self._scanned < end:
            topic, pose = self._at(self._scanned)
            if topic != POSE_TOPIC:
                self._scanned += 1
                continue
            stamp = pose.stamp_ns
            if until is not None and stamp > until:
                break
            twists, paired = self._twists.get(stamp, ()), self._paired.get(stamp, 0)
            if paired < len(twists):
                self._paired[stamp] = paired + 1
                joints = self._joints.get(stamp, ())
                self._make_row(pose, twists[paired], joints[paired] if paired < len(joints)
                               else None)
            self._scanned += 1
        self._forget()

    def _make_row(self, pose: StampedFields, twist: StampedFields,
                  joints: Optional[JointValues]) -> None:
        # Everything received before this pose, and the changes the node made before its tick.
        stamp = pose.stamp_ns
        until = max([self._scanned] + [index + 1 for index, change in self._changes
                                       if index >= self._scanned and change < stamp])
        view = self._view
        while self._applied < until:
            topic, item = self._at(self._applied)
            if topic == POSE_TOPIC:
                view.pose = _state(item, self._twists.get(item.stamp_ns))
                self._frame = item.frame_id
            elif topic == WRENCH_TOPIC:
                self._wrench.take(item)
            elif topic != TWIST_TOPIC:
                if topic == RESET_EVENTS and succeeded(item):
                    self._wrench.clear()
                before = view.target
                view.take(topic, item, self._made)
                if topic == TARGET_TOPIC:
                    self._held = self._applied
                elif view.target is not before:
                    self._held = None
            self._applied += 1
        self._changes = [(i, c) for i, c in self._changes if i >= self._applied]
        if self._first is None:
            self._first = stamp
        self._last = stamp
        target = view.target
        if self._held is not None:
            target = self._path.at(stamp, self._held) or target
        self._ready.append(_row(_state(pose, [twist]), stamp, target, view.anchor,
                                self._first, self._wrench.at(stamp), joints))
        self._made += 1

    def _forget(self) -> None:
        """Drop the messages applied and looked at, the twists and targets no row needs."""
        done = min(self._applied, self._scanned) - self._base
        if done < FORGET_BATCH or self._last is None:
            return
        del self._messages[:done]
        self._base += done
        for stamp in [s for s in self._twists if s < self._last - SETTLE_NS]:
            del self._twists[stamp]
            self._paired.pop(stamp, None)
        for stamp in [s for s in self._joints if s < self._last - SETTLE_NS]:
            del self._joints[stamp]
        self._path.forget_before(self._last)


def tick_rows(received: Sequence[Received], parameters: Mapping[str, object]) -> List[Row]:
    """
    Return one row per pose that has a twist of its stamp, in the order the poses came.

    A recording as a whole, made with ``RowStream``: a stamp published twice (a reset while
    paused publishes the state it leaves at the paused tick's stamp) makes two rows.

    :param received: the messages as received, in order.
    :param parameters: the node's parameters at the start (``NodeView``): ``anchor``, the
        anchor in the body frame (m), at least.
    """
    stream = RowStream(parameters)
    rows = []
    for message in received:
        rows.extend(stream.add(message))
    return rows + stream.finish()


def _state(pose: StampedFields, twists: Optional[List[StampedFields]]) -> BodyState:
    """Return the body state of a pose and the first twist of its stamp (at rest without)."""
    values = pose.values
    if not twists:
        return BodyState(values[:3], values[3:])
    velocity = twists[0].values
    return BodyState(values[:3], values[3:], velocity[:3], velocity[3:])


def _row(state: BodyState, stamp: int, target: Optional[Vector3], body_anchor: Vector3,
         start: int, wrench: Tuple[Vector3, Vector3], joints: Optional[JointValues]) -> Row:
    world_anchor = state.world_point(body_anchor)
    return Row(
        time=(stamp - start) * 1e-9, stamp_ns=stamp, position=state.position,
        orientation=state.orientation, linear_velocity=state.linear_velocity,
        angular_velocity=state.angular_velocity, anchor=world_anchor, target=target,
        anchor_error=None if target is None else math.dist(world_anchor, target),
        speed=math.hypot(*state.linear_velocity),
        angular_speed=math.hypot(*state.angular_velocity), body_anchor=body_anchor,
        wrench_force=wrench[0], wrench_torque=wrench[1], joints=joints)
