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
The body as one interactive marker, and the updates that keep RViz's copy of it.

The marker, ``body``, is the node's body at its pose, with one ``MOVE_3D`` control that shows
it always: RViz's Interact tool drags it on the plane that faces the camera. The control draws
the body as the node's RViz markers do (``monitoring.body_markers``): the box of ``box_size`` in
their colour, or a URDF link's pieces, each at its origin in the link frame, which is the
marker's pose (the ``pose`` the node publishes). ``MarkerUpdates`` numbers every update it
makes, one after the other (RViz's client resets the marker on a gap), and says when a pose
goes:

- at most ``MAX_POSE_RATE`` a second (RViz draws at 30 frames a second), and only when the body
  moved; the newest pose held back goes when its slot comes (``PushThrottle``);
- none while the marker is dragged: RViz holds pose updates until the drag ends, and the marker
  follows the cursor meanwhile; at the release the body's pose goes at once, and the marker
  snaps back onto the body;
- the whole marker when the body or the frame changed, never mid-drag (RViz would reset the
  drag it is in): then at the release.

``get_interactive_markers`` answers with the whole marker at the latest pose and the number of
the latest update, after which RViz takes the updates that follow.
"""

from typing import List, Optional

from geometry_msgs.msg import Pose as PoseMessage
from visualization_msgs.msg import (InteractiveMarker, InteractiveMarkerControl,
                                    InteractiveMarkerPose, InteractiveMarkerUpdate)

from ..description import BodyGeometry
from ..monitoring.body_markers import drawn_pieces, piece_marker
from ..monitoring.markers import BODY_COLOR
from ..pointer.geometry import Pose
from ..pointer.push_throttle import PushThrottle
from ..wire.messages import set_stamp

MARKER_NAME, CONTROL_NAME = 'body', 'drag'
# Pose updates a second at most: RViz's default frame rate.
MAX_POSE_RATE = 30.0
# The marker's scale (the size RViz draws its controls' aids at) over the longest edge of the
# body's box (a URDF link's: the box about its collision pieces).
SCALE_FRACTION = 1.2


def pose_message(pose: Pose) -> PoseMessage:
    """Return ``pose`` as a ``geometry_msgs/Pose``."""
    message = PoseMessage()
    p, q = message.position, message.orientation
    p.x, p.y, p.z = (float(c) for c in pose.position)
    q.x, q.y, q.z, q.w = (float(c) for c in pose.orientation)
    return message


def pose_of(message: PoseMessage) -> Pose:
    """Return a ``geometry_msgs/Pose`` as a ``Pose``."""
    p, q = message.position, message.orientation
    return Pose((p.x, p.y, p.z), (q.x, q.y, q.z, q.w))


def body_marker(*, frame_id: str, geometry: BodyGeometry, pose: Pose) -> InteractiveMarker:
    """
    Return the interactive marker of the body, dragged in 3D facing the camera.

    :param frame_id: the frame of ``pose``.
    :param geometry: the body's shape: its drawn pieces, in the link frame (the marker's).
    :param pose: the body's (link frame's) pose.
    """
    control = InteractiveMarkerControl(
        name=CONTROL_NAME, interaction_mode=InteractiveMarkerControl.MOVE_3D,
        always_visible=True, description='drag the body',
        markers=[piece_marker(piece) for piece in drawn_pieces(geometry, BODY_COLOR)])
    control.orientation.w = 1.0
    marker = InteractiveMarker(name=MARKER_NAME, description='', controls=[control],
                               scale=SCALE_FRACTION * float(max(geometry.extents)))
    marker.header.frame_id = frame_id
    marker.pose = pose_message(pose)
    return marker


class MarkerUpdates:
    """
    The updates of the body's marker, numbered one after the other (see the module).

    :param server_id: the server's name in each update (the node's full name).
    :param max_rate: pose updates a second at most.
    """

    def __init__(self, server_id: str, max_rate: float = MAX_POSE_RATE) -> None:
        """Start at update 0, nothing sent."""
        self.server_id = server_id
        self.sequence = 0
        self._throttle: PushThrottle[Pose] = PushThrottle(max_rate)
        self._sent: Optional[Pose] = None
        self._marker: Optional[InteractiveMarker] = None
        self._stale = False  # the whole marker is due (body or frame changed)
        self.dragging = False

    def _update(self, **fields) -> InteractiveMarkerUpdate:
        self.sequence += 1
        return InteractiveMarkerUpdate(server_id=self.server_id, seq_num=self.sequence,
                                       type=InteractiveMarkerUpdate.UPDATE, **fields)

    def marker(self, *, frame_id: str, geometry: BodyGeometry,
               pose: Pose) -> List[InteractiveMarkerUpdate]:
        """Return the whole marker's update, or none mid-drag (it then goes at the release)."""
        self._marker = body_marker(frame_id=frame_id, geometry=geometry, pose=pose)
        self._sent = pose
        if self.dragging:
            self._stale = True
            return []
        self._stale = False
        return [self._update(markers=[self._marker])]

    def pose(self, pose: Pose, now: float) -> List[InteractiveMarkerUpdate]:
        """Offer the body's newest pose at ``now`` (s); return the update to send, if any."""
        if self._marker is None or self.dragging or pose == self._sent:
            return []
        return self._pose_update(self._throttle.offer(pose, now))

    def flush(self, now: float) -> List[InteractiveMarkerUpdate]:
        """Return the pose held back whose slot came at ``now`` (s), if any."""
        if self.dragging:
            return []
        return self._pose_update(self._throttle.flush(now))

    def _pose_update(self, pose: Optional[Pose]) -> List[InteractiveMarkerUpdate]:
        if pose is None or pose == self._sent:
            return []
        return self._moved(pose)

    def _moved(self, pose: Optional[Pose]) -> List[InteractiveMarkerUpdate]:
        """Return the update that puts the marker at ``pose`` (None: where it was)."""
        if pose is not None:
            self._sent = pose
            self._marker.pose = pose_message(pose)
        update = InteractiveMarkerPose(name=MARKER_NAME, pose=self._marker.pose)
        update.header.frame_id = self._marker.header.frame_id
        return [self._update(poses=[update])]

    def drag_ended(self, pose: Optional[Pose]) -> List[InteractiveMarkerUpdate]:
        """
        Return the updates of a drag's end: the marker back on the body at ``pose``.

        The whole marker when the body or the frame changed during the drag, else its pose.
        """
        self.dragging = False
        if self._marker is None:
            return []
        if not self._stale:
            return self._moved(pose)
        self._stale = False
        if pose is not None:
            self._sent, self._marker.pose = pose, pose_message(pose)
        return [self._update(markers=[self._marker])]

    def current(self, stamp_ns: int = 0) -> List[InteractiveMarker]:
        """Return the whole marker as it is now (none before the first), for a new client."""
        if self._marker is None:
            return []
        set_stamp(self._marker.header.stamp, stamp_ns)
        return [self._marker]
