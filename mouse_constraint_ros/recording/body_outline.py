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
The outline of a URDF body on the figure's path plots: its convex hull, seen from above or aside.

``body_hull`` reads the recorded node's URDF body from its parameters at the start
(``received.BODY_PARAMETERS``: ``robot_description``, ``body_link``, ``density``) and gives the
convex hull's vertices of its collision pieces in the link frame (``BodyGeometry.hull_points``);
the box body has none (no ``robot_description``), nor has a recording whose node did not answer.
``outline`` places them by a recorded pose (the link frame's: the node publishes it) and returns
the 2-D convex hull of their projection on two world axes, the outline of the body seen along
the third.
"""

from typing import Callable, Mapping, Optional, Sequence, Tuple

import numpy as np


def body_hull(parameters: Mapping[str, object],
              warn: Callable[[str], None] = lambda _text: None) -> Optional[np.ndarray]:
    """
    Return the hull vertices (n x 3, link frame) of the recorded node's URDF body, or None.

    :param parameters: the recorded node's parameters at the start.
    :param warn: told in one line when the URDF cannot be read here (then None).
    """
    description = parameters.get('robot_description')
    if not description:
        return None
    from ..description.urdf_link import body_model  # the parser: a URDF body's figure only
    try:
        geometry = body_model(description, str(parameters.get('body_link', '')),
                              density=float(parameters.get('density', 0.0))).geometry
    except ValueError as error:
        warn(f"the node's robot_description cannot be read here ({error}): the figure draws "
             'no outline of the body')
        return None
    return np.asarray(geometry.hull_points, dtype=float)


def outline(hull: np.ndarray, position: Sequence[float], orientation: Sequence[float],
            axes: Tuple[int, int]) -> Optional[np.ndarray]:
    """
    Return the closed outline of the body seen along the axis not in ``axes``, or None.

    The link-frame ``hull`` points are placed by the pose (x + R p) and projected on the two
    world ``axes``; the outline is the 2-D convex hull of those points, counter-clockwise, its
    first vertex repeated at the end (k + 1 x 2). None when they span no area.

    :param hull: the body's hull vertices in the link frame (n x 3).
    :param position: the link frame's position (m).
    :param orientation: its orientation (x, y, z, w).
    :param axes: the two world axes drawn, e.g. (0, 1) from above.
    """
    from scipy.spatial import ConvexHull, QhullError  # a URDF body's figure only
    from scipy.spatial.transform import Rotation
    world = Rotation.from_quat(orientation).apply(hull) + np.asarray(position, dtype=float)
    flat = world[:, list(axes)]
    try:
        ring = flat[ConvexHull(flat).vertices]
    except QhullError:
        return None
    return np.vstack([ring, ring[:1]])
