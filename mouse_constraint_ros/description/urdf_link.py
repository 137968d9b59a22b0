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
One URDF link as the simulated body: mass, inertia about its COM, COM and geometry.

``body_model`` reads ``robot_description`` with yourdfpy (after lxml has checked the XML, so a
malformed one gets lxml's line and column), picks ``body_link`` (or the only link), and takes:

- mass and inertia from ``<inertial>``: its origin places the COM in the link frame and turns
  the inertia's axes, I_link = R I R^T (the body frame of the physics is the link's, moved to
  the COM);
- without ``<inertial>``, both from the collision pieces at ``density`` (kg/m^3): boxes,
  spheres and cylinders in closed form, meshes by trimesh's volume integrals, summed with the
  parallel-axis theorem (overlapping pieces count twice: give ``<inertial>`` then);
- the ``<collision>`` pieces (at least one: the body is grabbed by them and lands on them) and
  the ``<visual>`` ones, whose meshes are drawn.

Every failure is a ValueError of one line naming the link, the element and how to fix it.
"""

import io
import logging
import math
from typing import NamedTuple, Optional, Tuple

from lxml import etree
import numpy as np
import yourdfpy

from .body_geometry import BodyGeometry, Piece
from .hull import hull_vertices, HullError
from .inertia_check import gyration_note
from .mesh_files import ament_share, MeshFiles, PackageFinder
from .urdf_checks import check_link, checked_root, link_elements
from ..physics.algebra import Symmetric3
from ..physics.body import RigidBody
from ..physics.collision import MAX_VERTICES
from ..physics.limits import MAX_DISTANCE

# The longest refusal (characters): an unforeseen error's text is cut there.
MAX_REASON = 400


class BodyModel(NamedTuple):
    """A link as a rigid body: mass (kg), inertia about the COM in link axes, its geometry."""

    mass: float
    inertia: Symmetric3
    geometry: BodyGeometry
    notes: Tuple[str, ...] = ()  # warnings of one line each (``inertia_check``)

    def rigid_body(self) -> RigidBody:
        """Return the physics' body, validated (mass and inertia ranges, triangle inequality)."""
        try:
            return RigidBody(self.mass, self.inertia)
        except ValueError as error:
            raise ValueError(f'link {self.geometry.link!r}: {error}') from None


def body_model(robot_description: str, body_link: str = '', *, density: float = 0.0,
               find_package: PackageFinder = ament_share) -> BodyModel:
    """
    Return the body of link ``body_link`` of the URDF text; raise ValueError saying what is wrong.

    Whatever goes wrong on the way is a ValueError of one line naming the link and the element
    being read: an error the checks did not foresee (a parser's or trimesh's) too.

    :param robot_description: the URDF (XML text).
    :param body_link: the link's name; empty: the URDF's only link.
    :param density: kg/m^3 for a link without ``<inertial>``; 0: such a link is refused.
    :param find_package: the share directory of a ``package://`` name (the ament index's).
    """
    where = ['robot_description']
    try:
        with np.errstate(all='ignore'):
            return _body_model(robot_description, body_link, density, find_package, where)
    except ValueError as error:
        raise ValueError(' '.join(str(error).split())) from None
    except Exception as error:  # noqa: B902 - every failure is a refusal, never a traceback
        raise ValueError(f'{where[0]}: {type(error).__name__}: '
                         f'{" ".join(str(error).split())}'[:MAX_REASON]) from None


def _body_model(text: str, name: str, density: float, find_package: PackageFinder,
                where: list) -> BodyModel:
    """Return ``body_model``'s body; ``where[0]`` names the element being read."""
    link = _link(text, name)
    where[0] = f'link {link.name!r}'
    collisions, visuals = link.collisions, link.visuals
    if not collisions:
        raise ValueError(f'link {link.name!r} has no <collision>: the body is grabbed by its '
                         'collision geometry and lands on it; give it one')
    files = MeshFiles(find_package)
    for kind, elements in (('collision', collisions), ('visual', visuals)):
        for number, element in enumerate(elements):
            if element.geometry.mesh is not None:
                where[0] = _where(link.name, kind, number, len(elements))
                _prefixed(where[0], files.add, element.geometry.mesh.filename)
    where[0] = f'link {link.name!r}'
    _prefixed(where[0], files.read)
    pieces = {}
    for kind, elements in (('collision', collisions), ('visual', visuals)):
        built = []
        for number, element in enumerate(elements):
            where[0] = _where(link.name, kind, number, len(elements))
            built.append(_prefixed(where[0], _piece, element, kind, files))
        pieces[kind] = tuple(built)
    where[0] = f'link {link.name!r}'
    _check_hulls(link.name, pieces['collision'])
    notes: Tuple[str, ...] = ()
    if link.inertial is not None:
        mass, inertia, com = _inertial(link)
        notes = _inertia_notes(link.name, mass, inertia, pieces['collision'])
    elif density > 0.0:
        mass, inertia, com = _from_density(pieces['collision'], density, link.name)
    else:
        raise ValueError(
            f'link {link.name!r} has no <inertial>: give it one (mass, origin at the COM, '
            'inertia) or set density (kg/m^3) to compute them from its collision geometry')
    geometry = BodyGeometry(link.name, tuple(float(c) for c in com), pieces['collision'],
                            pieces['visual'])
    model = BodyModel(mass, inertia, geometry, notes)
    model.rigid_body()
    return model


def _inertia_notes(link: str, mass: float, inertia: Symmetric3,
                   pieces: Tuple[Piece, ...]) -> Tuple[str, ...]:
    """Return the warning of ``inertia_check`` for the link's inertial, if it gives one."""
    try:
        geometry_mass, geometry_inertia, _ = _from_density(pieces, 1.0, link)
    except (ValueError, ZeroDivisionError, FloatingPointError):
        return ()  # a geometry whose volume cannot be integrated says nothing
    note = gyration_note(link, mass, inertia, geometry_mass, geometry_inertia)
    return () if note is None else (note,)


def _link(text: str, name: str):
    """Return the yourdfpy link ``name`` of the URDF text (the only one when name is empty)."""
    root = checked_root(text)
    elements = link_elements(root)
    links = [element.get('name') for element in elements]
    if not links:
        raise ValueError('robot_description has no <link>')
    if not name:
        if len(links) > 1:
            raise ValueError(f'robot_description has {len(links)} links ({", ".join(links)}): '
                             'set body_link to the one to simulate')
        name = links[0]
    if name not in links:
        raise ValueError(f'body_link {name!r} is not a link of robot_description; its links: '
                         f'{", ".join(links)}')
    check_link(elements[links.index(name)])
    logger = logging.getLogger('yourdfpy')
    level = logger.level
    logger.setLevel(logging.CRITICAL)
    try:
        urdf = yourdfpy.URDF.load(io.BytesIO(etree.tostring(root)), build_scene_graph=False,
                                  load_meshes=False, load_collision_meshes=False)
    except Exception as error:  # noqa: B902 - yourdfpy raises many kinds on what it rejects
        raise ValueError(f'robot_description is not a valid URDF: {type(error).__name__} '
                         f'{error}') from None
    finally:
        logger.setLevel(level)
    if name not in urdf.link_map:
        raise ValueError(f'robot_description is not a valid URDF: its parser lost link {name!r}')
    return urdf.link_map[name]


def _where(link: str, kind: str, number: int, count: int) -> str:
    """Return how a refusal names the ``number``-th (from 0) of ``count`` <kind> elements."""
    return f'link {link!r} <{kind}>' + (f' {number + 1}' if count > 1 else '')


def _prefixed(where: str, function, *args):
    """Return ``function(*args)``; a ValueError it raises is prefixed with ``where``."""
    try:
        return function(*args)
    except ValueError as error:
        raise ValueError(f'{where}: {error}') from None


def _piece(element, kind: str, files: MeshFiles, *, closed: Optional[bool] = None) -> Piece:
    """
    Return one ``<collision>`` or ``<visual>`` element as a Piece.

    :param closed: whether a mesh must be a closed surface; None: a collision mesh must.
    """
    transform = np.eye(4) if element.origin is None else np.asarray(element.origin, dtype=float)
    geometry = element.geometry
    color = None
    material = getattr(element, 'material', None)
    if material is not None and material.color is not None:
        color = tuple(float(c) for c in material.color.rgba)
    if geometry.box is not None:
        size = tuple(float(e) for e in geometry.box.size)
        _positive(size, 'box size')
        return Piece('box', transform, size, color=color)
    if geometry.sphere is not None:
        radius = float(geometry.sphere.radius)
        _positive((radius,), 'sphere radius')
        return Piece('sphere', transform, (radius,), color=color)
    if geometry.cylinder is not None:
        size = (float(geometry.cylinder.radius), float(geometry.cylinder.length))
        _positive(size, 'cylinder radius and length')
        return Piece('cylinder', transform, size, color=color)
    if geometry.mesh is not None:
        uri = geometry.mesh.filename
        scale = np.broadcast_to(1.0 if geometry.mesh.scale is None else geometry.mesh.scale, 3)
        scale = tuple(float(s) for s in scale)
        mesh = files.mesh(uri, scale=None if geometry.mesh.scale is None else scale,
                          closed=kind == 'collision' if closed is None else closed)
        reach = float(np.abs(mesh.vertices).max())
        if not reach <= MAX_DISTANCE:
            raise ValueError(f'mesh {uri!r} at scale {" ".join(f"{s:g}" for s in scale)} '
                             f'reaches {reach:g} m from its frame, beyond {MAX_DISTANCE:g} m')
        hull = None
        if kind == 'collision':
            try:
                hull = hull_vertices(mesh.vertices)
            except HullError as error:
                shown = '' if geometry.mesh.scale is None else ' at scale ' + ' '.join(
                    f'{s:g}' for s in scale)
                raise ValueError(
                    f'mesh {uri!r}{shown} has no volume: {error}; a collision piece must bound '
                    'a volume (a sheet is a thin box)') from None
        return Piece('mesh', transform, mesh=mesh, uri=uri, color=color, scale=scale,
                     hull=hull)
    raise ValueError('has no box, sphere, cylinder or mesh')


def _check_hulls(link: str, pieces: Tuple[Piece, ...]) -> None:
    """Refuse collision meshes whose hulls have more vertices together than the floor takes."""
    count = sum(len(piece.hull) for piece in pieces if piece.hull is not None)
    if count > MAX_VERTICES:
        raise ValueError(f'link {link!r}: the hulls of its collision meshes have {count} '
                         f'vertices together, more than {MAX_VERTICES}: simplify the meshes')


def _positive(values: Tuple[float, ...], what: str) -> None:
    if not all(math.isfinite(v) and 0.0 < v <= MAX_DISTANCE for v in values):
        raise ValueError(f'{what} must be finite and > 0 (at most {MAX_DISTANCE:g} m), got '
                         f'{values}')


def _inertial(link) -> Tuple[float, Symmetric3, np.ndarray]:
    """Return the mass, the inertia about the COM in link axes, and the COM of ``<inertial>``."""
    inertial = link.inertial
    origin = np.eye(4) if inertial.origin is None else np.asarray(inertial.origin, dtype=float)
    mass = float(inertial.mass) if inertial.mass is not None else 0.0
    if not mass > 0.0 or not math.isfinite(mass):
        raise ValueError(f'link {link.name!r} <inertial> mass must be finite and > 0, got '
                         f'{mass!r}')
    tensor = np.zeros((3, 3)) if inertial.inertia is None else np.asarray(inertial.inertia,
                                                                          dtype=float)
    rotation = origin[:3, :3]
    if not (rotation - np.eye(3)).any():
        world = tensor  # kept to the bit: a URDF box gives the box parameters' numbers
    else:
        world = rotation @ tensor @ rotation.T
    return mass, _symmetric(world), origin[:3, 3]


def _from_density(pieces: Tuple[Piece, ...], density: float,
                  link: str) -> Tuple[float, Symmetric3, np.ndarray]:
    """Return mass, inertia about the COM (link axes) and COM of the pieces at ``density``."""
    parts = []
    for piece in pieces:
        mass, center, tensor = _piece_mass(piece, density)
        rotation = piece.transform[:3, :3]
        parts.append((mass, rotation @ center + piece.transform[:3, 3],
                      rotation @ tensor @ rotation.T))
    total = sum(m for m, _, _ in parts)
    com = sum(m * c for m, c, _ in parts) / total
    inertia = np.zeros((3, 3))
    for mass, center, tensor in parts:
        d = center - com
        inertia += tensor + mass * (float(d @ d) * np.eye(3) - np.outer(d, d))
    return float(total), _symmetric(inertia), com


def _piece_mass(piece: Piece, density: float) -> Tuple[float, np.ndarray, np.ndarray]:
    """Return a piece's mass, COM and inertia about it, in its own frame."""
    zero = np.zeros(3)
    if piece.kind == 'box':
        x, y, z = piece.size
        m = density * x * y * z
        return m, zero, np.diag((y * y + z * z, x * x + z * z, x * x + y * y)) * (m / 12.0)
    if piece.kind == 'sphere':
        r = piece.size[0]
        m = density * 4.0 / 3.0 * math.pi * r ** 3
        return m, zero, np.eye(3) * (0.4 * m * r * r)
    if piece.kind == 'cylinder':
        r, length = piece.size
        m = density * math.pi * r * r * length
        side = m * (3.0 * r * r + length * length) / 12.0
        return m, zero, np.diag((side, side, 0.5 * m * r * r))
    mesh = piece.mesh.copy()
    mesh.density = density
    return float(mesh.mass), np.asarray(mesh.center_mass), np.asarray(mesh.moment_inertia)


def _symmetric(m: np.ndarray) -> Symmetric3:
    """Return a 3 x 3 tensor in URDF order (ixx, ixy, ixz, iyy, iyz, izz)."""
    return (float(m[0, 0]), float(m[0, 1]), float(m[0, 2]), float(m[1, 1]), float(m[1, 2]),
            float(m[2, 2]))
