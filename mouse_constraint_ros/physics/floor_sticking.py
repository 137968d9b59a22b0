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
Contacts that stick: the body held by its pushing contacts at once, when the sweeps cannot.

A contact's friction rows, like its normal row, have the effective mass of turning the body
about its COM. For a body whose inertia is far below m r^2 (a heavy body with a small inertia)
that is a small fraction of the mass that sliding asks to stop, and sweeps then remove a slide
by that fraction per sweep: a 1e12 kg box of inertia 0.01 kg m^2, tipped onto its face, slides
on at 0.2 mm/s where it should stick (``normal_block`` gives the normal rows' side of it).

``stick`` solves the case in which every pushing contact sticks, together. With three or more
pushing contacts not on a line, their velocities (normal at its goal, tangential zero) fix the
body's six velocities y*: the least-squares solution of G y = goals, G the contacts' rows on
y = (v, w). The impulses that take the body there are the least-norm P with G^T P = M (y* - y),
M the mass matrix: a solve on the geometry alone, G^T's, and a product with M, which never
mixes the scales of m and I in one factorization. It is kept when every normal impulse is
>= 0, every tangential one within its cone |P_t| <= mu P_n and every other contact separates;
else the sweeps' answer stands.
"""

import math
from typing import List, Optional, Sequence, Tuple

import numpy as np

from .contact_row import GOAL, IMPULSES, LEVER, LEVER_X, LEVER_Y, LEVER_Z, NORMAL_IMPULSE

# How far (m/s) a contact's velocity may be from its goal; the rounding of the impulses'
# effects, some 1e-16 of them, is added (a heavy body's corners' pushes cancel in its turn).
ROUNDING = 64.0 * np.finfo(float).eps
# The rank below which the pushing contacts do not fix the body's velocities (three on a line):
# singular values of G (lengths in units of the farthest contact) under this share of the
# largest.
RANK_TOLERANCE = 1e-9


def stick(rows: Sequence[list], velocities: Tuple[float, ...], inverse_mass: float,
          world_inertia: Sequence[float], friction: float,
          tolerance: float) -> Optional[Tuple[float, ...]]:
    """
    Return the velocities with every pushing contact held, and set the rows' impulses; or None.

    :param rows: the contacts (``contact_row``) after the sweeps. On success their impulses
        are replaced (the others' set to zero).
    :param velocities: (vx, vy, vz, wx, wy, wz) with the rows' impulses applied.
    :param inverse_mass: 1 / m.
    :param world_inertia: the world-frame I_w as a symmetric 6-tuple (kg m^2).
    :param friction: mu.
    :param tolerance: how far (m/s) a contact's velocity may be from its goal.
    """
    active = [row for row in rows if row[NORMAL_IMPULSE] > 0.0]
    if len(active) < 3:
        return None
    # Lengths in units of the farthest contact, so that G's columns are alike in scale:
    # y' = (v, L w), G' = G diag(1, 1, 1, 1 / L, 1 / L, 1 / L), M' = diag(m, m, m, I_w / L^2).
    length = max(math.sqrt(sum(component * component for component in row[LEVER]))
                 for row in rows) or 1.0
    every = _rows(rows, length)
    geometry = _rows(active, length)
    if np.linalg.matrix_rank(geometry, tol=RANK_TOLERANCE * np.linalg.norm(geometry, 2)) < 6:
        return None
    mass = np.zeros((6, 6))
    mass[:3, :3] = np.eye(3) / inverse_mass
    i00, i01, i02, i11, i12, i22 = world_inertia
    mass[3:, 3:] = np.array([[i00, i01, i02], [i01, i11, i12], [i02, i12, i22]]) / (
        length * length)
    inverse = np.linalg.inv(mass[3:, 3:])
    vx, vy, vz, wx, wy, wz = velocities
    pushes = np.array([row[IMPULSES] for row in rows]).ravel()
    # y' without the rows' impulses: y' - M'^-1 G'^T P.
    wrench = every.T @ pushes
    free = np.array([vx, vy, vz, wx * length, wy * length, wz * length])
    free[:3] -= inverse_mass * wrench[:3]
    free[3:] -= inverse @ wrench[3:]
    goals = np.zeros(3 * len(active))
    goals[0::3] = [row[GOAL] for row in active]
    held = np.linalg.lstsq(geometry, goals, rcond=None)[0]
    impulses = np.linalg.lstsq(geometry.T, mass @ (held - free), rcond=None)[0]
    if not _admissible(impulses, geometry, every, held, rows, active, friction, tolerance):
        return None
    for row in rows:
        row[IMPULSES] = (0.0, 0.0, 0.0)
    for row, impulse in zip(active, impulses.reshape(-1, 3)):
        row[IMPULSES] = impulse.tolist()
    return (float(held[0]), float(held[1]), float(held[2]), float(held[3] / length),
            float(held[4] / length), float(held[5] / length))


def _rows(rows: Sequence[list], length: float) -> np.ndarray:
    """Return G': per contact its normal (z), then x and y rows on y' = (v, L w)."""
    g: List[List[float]] = []
    for row in rows:
        rx, ry, rz = row[LEVER_X] / length, row[LEVER_Y] / length, row[LEVER_Z] / length
        g.append([0.0, 0.0, 1.0, ry, -rx, 0.0])    # u_n = vz + wx ry - wy rx
        g.append([1.0, 0.0, 0.0, 0.0, rz, -ry])    # u_t = vx + wy rz - wz ry
        g.append([0.0, 1.0, 0.0, -rz, 0.0, rx])    # u_b = vy + wz rx - wx rz
    return np.array(g)


def _admissible(impulses: np.ndarray, geometry: np.ndarray, every: np.ndarray,
                held: np.ndarray, rows: Sequence[list], active: Sequence[list],
                friction: float, tolerance: float) -> bool:
    """Return whether the impulses push, keep to their cones and meet every goal."""
    pushes = impulses.reshape(-1, 3)
    if np.any(pushes[:, 0] < 0.0) or np.any(
            np.hypot(pushes[:, 1], pushes[:, 2]) > friction * pushes[:, 0]):
        return False
    slack = tolerance + ROUNDING * np.abs(geometry) @ np.abs(held)
    goals = np.array([(row[GOAL], 0.0, 0.0) for row in active]).ravel()
    if np.any(np.abs(geometry @ held - goals) > slack):
        return False
    # The other contacts separate: their normal velocities reach their goals or beyond.
    normal = every[0::3] @ held
    return all(normal[i] >= row[GOAL] - tolerance - ROUNDING * np.abs(every[3 * i]) @ np.abs(held)
               for i, row in enumerate(rows) if row[NORMAL_IMPULSE] <= 0.0)
