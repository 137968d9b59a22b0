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
The body's shape in its link frame: collision pieces (what is grabbed and lands), visuals.

Each piece is a URDF ``<collision>`` element: a box, sphere or cylinder (exact) or a closed
triangle mesh, placed by its origin in the link frame. The grab asks ``distance`` (0 on or inside
a piece), the view's and the markers' pointer ask ``ray`` (the nearest hit of a ray on the
pieces: primitives solved in closed form, meshes by trimesh's ray test), the floor takes the
convex pieces ``collision_shape`` gives (a mesh by its convex hull), and the drawings take
``surface`` (the visuals, or the collision pieces where a link has none).
"""

from dataclasses import dataclass
from functools import cached_property
import math
from typing import Optional, Sequence, Tuple, TYPE_CHECKING

import numpy as np

from .hull import hull_vertices
from ..physics.algebra import Vector3
from ..physics.collision import box_corners, CollisionShape, Cylinder, Sphere

if TYPE_CHECKING:
    import trimesh

# Sections of a cylinder and subdivisions of a sphere where one is drawn as triangles.
DRAWN_SECTIONS = 48
DRAWN_SUBDIVISIONS = 3


@dataclass(frozen=True)
class Piece:
    """
    One geometry element of the link, in the link frame.

    :param kind: 'box', 'sphere', 'cylinder' or 'mesh'.
    :param transform: its origin, a 4 x 4 homogeneous transform from its frame to the link's.
    :param size: box (x, y, z) edges; sphere (radius,); cylinder (radius, length) (m).
    :param mesh: the triangle mesh in its own frame, scaled (kind 'mesh').
    :param uri: the mesh's filename as the URDF names it (kind 'mesh').
    :param color: RGBA in [0, 1] (visuals), or None.
    :param scale: the URDF's ``scale`` of the mesh file (x, y, z), which ``mesh`` has applied.
    :param hull: a mesh's convex hull vertices in its own frame (``hull.hull_vertices``), or
        None: found from ``mesh`` when asked.
    """

    kind: str
    transform: np.ndarray
    size: Tuple[float, ...] = ()
    mesh: Optional['trimesh.Trimesh'] = None
    uri: str = ''
    color: Optional[Tuple[float, float, float, float]] = None
    scale: Tuple[float, float, float] = (1.0, 1.0, 1.0)
    hull: Optional[np.ndarray] = None

    def local(self, point: Sequence[float]) -> np.ndarray:
        """Return a link-frame point in the piece's frame."""
        rotation, origin = self.transform[:3, :3], self.transform[:3, 3]
        return rotation.T @ (np.asarray(point, dtype=float) - origin)

    def distance(self, point: Sequence[float]) -> float:
        """Return how far (m) a link-frame point lies from the piece, 0 on or inside it."""
        p = self.local(point)
        if self.kind == 'box':
            return box_distance(p, self.size)
        if self.kind == 'sphere':
            return max(0.0, math.hypot(*p) - self.size[0])
        if self.kind == 'cylinder':
            radius, length = self.size
            return math.hypot(max(0.0, math.hypot(p[0], p[1]) - radius),
                              max(0.0, abs(p[2]) - 0.5 * length))
        if self.mesh.contains([p])[0]:
            return 0.0
        import trimesh  # a mesh body's: the box body runs without it
        _, distance, _ = trimesh.proximity.closest_point(self.mesh, [p])
        return float(distance[0])

    def ray(self, origin: Sequence[float], direction: Sequence[float]) -> Optional[float]:
        """Return the nearest t >= 0 where origin + t direction (link frame) meets the piece."""
        rotation = self.transform[:3, :3]
        o = self.local(origin)
        d = rotation.T @ np.asarray(direction, dtype=float)
        if self.kind == 'box':
            return _ray_box(o, d, 0.5 * np.asarray(self.size))
        if self.kind == 'sphere':
            return _ray_sphere(o, d, self.size[0])
        if self.kind == 'cylinder':
            return _ray_cylinder(o, d, *self.size)
        hits, _, _ = self.mesh.ray.intersects_location([o], [d])
        if not len(hits):
            return None
        t = (hits - o) @ d / float(d @ d)
        t = t[t >= 0.0]
        return float(t.min()) if len(t) else None

    def triangles(self) -> 'trimesh.Trimesh':
        """Return the piece as triangles in the link frame (primitives tessellated)."""
        import trimesh
        if self.kind == 'box':
            mesh = trimesh.creation.box(self.size)
        elif self.kind == 'sphere':
            mesh = trimesh.creation.icosphere(DRAWN_SUBDIVISIONS, radius=self.size[0])
        elif self.kind == 'cylinder':
            mesh = trimesh.creation.cylinder(radius=self.size[0], height=self.size[1],
                                             sections=DRAWN_SECTIONS)
        else:
            mesh = self.mesh.copy()
        mesh.apply_transform(self.transform)
        return mesh


@dataclass(frozen=True)
class BodyGeometry:
    """
    A link's geometry: where its COM is and its collision and visual pieces, link frame.

    :param link: the link's name (its TF frame).
    :param com: the COM in the link frame (m): the physics' body frame is the link's, moved
        there.
    :param collisions: the collision pieces (at least one).
    :param visuals: the visual pieces (may be none: then the collision pieces are drawn).
    """

    link: str
    com: Vector3
    collisions: Tuple[Piece, ...]
    visuals: Tuple[Piece, ...] = ()

    @classmethod
    def box(cls, size: Sequence[float], *, link: str = 'body') -> 'BodyGeometry':
        """Return a box of full edge lengths ``size`` (m) about the frame's origin, the COM."""
        return cls(link, (0.0, 0.0, 0.0),
                   (Piece('box', np.eye(4), tuple(float(e) for e in size)),))

    def collision_shape(self) -> CollisionShape:
        """Return the convex collision pieces from the COM (``physics.collision``)."""
        com = np.asarray(self.com, dtype=float)
        vertices, spheres, cylinders = [], [], []
        for piece in self.collisions:
            rotation, origin = piece.transform[:3, :3], piece.transform[:3, 3] - com
            if piece.kind == 'box':
                exact = not (rotation - np.eye(3)).any()
                vertices.extend(box_corners(piece.size, center=tuple(origin),
                                            rotation=None if exact else rotation))
            elif piece.kind == 'sphere':
                spheres.append(Sphere(tuple(float(c) for c in origin), piece.size[0]))
            elif piece.kind == 'cylinder':
                axis = rotation[:, 2] / np.linalg.norm(rotation[:, 2])
                cylinders.append(Cylinder(tuple(float(c) for c in origin),
                                          tuple(float(c) for c in axis), piece.size[0],
                                          0.5 * piece.size[1]))
            else:
                hull = hull_vertices(piece.mesh.vertices) if piece.hull is None else piece.hull
                vertices.extend(tuple(float(c) for c in rotation @ v + origin) for v in hull)
        return CollisionShape(tuple(vertices), tuple(spheres), tuple(cylinders))

    def distance(self, point: Sequence[float]) -> float:
        """Return how far (m) a link-frame point lies from the nearest piece, 0 inside."""
        return min(piece.distance(point) for piece in self.collisions)

    def ray(self, origin: Sequence[float], direction: Sequence[float]) -> Optional[float]:
        """Return the nearest t >= 0 where the link-frame ray meets a collision piece."""
        hits = [t for t in (p.ray(origin, direction) for p in self.collisions) if t is not None]
        return min(hits) if hits else None

    def surface(self, *, collision: bool = False) -> 'trimesh.Trimesh':
        """Return the drawn surface in the link frame: the visuals (or collisions) as one mesh."""
        import trimesh
        pieces = self.collisions if collision or not self.visuals else self.visuals
        return trimesh.util.concatenate([piece.triangles() for piece in pieces])

    @cached_property
    def hull_points(self) -> np.ndarray:
        """Return the convex hull's vertices of all collision pieces, link frame (n x 3)."""
        return hull_vertices(self.surface(collision=True).vertices)

    @cached_property
    def extents(self) -> Tuple[float, float, float]:
        """Return the edges (m) of the link-frame box about the collision pieces' bounds."""
        edges = lone_box(self.collisions)
        if edges is not None:
            return edges
        low, high = self.surface(collision=True).bounds
        return tuple(float(h - lo) for lo, h in zip(low, high))


def lone_box(pieces: Sequence[Piece]) -> Optional[Vector3]:
    """Return the edges (m) of ``pieces`` that are one box about the frame's origin, else None."""
    if len(pieces) == 1 and pieces[0].kind == 'box' and not (
            pieces[0].transform - np.eye(4)).any():
        return tuple(float(e) for e in pieces[0].size)
    return None


def box_distance(local: Sequence[float], box_size: Sequence[float]) -> float:
    """
    Return the distance (m) from a point to the box about the origin, 0 on or inside it.

    The box has edges ``box_size`` along the axes: the distance is the norm of the excess of
    |local_i| over the half edges, where there is one.

    :param local: the point in the box's frame (m).
    :param box_size: the box's full edge lengths (m).
    """
    excess = [max(0.0, abs(float(c)) - 0.5 * size) for c, size in zip(local, box_size)]
    return math.hypot(*excess)


def _ray_box(o: np.ndarray, d: np.ndarray, half: np.ndarray) -> Optional[float]:
    """Return the entry t >= 0 of the ray into the axis-aligned box of half extents (slabs)."""
    low, high = 0.0, math.inf
    for k in range(3):
        if d[k] == 0.0:
            if abs(o[k]) > half[k]:
                return None
            continue
        a, b = (-half[k] - o[k]) / d[k], (half[k] - o[k]) / d[k]
        low, high = max(low, min(a, b)), min(high, max(a, b))
        if low > high:
            return None
    return float(low)


def _ray_sphere(o: np.ndarray, d: np.ndarray, radius: float) -> Optional[float]:
    """Return the nearest t >= 0 of the ray on the sphere about the origin."""
    a, b, c = d @ d, o @ d, o @ o - radius * radius
    disc = b * b - a * c
    if disc < 0.0:
        return None
    root = math.sqrt(disc)
    for t in ((-b - root) / a, (-b + root) / a):
        if t >= 0.0:
            return float(t) if c > 0.0 else 0.0
    return None


def _ray_cylinder(o: np.ndarray, d: np.ndarray, radius: float,
                  length: float) -> Optional[float]:
    """Return the nearest t >= 0 of the ray on the solid cylinder along z about the origin."""
    half = 0.5 * length
    if math.hypot(o[0], o[1]) <= radius and abs(o[2]) <= half:
        return 0.0
    hits = []
    a = d[0] * d[0] + d[1] * d[1]
    if a > 0.0:
        b = o[0] * d[0] + o[1] * d[1]
        c = o[0] * o[0] + o[1] * o[1] - radius * radius
        disc = b * b - a * c
        if disc >= 0.0:
            t = (-b - math.sqrt(disc)) / a
            if t >= 0.0 and abs(o[2] + t * d[2]) <= half:
                hits.append(t)
    if d[2] != 0.0:
        for cap in (half, -half):
            t = (cap - o[2]) / d[2]
            if t >= 0.0 and math.hypot(o[0] + t * d[0], o[1] + t * d[1]) <= radius:
                hits.append(t)
    return float(min(hits)) if hits else None
