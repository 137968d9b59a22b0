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
The recorded node's target and anchor as the messages received so far make them (no rclpy).

``NodeView`` takes each message in the order the node acted on it: the latest target received,
the grab the node took (its ``anchor`` change on ``/parameter_events`` that puts the new anchor
at the grab point: the grab is then the target and the anchor), a ``~/reset`` (the configured
anchor; the target the initial anchor's world position when ``hold_initial_anchor``, else none)
and a ``~/release`` (no target). A grab the node took is marked on the row from which it holds;
one it ignored on the row after it came. The grab and the anchor change come on two topics, and
under load the change may arrive first: a change that no pending grab explains is kept until
rows past it are handed out (``expire``), and a grab that arrives meanwhile and explains it is
the grab the node took, from the change's row.
"""

import math
from typing import Dict, List, Mapping, NamedTuple, Optional, Tuple

from service_msgs.msg import ServiceEventInfo

from .received import parameter_changes, PARAMETER_EVENTS_TOPIC, RELEASE_EVENTS, RESET_EVENTS
from ..physics import BodyState
from ..physics.algebra import Vector3
from ..wire.interface import GRAB_TOPIC, TARGET_TOPIC
from ..wire.messages import stamp_nanoseconds

# How far (m) a taken grab's new anchor may lie from the grab point, placed by the pose received
# before the change, beyond the motion of the anchor since that pose's stamp.
GRAB_MATCH = 1e-6


class AnchorChange(NamedTuple):
    """An anchor change no grab explained yet."""

    placed: Vector3  # the world point it put the anchor at
    reach: float  # how far that may lie from the grab point that explains it (m)
    row: int
    configured: Vector3  # the configured anchor before it


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
        # The latest anchor change no grab explained yet.
        self._unexplained: Optional[AnchorChange] = None

    def take(self, topic: str, item, row: int) -> None:
        """
        Apply one received message; ``row`` is the row that the next pose makes.

        :param item: a target's or a grab's point; else the message.
        """
        if topic == TARGET_TOPIC:
            self.target = tuple(item)
        elif topic == GRAB_TOPIC:
            self._grab(tuple(item), row)
        elif topic == PARAMETER_EVENTS_TOPIC:
            self._parameters_changed(parameter_changes(item), row)
        elif topic in (RESET_EVENTS, RELEASE_EVENTS) and succeeded(item):
            if topic == RELEASE_EVENTS:
                self.target = None
            else:
                self.anchor = self.configured
                self.target = self._reset_target()

    def _grab(self, point: Vector3, row: int) -> None:
        unexplained = self._unexplained
        if unexplained is not None and math.dist(unexplained.placed, point) <= unexplained.reach:
            # The node's anchor change for this grab came first: the grab was taken there.
            self._unexplained = None
            self.configured = unexplained.configured
            self._taken(point, len(self.pending), unexplained.row)
            return
        self.pending.append((point, row))

    def _taken(self, point: Vector3, index: int, row: int) -> None:
        """Mark ``point`` taken on ``row``, the grabs pending before its ``index`` ignored."""
        for refused, after in self.pending[:index]:
            self.marks.setdefault(after, (refused, False))
        del self.pending[:index + 1]
        self.marks[row] = (point, True)
        self.target = point

    def _parameters_changed(self, changes: Mapping[str, object], row: int) -> None:
        self.parameters.update(changes)
        anchor = changes.get('anchor')
        if anchor is None:
            return
        self.anchor = anchor
        self._unexplained = None
        if self.pose is None:
            self.configured = anchor
            return
        placed = self.pose.world_point(anchor)
        # The node placed it with its state of the latest tick, at most a tick or two after the
        # pose received (publish_rate_hz may skip some): allow 0.1 s of motion.
        reach = GRAB_MATCH + 0.1 * (math.hypot(*anchor) * math.hypot(
            *self.pose.angular_velocity) + math.hypot(*self.pose.linear_velocity))
        for index, (point, _) in enumerate(self.pending):
            if math.dist(placed, point) <= reach:
                self._taken(point, index, row)
                return
        # ros2 param set, ~/reset restoring it, or a grab still on its way.
        self._unexplained = AnchorChange(placed, reach, row, self.configured)
        self.configured = anchor

    def _reset_target(self) -> Optional[Vector3]:
        p = self.parameters
        if not p.get('hold_initial_anchor') or 'initial_position' not in p \
                or 'initial_orientation' not in p:
            return None
        start = BodyState(p['initial_position'], p['initial_orientation']).validated(
            prefix='initial_')
        return start.world_point(self.configured)

    def expire(self, row: int) -> None:
        """
        Mark the grabs still pending that came before row ``row`` as ignored.

        An anchor change of a row up to ``row`` that no grab explained is a parameter change.
        """
        if self._unexplained is not None and self._unexplained.row <= row:
            self._unexplained = None
        while self.pending and self.pending[0][1] <= row:
            point, after = self.pending.pop(0)
            self.marks.setdefault(after, (point, False))


def succeeded(event) -> bool:
    """Return whether a service event is a sent response that says success."""
    return (event.info.event_type == ServiceEventInfo.RESPONSE_SENT and len(event.response) == 1
            and event.response[0].success)


def change_stamp(topic: str, message) -> Optional[int]:
    """Return the node's stamp (ns) of a change, or None for a message without one."""
    if topic == PARAMETER_EVENTS_TOPIC:
        stamp = stamp_nanoseconds(message.stamp)
    elif topic in (RESET_EVENTS, RELEASE_EVENTS):
        stamp = stamp_nanoseconds(message.info.stamp)
    else:
        return None
    return stamp or None
