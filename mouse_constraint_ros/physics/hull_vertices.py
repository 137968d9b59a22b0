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
The vertices of a many-vertex hull near the floor, found without reading them all each substep.

A vertex p (body frame, from the COM) stands at height c . p above the COM, c the last row of
the rotation R (world z in body axes). The floor asks each substep for the lowest vertex (is
the body touching?) and for those within a band of it (the contacts). Reading every vertex
costs a pass over all of them; a body at rest, or turning slowly, asks about the same few.

So the vertices within ``CANDIDATE_BAND`` of the lowest are kept as candidates, with the row
c0 they were found for. For a row c, every vertex moves by at most |p| |c - c0| <= b d
(b: the farthest vertex from the COM, d = |c - c0|): one that was more than W above the lowest
is still more than W - 2 b d above the lowest now. While 2 b d <= W - band, then, the vertices
within ``band`` of the lowest are all candidates and the candidates answer exactly; past it, or
when too many vertices are near (a large face lying flat), every vertex is read again.

Heights are computed in one arithmetic, ((c_x p_x + c_y p_y) + c_z p_z), on numpy arrays and on
floats alike, so a substep's answer does not depend on whether the candidates gave it.
"""

import math
from typing import List, Optional, Tuple

import numpy as np

# Vertices within this height of the lowest (m), or twice the band asked for, are candidates.
CANDIDATE_BAND = 0.001
# Above this many candidates, every vertex is read (numpy) instead.
MAX_CANDIDATES = 24
# The most vertex contacts: the deepest and three spread over the support polygon
# (``spread``), as Bullet's persistent manifold keeps four points: a face lying flat stands on
# them, and the floor's sweeps cost what a box's do.
MAX_VERTEX_CONTACTS = 4

# (vertex index, height above the COM (m)).
Near = List[Tuple[int, float]]


class HullVertices:
    """The vertices of a body's polytopes (n x 3, body frame from the COM, m), sorted."""

    def __init__(self, points: np.ndarray, bound: float) -> None:
        """
        Keep ``points`` and ``bound`` (m), the farthest any vertex is from the COM.

        :param points: the vertices, n x 3, in the order the contacts are indexed.
        :param bound: at least the largest |p|.
        """
        self.points = np.ascontiguousarray(points, dtype=float)
        self.vertices = [tuple(p) for p in self.points.tolist()]
        self.bound = bound
        # The row of the last full read and its heights; the candidates' row, band, list.
        self._row: Optional[Tuple[float, float, float]] = None
        self._heights: Optional[np.ndarray] = None
        self._candidate_row: Optional[Tuple[float, float, float]] = None
        self._candidate_band = 0.0
        self._candidates: Optional[List[Tuple[int, float, float, float]]] = None
        self._listed_row: Optional[Tuple[float, float, float]] = None
        self._listed: Near = []
        self._listed_lowest = 0.0

    def lowest(self, row: Tuple[float, float, float]) -> float:
        """Return the lowest vertex's height above the COM (m) for the rotation's last row."""
        if self._candidate_heights(row, 0.0):
            return self._listed_lowest
        return float(self._read(row).min())

    def near(self, row: Tuple[float, float, float], ceiling: float, band: float) -> Near:
        """
        Return (index, height) of the vertices near the lowest, in index order.

        Those at most ``ceiling`` high and within ``band`` of the lowest; at most
        MAX_VERTEX_CONTACTS, spread over them.

        :param row: the rotation's last row.
        :param ceiling: the highest a vertex may be above the COM (m).
        :param band: how far above the lowest vertex one may be (m).
        """
        if self._candidate_heights(row, band):
            limit = min(ceiling, self._listed_lowest + band)
            near = [(i, h) for i, h in self._listed if h <= limit]
        else:
            heights = self._read(row)
            chosen = np.flatnonzero(heights <= min(ceiling, float(heights.min()) + band))
            near = list(zip(chosen.tolist(), heights[chosen].tolist()))
        if len(near) > MAX_VERTEX_CONTACTS:
            near = spread(self.points, near, row)
        return near

    def _candidate_heights(self, row: Tuple[float, float, float], band: float) -> bool:
        """
        Return whether the candidates answer for ``band`` at ``row``.

        If they do, ``_listed`` holds their (index, height) and ``_listed_lowest`` the lowest.
        """
        if not band < math.inf:
            return False
        r20, r21, r22 = row
        c0 = self._candidate_row
        if c0 is None or 2.0 * self.bound * math.sqrt(
                (r20 - c0[0]) ** 2 + (r21 - c0[1]) ** 2 + (r22 - c0[2]) ** 2) \
                > self._candidate_band - band:
            width = max(CANDIDATE_BAND, 2.0 * band)
            heights = self._read(row)
            chosen = np.flatnonzero(heights <= float(heights.min()) + width)
            self._listed_row = None
            if len(chosen) > MAX_CANDIDATES:
                # Too many to keep: the next call reads them all again, for its own band.
                self._candidate_row = self._candidates = None
                return False
            self._candidate_row, self._candidate_band = row, width
            self._candidates = [(i, *self.vertices[i]) for i in chosen.tolist()]
        if self._listed_row != row:
            # The touching test and the contacts of a substep ask for the same row.
            self._listed_row = row
            self._listed = [(i, r20 * a + r21 * b + r22 * c) for i, a, b, c in self._candidates]
            self._listed_lowest = min(h for _, h in self._listed)
        return True

    def _read(self, row: Tuple[float, float, float]) -> np.ndarray:
        """Return every vertex's height for ``row``; the last row's are kept."""
        if self._row != row:
            p = self.points
            self._row = row
            self._heights = p[:, 0] * row[0] + p[:, 1] * row[1] + p[:, 2] * row[2]
        return self._heights


def spread(points: np.ndarray, near: Near, row: Tuple[float, float, float]) -> Near:
    """
    Return MAX_VERTEX_CONTACTS or fewer of ``near`` that span them, in index order.

    The deepest point, the one farthest from it across the floor, and the two farthest on
    either side of the line through both: a quadrilateral of nearly the largest area (Bullet
    keeps its persistent manifold's four points so). Fewer when points coincide or lie on one
    line. Across the floor is the plane normal to ``row``: distances there are those of the
    world's x and y.
    """
    index = np.array([i for i, _ in near])
    heights = np.array([h for _, h in near])
    p = points[index]
    flat = p - np.outer(heights, row)
    deepest = int(np.argmin(heights))
    offset = flat - flat[deepest]
    far = int(np.argmax(np.einsum('ij,ij->i', offset, offset)))
    side = np.cross(offset, offset[far]) @ np.asarray(row)
    keep = sorted({deepest, far, int(np.argmax(side)), int(np.argmin(side))})
    return [near[k] for k in keep]
