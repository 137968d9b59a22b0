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
vertices come in the order of the input, as trimesh's hull gives them.

A point set without volume (a point, points on a line or in a plane) has no hull: ``HullError``
says which.
"""

import numpy as np
from scipy.spatial import ConvexHull, QhullError

# A hull thinner than this fraction of its extent counts as flat: its volume is below
# (extent^3 FLAT) (a sheet of float rounding, not a solid).
FLAT = 1e-9


class HullError(ValueError):
    """The points bound no volume; the message says how they lie."""


def hull_vertices(points: np.ndarray) -> np.ndarray:
    """
    Return the vertices of the convex hull of ``points`` (n x 3), in their input order.

    :raises HullError: the points lie at one point, on a line or in a plane.
    """
    points = np.asarray(points, dtype=float).reshape(-1, 3)
    shape = _flatness(points)
    if shape is not None:
        raise HullError(shape)
    try:
        hull = ConvexHull(points, qhull_options='Q0')
    except QhullError:
        try:
            hull = ConvexHull(points, qhull_options='QJ')
        except QhullError:
            raise HullError('its points lie in a plane') from None
    extent = float(np.ptp(points, axis=0).max())
    if not hull.volume > FLAT * extent ** 3:
        raise HullError('its points lie in a plane')
    return points[np.sort(hull.vertices)]


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
