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
from typing import NamedTuple, Tuple

from lxml import etree
import numpy as np
import yourdfpy

from .body_geometry import BodyGeometry, Piece
from .mesh_files import ament_share, load_mesh, PackageFinder
from .xml_declaration import as_xml_1_0
from ..physics.algebra import Symmetric3
from ..physics.body import RigidBody


class BodyModel(NamedTuple):
    """A link as a rigid body: mass (kg), inertia about the COM in link axes, its geometry."""

    mass: float
    inertia: Symmetric3
    geometry: BodyGeometry

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

    :param robot_description: the URDF (XML text).
    :param body_link: the link's name; empty: the URDF's only link.
    :param density: kg/m^3 for a link without ``<inertial>``; 0: such a link is refused.
    :param find_package: the share directory of a ``package://`` name (the ament index's).
    """
    link = _link(robot_description, body_link)
    collisions = tuple(_piece(element, link.name, 'collision', find_package)
                       for element in link.collisions)
    if not collisions:
        raise ValueError(f'link {link.name!r} has no <collision>: the body is grabbed by its '
                         'collision geometry and lands on it; give it one')
    visuals = tuple(_piece(element, link.name, 'visual', find_package)
                    for element in link.visuals)
    if link.inertial is not None:
        mass, inertia, com = _inertial(link)
    elif density > 0.0:
        mass, inertia, com = _from_density(collisions, density, link.name)
    else:
        raise ValueError(
            f'link {link.name!r} has no <inertial>: give it one (mass, origin at the COM, '
            'inertia) or set density (kg/m^3) to compute them from its collision geometry')
    geometry = BodyGeometry(link.name, tuple(float(c) for c in com), collisions, visuals)
    model = BodyModel(mass, inertia, geometry)
    model.rigid_body()
    return model


def _link(text: str, name: str):
    """Return the yourdfpy link ``name`` of the URDF text (the only one when name is empty)."""
    if not isinstance(text, str) or not text.strip():
        raise ValueError('robot_description is empty')
    data = as_xml_1_0(text).encode()  # pybullet's URDFs declare version 0.0
    try:
        root = etree.fromstring(data)
    except etree.XMLSyntaxError as error:
        raise ValueError(f'robot_description is not well-formed XML: {error}') from None
    if root.tag != 'robot':
        raise ValueError(f'robot_description must have a <robot> root, got <{root.tag}>')
    logger = logging.getLogger('yourdfpy')
    level = logger.level
    logger.setLevel(logging.CRITICAL)
    try:
        urdf = yourdfpy.URDF.load(io.BytesIO(data), build_scene_graph=False, load_meshes=False,
                                  load_collision_meshes=False)
    except (ValueError, KeyError, TypeError, AttributeError) as error:
        raise ValueError(f'robot_description is not a valid URDF: {type(error).__name__} '
                         f'{error}') from None
    finally:
        logger.setLevel(level)
    links = [link.name for link in urdf.robot.links]
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
    return urdf.link_map[name]


def _piece(element, link: str, kind: str, find_package: PackageFinder) -> Piece:
    """Return one ``<collision>`` or ``<visual>`` element as a Piece."""
    transform = np.eye(4) if element.origin is None else np.asarray(element.origin, dtype=float)
    geometry = element.geometry
    color = None
    material = getattr(element, 'material', None)
    if material is not None and material.color is not None:
        color = tuple(float(c) for c in material.color.rgba)
    where = f'link {link!r} <{kind}>'
    if geometry.box is not None:
        size = tuple(float(e) for e in geometry.box.size)
        _positive(size, where + ' box size')
        return Piece('box', transform, size, color=color)
    if geometry.sphere is not None:
        radius = float(geometry.sphere.radius)
        _positive((radius,), where + ' sphere radius')
        return Piece('sphere', transform, (radius,), color=color)
    if geometry.cylinder is not None:
        size = (float(geometry.cylinder.radius), float(geometry.cylinder.length))
        _positive(size, where + ' cylinder radius and length')
        return Piece('cylinder', transform, size, color=color)
    if geometry.mesh is not None:
        uri = geometry.mesh.filename
        try:
            mesh = load_mesh(uri, scale=geometry.mesh.scale, closed=kind == 'collision',
                             find_package=find_package)
        except ValueError as error:
            raise ValueError(f'{where}: {error}') from None
        scale = np.broadcast_to(1.0 if geometry.mesh.scale is None else geometry.mesh.scale, 3)
        return Piece('mesh', transform, mesh=mesh, uri=uri, color=color,
                     scale=tuple(float(s) for s in scale))
    raise ValueError(f'{where} has no box, sphere, cylinder or mesh')


def _positive(values: Tuple[float, ...], what: str) -> None:
    if not all(math.isfinite(v) and v > 0.0 for v in values):
        raise ValueError(f'{what} must be finite and > 0, got {values}')


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
