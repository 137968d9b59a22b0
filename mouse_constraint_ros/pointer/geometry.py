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
Where a pointer meets the body and the drag plane, in the world frame (plain floats, no ROS).

A press on the body is a ray from the camera; ``ray_box_hit`` finds where it first meets the
body's box (``box_size`` centred at the COM, turned with the body) by the slab method in the
body frame. While dragging, the pointer's ray meets the plane that faces the camera through the
grabbed point (``camera_plane_point``): the target stays at the grabbed point's depth, as in the
Box2D and Bounce testbeds and MuJoCo's perturbation. ``material_point`` carries a point of the
body from the pose the browser showed to the pose the node has now, so that a grab lands on the
point the user pressed even when the body moved since it was drawn. ``framing`` places a camera
that shows the body at a readable size. ``unit_pose`` takes a pose from a client as the turn its
quaternion stands for (normalised), or not at all when no turn can be read from it.
"""

import math
from typing import NamedTuple, Optional, Sequence

from ..physics.algebra import multiply, multiply_transposed, Quaternion, rotation_matrix, Vector3

# A quaternion whose squared norm is this close to 1 is unit to rounding.
UNIT_ROUNDING = 1e-12
# Below this |cos| between a ray and a plane's normal the ray counts as parallel to the plane.
PARALLEL = 1e-9
# A framed body's longest edge spans this fraction of the view's height, seen from this side
# (from the body towards the camera: front right, a little above).
FRAME_FRACTION = 0.25
FRAME_SIDE = (1.2, -1.6, 0.5)
# The near clipping plane at this fraction of the framing distance.
NEAR_FRACTION = 0.01


class Pose(NamedTuple):
    """A body pose: COM position (m) and orientation (x, y, z, w), world frame."""

    position: Vector3
    orientation: Quaternion


def unit_pose(pose: Pose) -> Optional[Pose]:
    """
    Return ``pose`` with its quaternion normalised, or None when it holds no pose.

    A quaternion q != 0 stands for the same turn as q / |q|; one unit to rounding (its squared
    norm within ``UNIT_ROUNDING`` of 1, as the node sends them) is kept bit for bit. None: a
    position or a quaternion component that is not finite, or a quaternion whose squared norm is
    not a positive finite number (zero, or one that overflows such as (1e300, 0, 0, 0)).
    """
    position = tuple(float(c) for c in pose.position)
    orientation = tuple(float(c) for c in pose.orientation)
    if len(position) != 3 or len(orientation) != 4:
        return None
    squared = sum(c * c for c in orientation)
    if not all(math.isfinite(c) for c in position) or not 0.0 < squared < math.inf:
        return None
    if abs(squared - 1.0) <= UNIT_ROUNDING:
        return Pose(position, orientation)
    norm = math.sqrt(squared)
    return Pose(position, tuple(c / norm for c in orientation))


def _sub(a: Sequence[float], b: Sequence[float]) -> Vector3:
    return (a[0] - b[0], a[1] - b[1], a[2] - b[2])


def _dot(a: Sequence[float], b: Sequence[float]) -> float:
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]


def _along(origin: Sequence[float], direction: Sequence[float], t: float) -> Vector3:
    return (origin[0] + t * direction[0], origin[1] + t * direction[1],
            origin[2] + t * direction[2])


def ray_box_hit(origin: Sequence[float], direction: Sequence[float], *, pose: Pose,
                box_size: Sequence[float]) -> Optional[Vector3]:
    """
    Return the first point where a ray meets the body's box, or None when it misses.

    The ray and the box are taken into the body frame (R^T (p - x)), where the box is
    [-s/2, s/2] on each axis, and each pair of faces bounds the ray's parameter t (the slab
    method). A ray that starts inside the box meets it where it leaves.

    :param origin: the ray's origin, world frame (m).
    :param direction: the ray's direction, world frame (any non-zero length).
    :param pose: the body's pose.
    :param box_size: the box's full edge lengths (m).
    :returns: the world point (m), or None for a miss, a ray pointing away, or a zero or
        non-finite direction.
    """
    rotation = rotation_matrix(pose.orientation)
    start = multiply_transposed(_sub(origin, pose.position), rotation)
    heading = multiply_transposed(tuple(float(c) for c in direction), rotation)
    if not all(math.isfinite(c) for c in (*start, *heading)) or not any(heading):
        return None
    near, far = -math.inf, math.inf
    for p, d, size in zip(start, heading, box_size):
        half = 0.5 * size
        if d == 0.0:
            if abs(p) > half:
                return None
            continue
        t1, t2 = (-half - p) / d, (half - p) / d
        near, far = max(near, min(t1, t2)), min(far, max(t1, t2))
    if near > far or far < 0.0:
        return None
    return _along(origin, direction, near if near >= 0.0 else far)


def camera_plane_point(origin: Sequence[float], direction: Sequence[float], *,
                       through: Sequence[float],
                       normal: Sequence[float]) -> Optional[Vector3]:
    """
    Return where a ray meets the plane through ``through`` with normal ``normal``.

    The point is origin + t direction with t = n . (through - origin) / n . direction.

    :param origin: the ray's origin, world frame (m): the camera.
    :param direction: the ray's direction: through the pointer.
    :param through: a point of the plane (m): the grabbed point.
    :param normal: the plane's normal: the camera's viewing direction.
    :returns: the world point (m), or None when the ray is parallel to the plane or meets it
        behind its origin.
    """
    rate = _dot(normal, direction)
    scale = math.sqrt(_dot(normal, normal) * _dot(direction, direction))
    if not math.isfinite(rate) or not scale > 0.0 or abs(rate) <= PARALLEL * scale:
        return None
    t = _dot(normal, _sub(through, origin)) / rate
    if not t >= 0.0:
        return None
    return _along(origin, direction, t)


def local_point(point: Sequence[float], pose: Pose) -> Vector3:
    """Return the world ``point`` in the body frame at ``pose``: R^T (point - x)."""
    return multiply_transposed(_sub(point, pose.position), rotation_matrix(pose.orientation))


def material_point(point: Sequence[float], *, shown: Pose, now: Pose) -> Vector3:
    """
    Return where the body point that was at ``point`` (pose ``shown``) is at pose ``now``.

    The point in the body frame is R_shown^T (point - x_shown); at the new pose it is
    x_now + R_now of that.

    :param point: a world point (m), on the body as it was shown.
    :param shown: the pose the point was taken at.
    :param now: the body's pose now.
    """
    return world_point(now, local_point(point, shown))


def world_point(pose: Pose, local: Sequence[float]) -> Vector3:
    """Return the world position of the body-frame point ``local`` (from the COM) at ``pose``."""
    x = multiply(tuple(float(c) for c in local), rotation_matrix(pose.orientation))
    return (pose.position[0] + x[0], pose.position[1] + x[1], pose.position[2] + x[2])


def wxyz(orientation: Sequence[float]) -> Quaternion:
    """Return a quaternion (x, y, z, w), REP 103's order, in the web view's order (w, x, y, z)."""
    return (orientation[3], orientation[0], orientation[1], orientation[2])


class Framing(NamedTuple):
    """A camera that frames the body: where it is, where it looks, its near plane (m)."""

    position: Vector3
    look_at: Vector3
    near: float


def framing(center: Sequence[float], box_size: Sequence[float], fov: float) -> Framing:
    """
    Return the camera that shows a box of ``box_size`` at ``center`` at a readable size.

    The camera looks at ``center`` from ``FRAME_SIDE``, as far as makes the longest edge span
    ``FRAME_FRACTION`` of the view's height, with its near plane in proportion (a 1 mm box and
    a 4 m box look alike).

    :param center: the box's centre (world, m): the box body's COM, the middle of a URDF
        body's drawn bounds.
    :param box_size: the box's edges (m): the body's drawn bounds.
    :param fov: the camera's vertical field of view (rad).
    """
    distance = max(box_size) / (FRAME_FRACTION * 2.0 * math.tan(0.5 * fov))
    norm = math.sqrt(_dot(FRAME_SIDE, FRAME_SIDE))
    position = _along(center, FRAME_SIDE, distance / norm)
    return Framing(position, tuple(float(c) for c in center), NEAR_FRACTION * distance)
