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
The normal rows of a few floor contacts solved together, exactly: a block solve.

Sequential impulses converge at a rate set by how the contacts' normal rows couple. Far apart
(a box's corners of a consistent inertia) they hardly do, and a few sweeps settle a resting
box. They couple strongly in two cases, and sweeps then leave the body sinking and creeping:

- a curved hull resting on a facet of a few millimetres, whose vertices' rows differ by little:
  one sweep shifts the load from a vertex to its neighbour and the next shifts it back;
- a body whose inertia is far from its contact geometry's, m r^2 / I far from 1 (a heavy body
  with a small inertia: a URDF written in grams, 500 kg with 0.00083 kg m^2). Each row's
  effective mass is then that of turning the body about its COM, I / r^2, far below the m its
  weight asks the contacts together to carry: a sweep mostly rocks the body from corner to
  corner and lifts it by a fraction I / (m r^2) of what it needs, so that ten sweeps leave such
  a body sinking and drifting, and let a heavy enough one fall through (the reverse,
  I / (m r^2) large, rocks the body slowly).
  Box2D's contact solver meets the first with two points and solves them as a block.

With accumulated normal impulses P >= 0, the rows ask for the linear complementarity problem

    P >= 0,  u >= 0,  P_i u_i = 0,

for the normal velocities less their goals u = b + K P. A row's velocity is G_i y, for
y = (v_z, w_x, w_y) and G_i = (1, r_y, -r_x) (the contact at r from the COM, normal z), and
impulses P change y by W G^T P, W = diag(1 / m, the x-y block of I_w^-1): K = G W G^T. It is
solved here by its active sets: for a set A of contacts that push, K_AA P_A = -b_A, kept when
every P_A >= 0 and every other contact separates (u_i >= 0). A few contacts have few sets, and
the last substep's set comes first, so a resting body solves one small system.

K mixes the scales of 1 / m and r^2 / I: its condition number is about m r^2 / I, and four
contacts on a plane leave it singular (their velocities span three motions: v_z, w_x, w_y).
So K is never formed or factored. The set's least-norm solution (the load shared among four
corners, not put on three) is taken through the geometry's SVD, G_A = U S V^T, which separates
the contacts' rank from the body's scales, and the square root of W, K_AA =
U S (V^T W V) S U^T with V^T W V = R^T R from the QR factors of W^(1/2) V: rounding then
perturbs the smallest of K's eigenvalues by some 1e-16 sqrt(m r^2 / I) of itself, where a
Cholesky factor of K perturbs it by 1e-16 m r^2 / I (and a regularization by its own size).
"""

from itertools import combinations
import math
from typing import List, Optional, Sequence, Tuple

import numpy as np

from .contact_row import GOAL, LEVER_X, LEVER_Y, NORMAL_IMPULSE

# The most contacts solved as a block: their active sets, 2^n of them, are tried in turn.
MOST_CONTACTS = 4
# Contacts' rows G_i (lengths in units of the farthest contact) whose singular value is below
# this share of the largest are taken as dependent: three on a line, or a contact twice.
RANK_TOLERANCE = 1e-9
# A contact's velocity is taken as on its goal within the tolerance asked for and this share of
# the impulses' effects on it, which rounding leaves (64 units in the last place).
ROUNDING = 64.0 * np.finfo(float).eps


def impulses(rows: Sequence[list], vz: float, wx: float, wy: float,
             weights: Tuple[float, float, float, float], tolerance: float,
             memo: list) -> Optional[List[float]]:
    """
    Return the normal impulses that solve the rows' problem (N s); None if none do.

    When the rows' impulses already solve it within ``tolerance`` (a body at rest, warm
    started), they are returned as they are, and nothing is factored.

    :param rows: the contacts (``contact_row``): their levers, goals and normal impulses.
    :param vz: the body's velocity along z (m/s), the rows' impulses applied.
    :param wx: its angular velocity about x (rad/s).
    :param wy: about y.
    :param weights: W: 1 / m and the world-frame I_w^-1's xx, xy and yy (module docstring).
    :param tolerance: how far (m/s) a contact's velocity may be from its goal.
    :param memo: an empty list, kept over a substep's sweeps: the geometry is kept in it.
    """
    residual = [vz + wx * row[LEVER_Y] - wy * row[LEVER_X] - row[GOAL] for row in rows]
    current = [row[NORMAL_IMPULSE] for row in rows]
    if all(-tolerance <= u and (u <= tolerance or p == 0.0)
           for u, p in zip(residual, current)):
        return current
    im, i00, i01, i11 = weights
    if not memo:
        # Lengths in units of the farthest contact, so that G's columns are alike in scale:
        # y' = (v_z, L w_x, L w_y), G' = (1, r_y / L, -r_x / L), W' = diag(1 / m, L^2 I^-1).
        length = max(math.hypot(row[LEVER_X], row[LEVER_Y]) for row in rows) or 1.0
        geometry = np.array([[1.0, row[LEVER_Y] / length, -row[LEVER_X] / length] for row in rows])
        scale = length * length
        weight = np.array([[im, 0.0, 0.0], [0.0, i00 * scale, i01 * scale],
                           [0.0, i01 * scale, i11 * scale]])
        root = np.zeros((3, 3))
        root[0, 0] = math.sqrt(im)
        root[1:, 1:] = np.linalg.cholesky(weight[1:, 1:])
        memo.extend((geometry, weight, root, length))
    geometry, weight, root, length = memo
    goals = np.array([row[GOAL] for row in rows])
    # y' without the rows' impulses, and the velocities the rows would have without them.
    free = np.array([vz, wx * length, wy * length]) - weight @ (geometry.T @ np.array(current))
    b = geometry @ free - goals
    tried = set()
    for active in _sets(len(rows), tuple(i for i, p in enumerate(current) if p > 0.0)):
        if active in tried:
            continue
        tried.add(active)
        solution = np.zeros(len(rows))
        if active:
            pushes = _least_norm(geometry[list(active)], root, -b[list(active)])
            if pushes is None or pushes.min() < 0.0:
                continue
            solution[list(active)] = pushes
        u = geometry @ (free + weight @ (geometry.T @ solution)) - goals
        # The velocities' own rounding: some 1e-16 of the impulses' effects, whose sum is the
        # body's small change (a heavy body's corners' pushes cancel in its turn).
        slack = tolerance + ROUNDING * (np.abs(geometry) @ (
            np.abs(weight) @ (np.abs(geometry.T) @ np.abs(solution))))
        if all(-slack[i] <= u[i] and (u[i] <= slack[i] or i not in active)
               for i in range(len(rows))):
            return [float(p) for p in solution]
    return None


def _least_norm(geometry: np.ndarray, root: np.ndarray, c: np.ndarray) -> Optional[np.ndarray]:
    """
    Return the least-norm P with G W G^T P = c, for W = root root^T; None if there is none.

    :param geometry: G, a row per contact.
    :param root: W's lower Cholesky factor.
    """
    u, s, vt = np.linalg.svd(geometry, full_matrices=False)
    rank = int(np.count_nonzero(s > RANK_TOLERANCE * s[0]))
    u, s, v = u[:, :rank], s[:rank], vt[:rank].T
    # G W G^T = U S (V^T W V) S U^T and V^T W V = R^T R, R from the QR factors of root^T V.
    r = np.linalg.qr(root.T @ v, mode='r')
    if not np.all(np.abs(np.diag(r)) > 0.0):
        return None
    t = np.linalg.solve(r, np.linalg.solve(r.T, (u.T @ c) / s))
    return u @ (t / s)


def _sets(n: int, first: tuple):
    """Yield the active sets to try: ``first``, then every set, the largest first."""
    yield first
    for size in range(n, -1, -1):
        yield from combinations(range(n), size)
