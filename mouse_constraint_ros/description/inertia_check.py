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
An ``<inertial>`` far from its link's collision geometry: a warning line, the likely slip named.

The radius of gyration r = sqrt(trace(I) / (2 m)) is the root mean square distance of the mass
from its COM. A link's collision pieces at uniform density give theirs; a body's own can differ
(a hollow shell, a weighted base), but not by a factor of ``FAR`` either way unless a unit
slipped: a URDF written in grams (the mass read as 1000 times the inertia's, r / 31.6), an
inertia for centimetres or millimetres (r / 100, r / 1000), or a placeholder inertia of 1 on a
small body (pybullet's cube_small, duck and teddy: r = 3.9 m on a 5 cm body). The physics
simulates it all the same; the warning says why a body sinks, creeps or rocks as its stated
inertia makes it.
"""

import math
from typing import Optional, Sequence

# A radius of gyration this many times the geometry's, or below one over it, is warned about.
FAR = 10.0


def gyration_note(link: str, mass: float, inertia: Sequence[float], geometry_mass: float,
                  geometry_inertia: Sequence[float]) -> Optional[str]:
    """
    Return one warning line if the inertia's radius of gyration is far from the geometry's.

    :param link: the link's name.
    :param mass: the ``<inertial>`` mass (kg).
    :param inertia: its inertia about the COM as a symmetric 6-tuple (kg m^2).
    :param geometry_mass: the collision pieces' mass at some uniform density (kg).
    :param geometry_inertia: theirs about their COM, as a symmetric 6-tuple (kg m^2).
    """
    given = _gyration(mass, inertia)
    shape = _gyration(geometry_mass, geometry_inertia)
    if not (given > 0.0 and shape > 0.0):
        return None  # a geometry without volume (an open mesh) says nothing
    ratio = given / shape
    if 1.0 / FAR <= ratio <= FAR:
        return None
    factor = (1.0 / ratio) ** 2 if ratio < 1.0 else ratio ** 2
    if ratio < 1.0:
        slip = ('too small for its mass: a mass in grams reads 1000 times, an inertia for '
                'centimetres 1e4, for millimetres 1e6')
    else:
        slip = ('too large for its mass: a placeholder inertia (ixx="1"), or an inertia in '
                'g m^2 or for a mass in grams, reads 1000 times and more')
    return (f'link {link!r}: <inertial> radius of gyration {given:.3g} m is {ratio:.3g} times '
            f"its collision geometry's at uniform density ({shape:.3g} m): its inertia looks "
            f'{factor:.3g} times {slip}; the body turns as stated (docs/bodies.md)')


def _gyration(mass: float, inertia: Sequence[float]) -> float:
    """Return sqrt(trace(I) / (2 m)) (m), or 0 where it is not a positive finite number."""
    xx, _, _, yy, _, zz = inertia
    value = (xx + yy + zz) / (2.0 * mass) if mass > 0.0 else 0.0
    return math.sqrt(value) if math.isfinite(value) and value > 0.0 else 0.0
