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
The body in the page: the box of ``box_size``, or a URDF link's pieces, and its anchor sphere.

The box body (and a link that is one uncoloured box about its origin) is one box scene node,
``/body``, as it always was. Any other URDF link is a frame, ``/body``, at the pose the node
publishes (the link frame), holding one scene node per visual piece (the collision pieces where
the link has no ``<visual>``), each at its origin in the link frame: a mesh as its triangles
(``add_mesh_simple``), a box, a sphere and a cylinder as viser's shapes (a cylinder along z, as
in URDF), each in its material's colour, else the markers' body colour. The anchor sphere is
a child of ``/body`` at the ``anchor`` parameter, which is in the same frame. A press on a piece
reaches ``/body``'s drag and click callbacks: the page hands a pointer event on a scene node to
its ancestors.

``draw`` replaces the scene nodes when the shape changes, registers the callbacks on the new
``/body`` and puts it at the last pose shown; a box that only changes its edges is resized in
place. ``extents`` and ``center`` are the drawn body's bounds in its frame, for the spheres'
size and the camera's framing.
"""

from typing import Callable, List, Optional, Sequence, Tuple

import numpy as np
import viser
from viser import transforms

from ..description.body_geometry import BodyGeometry, lone_box, Piece
from ..monitoring.markers import ANCHOR_COLOR, BODY_COLOR
from ..physics.algebra import Vector3

# Sections of a drawn cylinder, subdivisions of a drawn sphere (as ``Piece.triangles``).
CYLINDER_SECTIONS = 48
SPHERE_SUBDIVISIONS = 3


def _rgb(color: Sequence[float]) -> tuple:
    return tuple(float(c) for c in color[:3])


def _colour(piece: Piece) -> Tuple[tuple, Optional[float]]:
    """Return a piece's RGB and opacity (None: opaque): its material's, else the body's."""
    rgba = BODY_COLOR if piece.color is None else piece.color
    return _rgb(rgba), (float(rgba[3]) if rgba[3] < 1.0 else None)


def drawn_pieces(geometry: BodyGeometry) -> Tuple[Piece, ...]:
    """Return the pieces the page draws: the visuals, or the collision pieces without any."""
    return geometry.visuals or geometry.collisions


def add_piece(scene: viser.SceneApi, name: str, piece: Piece):
    """Add one piece's scene node, ``name``, at its origin in its parent's (link) frame."""
    color, opacity = _colour(piece)
    place = {'position': tuple(float(c) for c in piece.transform[:3, 3]),
             'wxyz': tuple(float(c) for c in transforms.SO3.from_matrix(
                 piece.transform[:3, :3]).wxyz)}
    if piece.kind == 'box':
        return scene.add_box(name, color, piece.size, opacity=opacity, **place)
    if piece.kind == 'sphere':
        return scene.add_icosphere(name, piece.size[0], color, subdivisions=SPHERE_SUBDIVISIONS,
                                   opacity=opacity, **place)
    if piece.kind == 'cylinder':
        radius, length = piece.size
        return scene.add_cylinder(name, radius, length, color, radial_segments=CYLINDER_SECTIONS,
                                  opacity=opacity, **place)
    return scene.add_mesh_simple(name, np.asarray(piece.mesh.vertices, dtype=float),
                                 np.asarray(piece.mesh.faces), color=color, opacity=opacity,
                                 side='double', **place)


class BodyDrawing:
    """
    The body's scene nodes on one viser scene.

    :param scene: the server's scene.
    :param geometry: the body's shape to draw first.
    """

    def __init__(self, scene: viser.SceneApi, geometry: BodyGeometry) -> None:
        """Draw ``geometry`` at the origin, with no callbacks yet."""
        self._scene = scene
        self._callbacks: List[Tuple[Callable, Callable]] = []
        self._pose = ((0.0, 0.0, 0.0), (1.0, 0.0, 0.0, 0.0))  # position, wxyz
        self.geometry: Optional[BodyGeometry] = None
        self.body = self.anchor = None
        self.pieces: list = []  # the pieces' scene nodes (none for the box body)
        self.extents: Vector3 = (0.0, 0.0, 0.0)
        self.center: Vector3 = (0.0, 0.0, 0.0)
        self.draw(geometry)

    def bind(self, on_drag: Callable, on_click: Callable) -> None:
        """Call ``on_drag`` and ``on_click`` on a left drag or a click, with shift or without."""
        self._callbacks.append((on_drag, on_click))
        self._register(on_drag, on_click)

    def _register(self, on_drag: Callable, on_click: Callable) -> None:
        body = self.body
        body.on_drag('left')(on_drag)
        body.on_drag('left', modifier='shift')(on_drag)
        body.on_click(on_click)
        body.on_click(modifier='shift')(on_click)

    def draw(self, geometry: BodyGeometry) -> bool:
        """
        Draw ``geometry`` unless it is the one drawn; return whether the scene nodes were replaced.

        A box body whose edges change is resized in place (False).
        """
        if geometry is self.geometry:
            return False
        self.geometry = geometry
        pieces = drawn_pieces(geometry)
        edges = lone_box(pieces) if pieces[0].color is None else None
        if edges is not None:
            self.extents, self.center = edges, (0.0, 0.0, 0.0)
        else:
            low, high = geometry.surface().bounds
            self.extents = tuple(float(h - lo) for lo, h in zip(low, high))
            self.center = tuple(float(0.5 * (lo + h)) for lo, h in zip(low, high))
        if edges is not None and self.body is not None and not self.pieces:
            self.body.dimensions = edges
            return False
        self._remove()
        position, wxyz = self._pose
        if edges is not None:
            self.body = self._scene.add_box('/body', _rgb(BODY_COLOR), edges,
                                            opacity=BODY_COLOR[3], position=position, wxyz=wxyz)
        else:
            self.body = self._scene.add_frame('/body', show_axes=False, position=position,
                                              wxyz=wxyz)
            self.pieces = [add_piece(self._scene, f'/body/piece_{i}', piece)
                           for i, piece in enumerate(pieces)]
        # A child of the body: it moves with the body's pose, at no cost per push.
        self.anchor = self._scene.add_icosphere('/body/anchor', 1.0, _rgb(ANCHOR_COLOR))
        for callbacks in self._callbacks:
            self._register(*callbacks)
        return True

    def _remove(self) -> None:
        for handle in (self.anchor, *self.pieces, self.body):
            if handle is not None:
                handle.remove()
        self.body = self.anchor = None
        self.pieces = []

    def move(self, position: Vector3, wxyz: Sequence[float]) -> None:
        """Put ``/body`` at ``position`` turned by ``wxyz`` (the body frame's pose)."""
        self._pose = (tuple(position), tuple(wxyz))
        self.body.position, self.body.wxyz = position, wxyz
