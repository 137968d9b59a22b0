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
Mouse gestures on the body turned into the node's inputs: grab, targets, release (no ROS here).

============================  ==============================================================
gesture                       inputs to the node
============================  ==============================================================
press on the body and move    ``grab`` at the pressed point of the body, carried to the
                              node's latest pose (``material_point``)
drag                          a ``target`` per pointer event: the pointer's ray on the plane
                              through the grabbed point that faces the camera
release                       ``~/release``: the body flies free
release with HOLD_MODIFIER,   nothing more: the last target holds the body where it was let
or the page's hold toggle on  go
click (press, release, no     ``grab`` where the ray first meets the box at the latest pose
motion)                       (``ray_box_hit``), then a release as above
============================  ==============================================================

A drag's plane is fixed when it starts, like the web view's own: the camera does not move
during a drag (the view locks it), so each target is the pointer's ray from the camera met with
that plane. ``Gestures`` keeps one drag per browser (client id); a drag whose start it never saw
sends nothing.
"""

from typing import Dict, List, NamedTuple, Optional, Sequence

from .geometry import camera_plane_point, material_point, Pose, ray_box_hit
from ..physics.algebra import Vector3

# Held at release (the drag's modifier), it keeps the body held instead of letting it fly.
HOLD_MODIFIER = 'shift'

GRAB, TARGET, RELEASE = 'grab', 'target', 'release'


class Action(NamedTuple):
    """One input for the node: ``kind`` GRAB or TARGET at ``point`` (m), or RELEASE."""

    kind: str
    point: Optional[Vector3] = None


class Camera(NamedTuple):
    """The browser's camera when a drag starts: its position and viewing direction (world)."""

    position: Vector3
    forward: Vector3


class _Drag(NamedTuple):
    camera: Optional[Camera]
    through: Vector3


def _holds(modifier: Optional[str], hold: bool) -> bool:
    return hold or modifier == HOLD_MODIFIER


class Gestures:
    """The drags in progress, one per browser, and what each pointer event sends."""

    def __init__(self) -> None:
        """Start with no drag."""
        self._drags: Dict[int, _Drag] = {}

    def dragging(self, client: int) -> bool:
        """Return whether browser ``client`` is dragging the body."""
        return client in self._drags

    def start(self, client: int, *, pressed: Sequence[float], camera: Optional[Camera],
              shown: Pose, now: Pose) -> List[Action]:
        """
        Start a drag: grab the pressed point of the body.

        :param client: the browser's id.
        :param pressed: the pressed point on the body as the browser drew it (world, m).
        :param camera: the browser's camera; None when it has not reported it: the targets are
            then the web view's own drag-plane points.
        :param shown: the body's pose the browser drew.
        :param now: the body's latest pose from the node.
        :returns: the grab.
        """
        grabbed = material_point(pressed, shown=shown, now=now)
        self._drags[client] = _Drag(camera, grabbed)
        return [Action(GRAB, grabbed)]

    def move(self, client: int, pointer: Sequence[float]) -> List[Action]:
        """
        Return the target for a pointer event of a drag (none for an unknown drag).

        :param client: the browser's id.
        :param pointer: a point on the pointer's ray other than the camera (world, m): the
            web view's own drag-plane point.
        """
        drag = self._drags.get(client)
        if drag is None:
            return []
        if drag.camera is None:
            return [Action(TARGET, tuple(float(c) for c in pointer))]
        origin = drag.camera.position
        direction = tuple(p - o for p, o in zip(pointer, origin))
        point = camera_plane_point(origin, direction, through=drag.through,
                                   normal=drag.camera.forward)
        return [] if point is None else [Action(TARGET, point)]

    def end(self, client: int, pointer: Sequence[float], *, modifier: Optional[str],
            hold: bool) -> List[Action]:
        """
        End a drag: the last target, then a release unless it holds.

        :param client: the browser's id.
        :param pointer: the pointer's last point on its ray (world, m).
        :param modifier: the modifier keys of the drag's last segment (None: none).
        :param hold: the page's hold toggle.
        """
        actions = self.move(client, pointer)
        if self._drags.pop(client, None) is not None and not _holds(modifier, hold):
            actions.append(Action(RELEASE))
        return actions

    @staticmethod
    def click(origin: Sequence[float], direction: Sequence[float], *, now: Pose,
              box_size: Sequence[float], modifier: Optional[str], hold: bool) -> List[Action]:
        """
        Return what a click on the body sends: a grab where its ray meets the box, a release.

        :param origin: the click's ray origin (world, m).
        :param direction: its direction.
        :param now: the body's latest pose.
        :param box_size: the box's edges (m).
        :param modifier: the modifier keys held (None: none).
        :param hold: the page's hold toggle.
        :returns: nothing when the ray misses the box at the latest pose.
        """
        hit = ray_box_hit(origin, direction, pose=now, box_size=box_size)
        if hit is None:
            return []
        return [Action(GRAB, hit)] + ([] if _holds(modifier, hold) else [Action(RELEASE)])
