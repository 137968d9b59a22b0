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
What dragging the body's interactive marker in RViz sends to the node (plain floats, no ROS).

RViz's Interact tool, on a ``MOVE_3D`` control, picks the point under the cursor at a press
and moves the marker on the plane through it that faces the camera, the point staying under the
cursor. ``MarkerDrag`` turns that into the node's inputs, as the web view's gestures do:

=====================================  ========================================================
feedback                               inputs to the node
=====================================  ========================================================
press (MOUSE_DOWN) with the hit point  ``grab`` at the pressed point of the body, carried from
                                       the pose RViz showed to the node's latest pose
press whose pick failed, or whose      nothing yet: the drag moves the node's anchor
point the node would refuse
move (POSE_UPDATE while pressed)       a ``target``: the grabbed point moved with the marker
release (MOUSE_UP)                     ``~/release``, unless the drag holds: the last target
                                       keeps the body where it was let go
=====================================  ========================================================

One drag at a time: the client that pressed owns it until it releases; the feedback of others
meanwhile is passed over, as is a move or a release without a press, and a pose or a point
that is not finite.

A pose's quaternion is read as the turn it stands for, normalised (``unit_pose``); a pose whose
quaternion cannot be normalised (zero, not finite, overflowing) is passed over. A grab is sent
only when the node takes it: its point, at the node's latest pose, within ``grab_margin`` of the
body's collision pieces (a URDF link's boxes, spheres, cylinders and meshes, or the box of
``box_size``: the node's own test, ``inputs.grab``). A point the node would refuse is no hit,
and the drag moves the node's anchor, which the node still holds: the drag never goes on from a
point that is not the anchor.
"""

import math
from typing import List, Optional, Sequence

from ..description import BodyGeometry
from ..inputs.grab import grab
from ..physics import BodyState
from ..physics.algebra import Vector3
from ..pointer.geometry import local_point, material_point, Pose, unit_pose, world_point
from ..pointer.gestures import Action, GRAB, RELEASE, TARGET


def _finite(*values: Sequence[float]) -> bool:
    return all(math.isfinite(c) for value in values for c in value)


class MarkerDrag:
    """The drag of the marker in progress, if any, and what each feedback event sends."""

    def __init__(self) -> None:
        """Start with no drag."""
        self.client: Optional[str] = None
        self._local: Vector3 = (0.0, 0.0, 0.0)

    @property
    def dragging(self) -> bool:
        """Return whether a client is dragging the marker."""
        return self.client is not None

    def press(self, client: str, *, shown: Pose, hit: Optional[Vector3], now: Pose,
              anchor: Vector3, geometry: BodyGeometry, margin: float) -> List[Action]:
        """
        Start a drag: grab the pressed point of the body, or drag by the anchor without one.

        :param client: the RViz client's id.
        :param shown: the marker's pose at the press: the body (link frame) as RViz showed it.
        :param hit: the pressed point (world, m), None when RViz's pick found none.
        :param now: the body's latest pose from the node (its link frame's).
        :param anchor: the node's anchor (body frame, m), dragged when there is no hit.
        :param geometry: the body's shape in its link frame (``BodyShape``).
        :param margin: the node's ``grab_margin`` (m): how far off the body a grab is taken.
        :returns: the grab, or nothing.
        """
        shown, now = unit_pose(shown), unit_pose(now)
        if self.client not in (None, client) or shown is None or now is None:
            return []
        self.client = client
        if hit is None or not _finite(hit):
            self._local = tuple(anchor)
            return []
        local = local_point(hit, shown)
        point = material_point(hit, shown=shown, now=now)
        if not grab(BodyState(now.position, now.orientation), geometry, point).taken(margin):
            self._local = tuple(anchor)
            return []
        self._local = local
        return [Action(GRAB, point)]

    def move(self, client: str, marker: Pose) -> List[Action]:
        """Return the target for the marker moved to ``marker`` (none outside the drag)."""
        marker = unit_pose(marker)
        if client != self.client or marker is None:
            return []
        return [Action(TARGET, world_point(marker, self._local))]

    def release(self, client: str, *, hold: bool) -> List[Action]:
        """End the drag: a release unless ``hold`` (none outside the drag)."""
        if client != self.client:
            return []
        self.client = None
        return [] if hold else [Action(RELEASE)]
