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
release                       ``~/release``: the body flies free (``SEGMENT_GAP`` later)
release with HOLD_MODIFIER    nothing more: the last target holds the body where it was let
down, or the page's hold      go
toggle on
click (press, release, no     ``grab`` where the ray first meets the body's collision pieces
motion)                       at the latest pose (``ray_body_hit``), then a release as above
============================  ==============================================================

A drag's plane is fixed when it starts, like the web view's own: the camera does not move
during a drag (the view locks it), so each target is the pointer's ray from the camera met with
that plane. ``Gestures`` keeps one drag per browser (client id); a drag whose start it never saw
sends nothing.

The web view splits a drag into one segment per modifier held: shift pressed mid-drag ends the
segment (an end without the modifier, as a release would send) and starts the next (with it).
So an end does not release at once: the drag waits ``SEGMENT_GAP`` for its next segment, which
goes on with the same grab and plane, and only then releases (``due``). Shift down when the
button is let go thus holds, however shortly before; the page confirms the next segment at
once (``scene``), where the web view would wait for the pointer to move or 0.1 s.
"""

from typing import Dict, List, NamedTuple, Optional, Sequence, Tuple

from .body_shape import ray_body_hit
from .geometry import camera_plane_point, material_point, Pose
from ..description.body_geometry import BodyGeometry
from ..physics.algebra import Vector3

# Held at release (the drag's modifier), it keeps the body held instead of letting it fly.
HOLD_MODIFIER = 'shift'

GRAB, TARGET, RELEASE = 'grab', 'target', 'release'

# How long an end waits for the next segment of its drag before it releases (s): the page
# starts it within milliseconds; a throw is held this much longer.
SEGMENT_GAP = 0.05


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


class _Ending(NamedTuple):
    drag: _Drag
    due: float  # when it releases, if nothing goes on with it (s)
    release: bool


class Gestures:
    """
    The drags in progress, one per browser, and what each pointer event sends.

    :param segment_gap: how long an end waits for the next segment of its drag (s).
    """

    def __init__(self, segment_gap: float = SEGMENT_GAP) -> None:
        """Start with no drag."""
        self.segment_gap = segment_gap
        self._drags: Dict[int, _Drag] = {}
        self._endings: Dict[int, _Ending] = {}

    def dragging(self, client: int) -> bool:
        """Return whether browser ``client`` is dragging the body."""
        return client in self._drags

    def ending(self, client: int) -> bool:
        """Return whether browser ``client``'s drag ended and waits for its next segment."""
        return client in self._endings

    def start(self, client: int, *, pressed: Sequence[float], camera: Optional[Camera],
              shown: Pose, now: Pose, at: float) -> List[Action]:
        """
        Start a drag: grab the pressed point of the body; or go on with the one just ended.

        :param client: the browser's id.
        :param pressed: the pressed point on the body as the browser drew it (world, m).
        :param camera: the browser's camera; None when it has not reported it: the targets are
            then the web view's own drag-plane points.
        :param shown: the body's pose the browser drew.
        :param now: the body's latest pose from the node.
        :param at: the time of the event (s, monotonic).
        :returns: the grab (after the release of an ended drag that was due); nothing when this
            is the next segment of a drag that ended within ``segment_gap``.
        """
        ending = self._endings.pop(client, None)
        if ending is not None and at <= ending.due:
            self._drags[client] = ending.drag
            return []
        released = [Action(RELEASE)] if ending is not None and ending.release else []
        grabbed = material_point(pressed, shown=shown, now=now)
        self._drags[client] = _Drag(camera, grabbed)
        return released + [Action(GRAB, grabbed)]

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
            hold: bool, at: float) -> List[Action]:
        """
        End a drag's segment: the last target; a release ``segment_gap`` later unless it holds.

        :param client: the browser's id.
        :param pointer: the pointer's last point on its ray (world, m).
        :param modifier: the modifier keys of the segment (None: none).
        :param hold: the page's hold toggle.
        :param at: the time of the event (s, monotonic).
        :returns: the last target; the release comes from ``due``.
        """
        actions = self.move(client, pointer)
        drag = self._drags.pop(client, None)
        if drag is not None:
            self._endings[client] = _Ending(drag, at + self.segment_gap,
                                            not _holds(modifier, hold))
        return actions

    def due(self, at: float) -> List[Action]:
        """Return the releases of the drags that ended more than ``segment_gap`` before ``at``."""
        over: List[Tuple[int, _Ending]] = [(client, ending) for client, ending
                                           in self._endings.items() if at > ending.due]
        for client, _ in over:
            del self._endings[client]
        return [Action(RELEASE) for _, ending in over if ending.release]

    @staticmethod
    def click(origin: Sequence[float], direction: Sequence[float], *, now: Pose,
              geometry: BodyGeometry, modifier: Optional[str],
              hold: bool) -> List[Action]:
        """
        Return what a click on the body sends: a grab where its ray meets the body, a release.

        :param origin: the click's ray origin (world, m).
        :param direction: its direction.
        :param now: the body's latest pose (its frame's: the link's for a URDF body).
        :param geometry: the body's shape in that frame (its collision pieces are met).
        :param modifier: the modifier keys held (None: none).
        :param hold: the page's hold toggle.
        :returns: nothing when the ray misses the body at the latest pose.
        """
        return Gestures.click_at(ray_body_hit(origin, direction, pose=now, geometry=geometry),
                                 modifier=modifier, hold=hold)

    @staticmethod
    def click_at(hit: Optional[Sequence[float]], *, modifier: Optional[str],
                 hold: bool) -> List[Action]:
        """
        Return what a click whose ray met the body at ``hit`` sends: a grab there, a release.

        :param hit: where the ray first met the body (world, m; a robot's nearest link), or
            None for a miss: nothing is sent.
        :param modifier: the modifier keys held (None: none).
        :param hold: the page's hold toggle.
        """
        if hit is None:
            return []
        point = tuple(float(c) for c in hit)
        return [Action(GRAB, point)] + ([] if _holds(modifier, hold) else [Action(RELEASE)])
