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
Where a grab lands on the body: the distance from a point to the body's shape, and the anchor.

A grab is a world point, such as one clicked on the body in RViz or in the browser. It is taken
when it lies on or inside one of the body's collision pieces (``BodyGeometry.distance``: a URDF
link's boxes, spheres, cylinders and closed meshes, or the box of ``box_size`` centred at the
COM) turned with the body, or at most ``margin`` outside: a click lands on the body as drawn,
by markers that trail the latest tick and a depth buffer of limited precision. The point,
expressed in the body (link) frame, is then the new anchor, unchanged (not projected onto the
shape): its world position is the grabbed point, so the
anchor error C = x + R r - x_mouse (seed eq. 1.1) is zero when the target is set there and
nothing jumps. No ROS here.
"""

import math
import sys
from typing import NamedTuple, Sequence

from ..description.body_geometry import BodyGeometry, box_distance
from ..physics import BodyState
from ..physics.algebra import multiply_transposed, rotation_matrix, Vector3


def to_body_frame(state: BodyState, point: Sequence[float]) -> Vector3:
    """
    Return the world ``point`` in the body frame of ``state``: R^T (point - x), from its origin.

    :param state: the body's pose (position and unit orientation x y z w).
    :param point: x, y, z in the world frame (m).
    """
    x, y, z = state.position
    offset = (float(point[0]) - x, float(point[1]) - y, float(point[2]) - z)
    return multiply_transposed(offset, rotation_matrix(state.orientation))


# The rounding of a world point into the body frame and onto the box, in units of the sizes
# involved (|point| + |position| + the box's diagonal): a few float epsilons of them.
ROUNDING = 8.0 * sys.float_info.epsilon


class Grab(NamedTuple):
    """
    What a grab gives: the body-frame point and its distance off the box (m, 0 on it).

    ``rounding`` bounds the error of that distance (m): a point exactly on the box (its corner,
    with margin 0) is a few 1e-17 m off once turned into the body frame, and is taken.
    """

    anchor: Vector3
    distance: float
    rounding: float = 0.0

    def taken(self, margin: float) -> bool:
        """Return whether the point is within ``margin`` (m) of the box, up to rounding."""
        return self.distance <= margin + self.rounding


def grab(state: BodyState, geometry: BodyGeometry, point: Sequence[float]) -> Grab:
    """
    Return the body-frame anchor for the world ``point`` and how far off the body it is.

    :param state: the pose of the body's frame (the link's) when the grab arrives.
    :param geometry: the body's shape in that frame.
    :param point: the grabbed point in the world frame (m), finite.
    """
    local = to_body_frame(state, point)
    scale = math.hypot(*point) + math.hypot(*state.position) + math.hypot(*geometry.extents)
    return Grab(local, geometry.distance(local), ROUNDING * scale)


__all__ = ['box_distance', 'grab', 'Grab', 'to_body_frame']
