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
The body's convex collision pieces, in the body frame from the COM, and their floor contacts.

A body is a union of convex pieces; each meets the floor where it reaches lowest:

- polytopes (a box, a mesh's convex hull): their vertices, fixed in the body. A vertex within
  the contact margin of the plane is a contact (a shape of more than ``PLAIN_VERTICES``: only
  within a band above its lowest vertex, what the substep can bring down to the plane, and at
  most four that span them; ``hull_vertices``);
- spheres: exactly the lowest point, centre - radius z, one contact that rolls with the body;
- cylinders: exactly the lowest point of each rim circle, and the rim points a quarter, a half
  and three quarters of the way round from it (``RIM_POINTS`` per rim), so a cylinder on its
  side rolls on two exact points and one on its base stands on a square inscribed in it whose
  corner is the rim's lowest point (the one it would tip over).

Vertices are kept sorted by (-z, -y, -x): a box's eight corners then come in the order of its
index bits (bit 0 set: -x, bit 1: -y, bit 2: -z; ``box_corners``), and a box, a mesh cube and
a URDF box give the same contacts in the same order, so they step alike to the bit. Contacts
are indexed (vertices first, then the spheres' and the rims' points) so that the floor's warm
start matches those of two substeps.
"""

from dataclasses import dataclass, field
import math
from typing import List, Optional, Sequence, Tuple

import numpy as np

from .algebra import Vector3
from .hull_vertices import HullVertices
from .limits import MAX_DISTANCE
from .validation import finite_vector, scalar, shown

# Shapes of at most this many vertices (a box, a mesh cube) take every vertex within the margin
# as a contact, on plain floats in the box's own order and arithmetic.
PLAIN_VERTICES = 8
# Contacts per cylinder rim: the lowest point and three more, a quarter turn apart.
RIM_POINTS = 4
# The most vertices a body's pieces may have in all: the contact test reads them every substep.
MAX_VERTICES = 100000

# (index, r_x, r_y, r_z, separation): a contact point offset r from the COM (world axes, m) and
# how far above the plane it is (m).
Contact = Tuple[int, float, float, float, float]


@dataclass(frozen=True)
class Sphere:
    """A sphere of ``radius`` (m) centred at ``center`` (body frame, from the COM, m)."""

    center: Vector3
    radius: float


@dataclass(frozen=True)
class Cylinder:
    """
    A solid cylinder: ``center`` and unit ``axis`` in the body frame (from the COM), m.

    :param radius: its radius (m).
    :param half_length: half its length along the axis (m).
    """

    center: Vector3
    axis: Vector3
    radius: float
    half_length: float


@dataclass(frozen=True)
class CollisionShape:
    """
    The convex pieces of a body, in the body frame from the COM (m).

    :param vertices: the polytopes' vertices (boxes' corners, meshes' hull vertices), n x 3.
    :param spheres: the spheres.
    :param cylinders: the cylinders.
    """

    vertices: Tuple[Vector3, ...] = ()
    spheres: Tuple[Sphere, ...] = ()
    cylinders: Tuple[Cylinder, ...] = ()
    # Derived: the radius of a ball about the COM holding every piece (a cheap bound of the
    # reach below it), and a many-vertex shape's vertices as ``hull_vertices`` keeps them.
    bound: float = field(init=False, repr=False, compare=False)
    hull: Optional[HullVertices] = field(init=False, repr=False, compare=False)

    def __post_init__(self) -> None:
        """Validate the pieces, sort the vertices, derive the bound; raise ValueError."""
        if not (self.vertices or self.spheres or self.cylinders):
            raise ValueError('a collision shape needs at least one piece')
        points = np.array(self.vertices, dtype=float).reshape(-1, 3)
        if len(points) > MAX_VERTICES:
            raise ValueError(f'the collision pieces have {len(points)} vertices, more than '
                             f'{MAX_VERTICES}: simplify the meshes')
        if not np.isfinite(points).all() or (len(points) and np.abs(points).max() > MAX_DISTANCE):
            raise ValueError(f'collision vertices must be finite and within {MAX_DISTANCE:g} m')
        order = np.lexsort((-points[:, 0], -points[:, 1], -points[:, 2])) if len(points) else []
        points = points[order]
        object.__setattr__(self, 'vertices', tuple(tuple(float(c) for c in p) for p in points))
        bound = float(np.sqrt((points * points).sum(axis=1)).max()) if len(points) else 0.0
        object.__setattr__(self, 'hull', HullVertices(points, bound)
                           if len(points) > PLAIN_VERTICES else None)
        for sphere in self.spheres:
            finite_vector('sphere center', sphere.center)
            scalar('sphere radius', sphere.radius, above=0.0, at_most=MAX_DISTANCE)
            bound = max(bound, math.hypot(*sphere.center) + sphere.radius)
        for cylinder in self.cylinders:
            finite_vector('cylinder center', cylinder.center)
            axis = finite_vector('cylinder axis', cylinder.axis)
            if abs(math.hypot(*axis) - 1.0) > 1e-9:
                raise ValueError(f'cylinder axis must be a unit vector, got {shown(axis)}')
            scalar('cylinder radius', cylinder.radius, above=0.0, at_most=MAX_DISTANCE)
            scalar('cylinder length', cylinder.half_length, above=0.0, at_most=MAX_DISTANCE)
            bound = max(bound, math.hypot(*cylinder.center)
                        + math.hypot(cylinder.radius, cylinder.half_length))
        object.__setattr__(self, 'bound', bound)

    @classmethod
    def box(cls, size: Sequence[float], center: Vector3 = (0.0, 0.0, 0.0)) -> 'CollisionShape':
        """Return a box of full edge lengths ``size`` along the body axes about ``center``."""
        return cls(vertices=box_corners(size, center=center))

    def reach(self, rotation: Sequence[float]) -> float:
        """Return how far below the COM the lowest point reaches (m), for rotation matrix R."""
        r20, r21, r22 = rotation[6], rotation[7], rotation[8]
        lowest = math.inf
        if self.hull is not None:
            lowest = self.hull.lowest((r20, r21, r22))
        else:
            for a, b, c in self.vertices:
                lowest = min(lowest, r20 * a + r21 * b + r22 * c)
        for sphere in self.spheres:
            cx, cy, cz = sphere.center
            lowest = min(lowest, r20 * cx + r21 * cy + r22 * cz - sphere.radius)
        for cylinder in self.cylinders:
            for _, _, rz in _rim_lowest(cylinder, rotation):
                lowest = min(lowest, rz)
        return -lowest

    def contacts(self, rotation: Sequence[float], base: float, margin: float,
                 band: float = math.inf) -> List[Contact]:
        """
        Return the contact points within ``margin`` of the plane, in index order.

        :param rotation: the body's rotation matrix R, row major.
        :param base: the COM's height above the plane (m).
        :param margin: how far above the plane a point is still a contact (m).
        :param band: a many-vertex shape's vertices count only within this much (m) of its
            lowest one: those the substep can bring to the plane (``floor_contact``).
        """
        r00, r01, r02, r10, r11, r12, r20, r21, r22 = rotation
        found: List[Contact] = []
        count = len(self.vertices)
        if count:
            if count <= PLAIN_VERTICES:
                # A box: plain floats, in the order and the arithmetic of the box's corners.
                for index, (a, b, c) in enumerate(self.vertices):
                    rz = r20 * a + r21 * b + r22 * c
                    s = base + rz
                    if s <= margin:
                        found.append((index, r00 * a + r01 * b + r02 * c,
                                      r10 * a + r11 * b + r12 * c, rz, s))
            else:
                for i, rz in self.hull.near((r20, r21, r22), margin - base, band):
                    a, b, c = self.vertices[i]
                    found.append((i, r00 * a + r01 * b + r02 * c, r10 * a + r11 * b + r12 * c,
                                  rz, base + rz))
        index = count
        for sphere in self.spheres:
            cx, cy, cz = sphere.center
            rz = r20 * cx + r21 * cy + r22 * cz - sphere.radius
            s = base + rz
            if s <= margin:
                found.append((index, r00 * cx + r01 * cy + r02 * cz,
                              r10 * cx + r11 * cy + r12 * cz, rz, s))
            index += 1
        for cylinder in self.cylinders:
            for rx, ry, rz in _rim_points(cylinder, rotation):
                s = base + rz
                if s <= margin:
                    found.append((index, rx, ry, rz, s))
                index += 1
        return found


def box_corners(size: Sequence[float], *, center: Vector3 = (0.0, 0.0, 0.0),
                rotation: Optional[np.ndarray] = None) -> Tuple[Vector3, ...]:
    """
    Return the eight corners of a box of full edge lengths ``size`` (m).

    :param center: the box's centre (m).
    :param rotation: the 3 x 3 rotation of its axes; None: the frame's.
    """
    hx, hy, hz = (0.5 * float(e) for e in size)
    corners = []
    for i in range(8):
        local = np.array((-hx if i & 1 else hx, -hy if i & 2 else hy, -hz if i & 4 else hz))
        if rotation is not None:
            local = rotation @ local
        corners.append(tuple(float(c + o) for c, o in zip(local, center)))
    return tuple(corners)


def _rim_frame(cylinder: Cylinder, rotation: Sequence[float]):
    """Return the rims' world centres (from the COM), the axis and the rim's down direction."""
    r00, r01, r02, r10, r11, r12, r20, r21, r22 = rotation
    cx, cy, cz = cylinder.center
    ax, ay, az = cylinder.axis
    center = (r00 * cx + r01 * cy + r02 * cz, r10 * cx + r11 * cy + r12 * cz,
              r20 * cx + r21 * cy + r22 * cz)
    axis = (r00 * ax + r01 * ay + r02 * az, r10 * ax + r11 * ay + r12 * az,
            r20 * ax + r21 * ay + r22 * az)
    # Down (0, 0, -1) projected onto the rim's plane: -z + (z . a) a.
    dx, dy, dz = axis[2] * axis[0], axis[2] * axis[1], axis[2] * axis[2] - 1.0
    size = math.sqrt(dx * dx + dy * dy + dz * dz)
    if size < 1e-9:
        # The axis is vertical: any rim direction is lowest; the body's own, for continuity.
        ux, uy, uz = (r00 * 1.0, r10 * 1.0, r20 * 1.0) if abs(axis[0]) < 0.9 else (r01, r11, r21)
        dot = ux * axis[0] + uy * axis[1] + uz * axis[2]
        dx, dy, dz = ux - dot * axis[0], uy - dot * axis[1], uz - dot * axis[2]
        size = math.sqrt(dx * dx + dy * dy + dz * dz)
    down = (dx / size, dy / size, dz / size)
    h = cylinder.half_length
    rims = tuple((center[0] + sign * h * axis[0], center[1] + sign * h * axis[1],
                  center[2] + sign * h * axis[2]) for sign in (1.0, -1.0))
    return rims, axis, down


def _rim_lowest(cylinder: Cylinder, rotation: Sequence[float]) -> List[Vector3]:
    """Return each rim's lowest point, from the COM in world axes (m)."""
    rims, _, down = _rim_frame(cylinder, rotation)
    r = cylinder.radius
    return [(c[0] + r * down[0], c[1] + r * down[1], c[2] + r * down[2]) for c in rims]


def _rim_points(cylinder: Cylinder, rotation: Sequence[float]) -> List[Vector3]:
    """Return RIM_POINTS points of each rim, a quarter turn apart from its lowest one."""
    rims, axis, down = _rim_frame(cylinder, rotation)
    # side = axis x down: the rim's direction a quarter turn from down.
    side = (axis[1] * down[2] - axis[2] * down[1], axis[2] * down[0] - axis[0] * down[2],
            axis[0] * down[1] - axis[1] * down[0])
    r = cylinder.radius
    points = []
    for c in rims:
        for u, v in ((1.0, 0.0), (0.0, 1.0), (-1.0, 0.0), (0.0, -1.0)):
            points.append(tuple(c[k] + r * (u * down[k] + v * side[k]) for k in range(3)))
    return points
