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
A whole robot in the page: every link's pieces, each link a scene node of its own.

Each link that has pieces to draw (its ``<visual>`` ones, else its ``<collision>`` ones) is a
frame, ``/robot/link_<i>`` (i: the link's place in the URDF), holding one scene node per piece
at its origin in the link frame, drawn as a single URDF link's are (``body_drawing.add_piece``).
``move`` puts every link frame at its pose in one message. A press on a piece reaches its link
frame's drag and click callbacks, and ``link_of`` says which link a callback's scene node is.
The anchor sphere is a scene node of its own in the world, moved with each push: the link it
is on changes with each grab.

``extents`` and ``center`` are the robot's drawn bounds at the poses shown (world frame, for
the camera's framing); ``longest`` is its largest link's longest drawn edge, for the spheres'
size.
"""

from typing import Callable, Dict, List, Optional

import numpy as np
import viser

from .body_drawing import add_piece
from ..monitoring.markers import ANCHOR_COLOR
from ..physics.algebra import multiply, rotation_matrix, Vector3
from ..pointer.geometry import Pose, wxyz

# The robot's scene nodes are under this one.
ROBOT_NODE = '/robot'


def _corners(low, high) -> np.ndarray:
    """Return the 8 corners of the box from ``low`` to ``high``."""
    return np.array([(x, y, z) for x in (low[0], high[0]) for y in (low[1], high[1])
                     for z in (low[2], high[2])], dtype=float)


class RobotDrawing:
    """
    A robot's scene nodes on one viser scene.

    :param scene: the server's scene.
    :param links: the robot's links' pieces (``description.robot_links.RobotLinks``, with the
        visuals).
    """

    def __init__(self, scene: viser.SceneApi, links) -> None:
        """Draw every link with pieces at the origin, and the anchor sphere; no callbacks yet."""
        self.links = links
        self.frames: Dict[str, viser.FrameHandle] = {}
        self.pieces: Dict[str, list] = {}
        self._link_of: Dict[str, str] = {}
        self._corners: Dict[str, np.ndarray] = {}
        longest = 0.0
        for index, link in enumerate(links.pieces):
            drawn = links.drawn(link)
            if not drawn:
                continue
            name = f'{ROBOT_NODE}/link_{index}'
            self.frames[link] = scene.add_frame(name, show_axes=False)
            self.pieces[link] = [add_piece(scene, f'{name}/piece_{i}', piece)
                                 for i, piece in enumerate(drawn)]
            self._link_of[name] = link
            bounds = [piece.triangles().bounds for piece in drawn]
            low, high = np.min([b[0] for b in bounds], 0), np.max([b[1] for b in bounds], 0)
            self._corners[link] = _corners(low, high)
            longest = max(longest, float(np.max(high - low)))
        self.longest = longest or 0.1
        self.anchor = scene.add_icosphere(f'{ROBOT_NODE}/anchor', 1.0,
                                          tuple(float(c) for c in ANCHOR_COLOR[:3]))
        self.extents: Vector3 = (self.longest,) * 3
        self.center: Vector3 = (0.0, 0.0, 0.0)

    def bind(self, on_drag: Callable, on_click: Callable) -> None:
        """Call ``on_drag`` and ``on_click`` on a link's left drag or click, shift or not."""
        for frame in self.frames.values():
            frame.on_drag('left')(on_drag)
            frame.on_drag('left', modifier='shift')(on_drag)
            frame.on_click(on_click)
            frame.on_click(modifier='shift')(on_click)

    def link_of(self, handle) -> Optional[str]:
        """Return the link whose frame ``handle`` is (a callback's target), or None."""
        return self._link_of.get(getattr(handle, 'name', None))

    def move(self, poses: Dict[str, Pose]) -> None:
        """Put each link's frame at its pose (world frame); a link without one stays."""
        points: List[np.ndarray] = []
        for link, frame in self.frames.items():
            pose = poses.get(link)
            if pose is None:
                continue
            frame.position, frame.wxyz = pose.position, wxyz(pose.orientation)
            rotation = rotation_matrix(pose.orientation)
            points.extend(np.add(multiply(tuple(corner), rotation), pose.position)
                          for corner in self._corners[link])
        if points:
            low, high = np.min(points, 0), np.max(points, 0)
            self.extents = tuple(float(e) for e in np.maximum(high - low, 1e-6))
            self.center = tuple(float(c) for c in 0.5 * (low + high))

    def remove(self) -> None:
        """Remove every scene node of the robot."""
        for handle in (self.anchor, *[p for ps in self.pieces.values() for p in ps],
                       *self.frames.values()):
            handle.remove()
        self.frames, self.pieces, self._link_of = {}, {}, {}
