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
The convex hull's vertices of a point set, in time that grows gently with the points.

Qhull's default merging of coplanar facets (trimesh's ``QbB Pp``) takes quadratic time and
more on points that lie on circles, as every cylinder's rims do: 20 000 such points take
seconds. Without merging (``Q0``) Qhull takes milliseconds for them and keeps the same
vertices on the shapes a URDF holds (boxes, cylinders, revolved cups, spheres; the tests
compare it with trimesh's hull); where it meets a precision problem it joggles (``QJ``). The
vertices come in the order of the input, as trimesh's hull gives them. Its time still grows
with the square of the points on circles: the input is bounded (``MAX_HULL_INPUT``).

A point set without volume (a point, points on a line or in a plane) has no hull: ``HullError``
says which.
"""

from typing import TYPE_CHECKING

import numpy as np

if TYPE_CHECKING:
    from scipy.spatial import ConvexHull

# A hull thinner than this fraction of its extent counts as flat: its volume is below
# (extent^3 FLAT) (a sheet of float rounding, not a solid).
FLAT = 1e-9
# The most points Qhull is given for one hull (a fraction of a second on points on circles,
# where its time grows with their square), the sample whose hull drops the inner points of
# more, and the points tested against that hull at once (a bound on the memory).
MAX_HULL_INPUT = 10000
SAMPLE = 256
CHUNK = 4096


class HullError(ValueError):
    """The points bound no volume; the message says how they lie."""


def hull_vertices(points: np.ndarray) -> np.ndarray:
    """
    Return the vertices of the convex hull of ``points`` (n x 3), in their input order.

    Of more than ``MAX_HULL_INPUT`` points, those strictly inside the hull of an even sample of
    ``SAMPLE`` of them are no vertices and are dropped first; if more than ``MAX_HULL_INPUT``
    remain (points on circles all are vertices), the hull is that of an even sample of
    ``MAX_HULL_INPUT`` of them.

    :raises HullError: the points lie at one point, on a line or in a plane.
    """
    points = np.asarray(points, dtype=float).reshape(-1, 3)
    shape = _flatness(points)
    if shape is not None:
        raise HullError(shape)
    chosen = np.arange(len(points))
    if len(points) > MAX_HULL_INPUT:
        chosen = _outside_sample(points)
        if len(chosen) > MAX_HULL_INPUT:
            chosen = chosen[_even(len(chosen), MAX_HULL_INPUT)]
    hull = _hull(points[chosen])
    extent = float(np.ptp(points, axis=0).max())
    if not hull.volume > FLAT * extent ** 3:
        raise HullError('its points lie in a plane')
    return points[np.sort(chosen[hull.vertices])]


def _hull(points: np.ndarray) -> 'ConvexHull':
    """Return Qhull's hull of ``points``, joggled where it meets a precision problem."""
    from scipy.spatial import ConvexHull, QhullError  # a URDF body's: the box runs without
    try:
        return ConvexHull(points, qhull_options='Q0')
    except QhullError:
        try:
            return ConvexHull(points, qhull_options='QJ')
        except QhullError:
            raise HullError('its points lie in a plane') from None


def _even(count: int, taken: int) -> np.ndarray:
    """Return ``taken`` indices spread evenly over ``range(count)``, the first and last in."""
    return np.unique(np.linspace(0, count - 1, taken).round().astype(int))


def _outside_sample(points: np.ndarray) -> np.ndarray:
    """Return the indices of ``points`` not strictly inside the hull of an even sample."""
    sample = _even(len(points), SAMPLE)
    try:
        hull = _hull(points[sample])
    except HullError:
        return np.arange(len(points))
    tolerance = FLAT * float(np.ptp(points, axis=0).max())
    keep = np.zeros(len(points), dtype=bool)
    keep[sample[hull.vertices]] = True
    normals, offsets = hull.equations[:, :3], hull.equations[:, 3]
    for start in range(0, len(points), CHUNK):
        part = points[start:start + CHUNK]
        keep[start:start + CHUNK] |= (part @ normals.T + offsets).max(axis=1) > -tolerance
    return np.flatnonzero(keep)


def _flatness(points: np.ndarray):
    """Return how points without volume lie ('at one point', ...), or None for a solid."""
    if len(points) == 0:
        return 'it has no points'
    centred = points - points.mean(axis=0)
    singular = np.linalg.svd(centred, compute_uv=False)
    top = float(singular[0]) if len(singular) else 0.0
    if not top > 0.0:
        return 'its points lie at one point'
    if len(singular) < 2 or not singular[1] > FLAT * top:
        return 'its points lie on a line'
    if len(singular) < 3 or not singular[2] > FLAT * top:
        return 'its points lie in a plane'
    return None
