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
Every link's collision pieces of a robot, in its link frame: what a grab lands on.

With ``visuals``, also each link's visual pieces: what the web view draws.

A collision mesh exported from CAD is often not a closed surface (KUKA iiwa's link_7, for one):
a robot's link takes such a mesh by its convex hull, with a warning line, since only the density
route needs the volume a closed mesh bounds and a robot's links carry their ``<inertial>``.
"""

import dataclasses
import functools
import io
import logging
from typing import Callable, Dict, List, NamedTuple, Tuple

import numpy as np

from .body_geometry import BodyGeometry, Piece
from .mesh_files import ament_share, MeshFiles, PackageFinder
from .urdf_link import _piece, _prefixed
from .xml_declaration import as_xml_1_0


class RobotLinks(NamedTuple):
    """
    Each link's collision pieces (link frame), and the warnings loading them gave.

    ``visuals`` holds each link's visual pieces when they were asked for (``robot_links``), else
    nothing.
    """

    pieces: Dict[str, Tuple[Piece, ...]]
    warnings: Tuple[str, ...]
    visuals: Dict[str, Tuple[Piece, ...]] = {}

    def drawn(self, link: str) -> Tuple[Piece, ...]:
        """Return the pieces a view draws of ``link``: its visuals, else its collision pieces."""
        return self.visuals.get(link) or self.pieces.get(link, ())

    def distance(self, link: str, point: np.ndarray) -> float:
        """Return how far a point (``link``'s frame) lies from the link (inf: no pieces)."""
        pieces = self.pieces.get(link, ())
        return min((piece.distance(point) for piece in pieces), default=float('inf'))

    def geometry(self, link: str) -> BodyGeometry:
        """
        Return the pieces of a link as a BodyGeometry (its visuals, when loaded, with them).

        A link without collision pieces is a 5 cm cube at its frame.
        """
        pieces = self.pieces.get(link, ())
        if not pieces:
            return BodyGeometry.box((0.05, 0.05, 0.05), link=link)
        return BodyGeometry(link, (0.0, 0.0, 0.0), pieces, self.visuals.get(link, ()))


def robot_links(text: str, *, find_package: PackageFinder = ament_share,
                warn: Callable[[str], None] = lambda _line: None,
                visuals: bool = False) -> RobotLinks:
    """
    Return the collision pieces of every link of the URDF ``text``.

    :param text: the URDF (already checked by ``robot_structure``).
    :param find_package: resolves ``package://`` names.
    :param warn: called with one line per mesh taken by its convex hull.
    :param visuals: also load every link's visual pieces (their meshes).
    """
    import yourdfpy  # a URDF body's: the box body runs without it
    logger = logging.getLogger('yourdfpy')
    level = logger.level
    logger.setLevel(logging.CRITICAL)
    try:
        urdf = yourdfpy.URDF.load(io.BytesIO(as_xml_1_0(text).encode()), build_scene_graph=False,
                                  load_meshes=False, load_collision_meshes=False)
    except (ValueError, KeyError, TypeError, AttributeError) as error:
        raise ValueError(f'robot_description is not a valid URDF: {type(error).__name__} '
                         f'{error}') from None
    finally:
        logger.setLevel(level)
    pieces: Dict[str, Tuple[Piece, ...]] = {}
    drawn: Dict[str, Tuple[Piece, ...]] = {}
    warnings: List[str] = []
    for link in urdf.robot.links:
        files = MeshFiles(find_package)
        where = f'link {link.name!r} <collision>'
        for element in link.collisions:
            if element.geometry.mesh is not None:
                _prefixed(where, files.add, element.geometry.mesh.filename)
        _prefixed(where, files.read)
        found = []
        for element in link.collisions:
            piece = _prefixed(where, functools.partial(_piece, closed=False), element,
                              'collision', files)
            if piece.kind == 'mesh' and not piece.mesh.is_watertight:
                line = (f'{where} mesh {piece.uri!r} is not a closed surface: its convex hull '
                        'is taken for grabs')
                warnings.append(line)
                warn(line)
                piece = dataclasses.replace(piece, mesh=piece.mesh.convex_hull)
            found.append(piece)
        pieces[link.name] = tuple(found)
        if visuals:
            drawn[link.name] = _visuals(link, find_package)
    return RobotLinks(pieces, tuple(warnings), drawn)


def _visuals(link, find_package: PackageFinder) -> Tuple[Piece, ...]:
    """Return a yourdfpy link's ``<visual>`` pieces, their meshes read (ValueError if not)."""
    files = MeshFiles(find_package)
    where = f'link {link.name!r} <visual>'
    for element in link.visuals:
        if element.geometry.mesh is not None:
            _prefixed(where, files.add, element.geometry.mesh.filename)
    _prefixed(where, files.read)
    return tuple(_prefixed(where, _piece, element, 'visual', files) for element in link.visuals)
