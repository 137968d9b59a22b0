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
press whose pick failed                nothing yet: the drag moves the node's anchor
move (POSE_UPDATE while pressed)       a ``target``: the grabbed point moved with the marker
release (MOUSE_UP)                     ``~/release``, unless the drag holds: the last target
                                       keeps the body where it was let go
=====================================  ========================================================

One drag at a time: the client that pressed owns it until it releases; the feedback of others
meanwhile is passed over, as is a move or a release without a press, and a pose or a point
that is not finite.
"""

import math
from typing import List, Optional, Sequence

from ..physics.algebra import Vector3
from ..pointer.geometry import local_point, material_point, Pose, world_point
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
              anchor: Vector3) -> List[Action]:
        """
        Start a drag: grab the pressed point of the body, or drag by the anchor without one.

        :param client: the RViz client's id.
        :param shown: the marker's pose at the press: the body as RViz showed it.
        :param hit: the pressed point (world, m), None when RViz's pick found none.
        :param now: the body's latest pose from the node.
        :param anchor: the node's anchor (body frame, m), dragged when there is no hit.
        :returns: the grab, or nothing.
        """
        if self.client not in (None, client) or not _finite(*shown, *now):
            return []
        self.client = client
        if hit is None or not _finite(hit):
            self._local = tuple(anchor)
            return []
        self._local = local_point(hit, shown)
        return [Action(GRAB, material_point(hit, shown=shown, now=now))]

    def move(self, client: str, marker: Pose) -> List[Action]:
        """Return the target for the marker moved to ``marker`` (none outside the drag)."""
        if client != self.client or not _finite(*marker):
            return []
        return [Action(TARGET, world_point(marker, self._local))]

    def release(self, client: str, *, hold: bool) -> List[Action]:
        """End the drag: a release unless ``hold`` (none outside the drag)."""
        if client != self.client:
            return []
        self.client = None
        return [] if hold else [Action(RELEASE)]
