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
(a box's corners) they hardly do, and a few sweeps settle a resting box. A curved hull rests
on a facet of a few millimetres, whose vertices' rows differ by little: one sweep shifts the
load from a vertex to its neighbour and the next shifts it back, and ten sweeps leave the body
trembling (Box2D's contact solver meets the same with two points and solves them as a block).

With accumulated normal impulses P >= 0 and the normal velocities u = b + K P (b: with no
normal impulse, less the goal; K_ij = 1 / m + (r_i x z) . I_w^-1 (r_j x z)), the rows ask for
the linear complementarity problem

    P >= 0,  u >= 0,  P_i u_i = 0,

solved here by its active sets: for a set A of contacts that push, K_AA P_A = -b_A, kept when
every P_A >= 0 and every other contact separates (u_i >= 0). A few contacts have few sets,
and the last substep's set comes first, so a resting body solves one small system. Four
contacts on a plane leave K singular (the normal velocities span three motions: vz, wx, wy):
``REGULARIZATION`` of K's mean diagonal is added to it, which picks the smallest impulses
among the solutions (the load shared, not put on three corners) and moves each contact's
velocity by that fraction of its impulse's effect.
"""

from itertools import combinations
import math
from typing import List, Optional, Sequence

# The most contacts solved as a block: their active sets, 2^n of them, are tried in turn.
MOST_CONTACTS = 4
# K + REGULARIZATION * mean(diag K) * I: solvable with four coplanar contacts; the bias it
# leaves on a contact's velocity is this fraction of what its impulse does.
REGULARIZATION = 1e-10


def impulses(rows: Sequence[list], vz: float, wx: float, wy: float, im: float,
             tolerance: float, memo: list) -> Optional[List[float]]:
    """
    Return the normal impulses that solve the rows' problem (N s); None if none do.

    When the rows' impulses already solve it within ``tolerance`` (a body at rest, warm
    started), they are returned as they are, and K is not made.

    :param rows: ``floor_contact.Rows``: r at 1 and 2, I_w^-1 (r x z) at 5 and 6, the goal at
        18, the accumulated normal impulse at 19.
    :param vz: the body's velocity along z (m/s), the rows' impulses applied.
    :param wx: its angular velocity about x (rad/s).
    :param wy: about y.
    :param im: 1 / m.
    :param tolerance: how far (m/s) a contact's velocity may be from its goal.
    :param memo: an empty list, kept over a substep's sweeps: K is kept in it.
    """
    residual = [vz + wx * row[2] - wy * row[1] - row[18] for row in rows]
    current = [row[19] for row in rows]
    if all(-tolerance <= u and (u <= tolerance or p == 0.0)
           for u, p in zip(residual, current)):
        return current
    if not memo:
        k = [[im + a[2] * b[5] - a[1] * b[6] for b in rows] for a in rows]
        memo.extend((k, REGULARIZATION * sum(k[i][i] for i in range(len(rows))) / len(rows)))
    k, extra = memo
    n = len(rows)
    b = [u - sum(kij * p for kij, p in zip(ki, current)) for u, ki in zip(residual, k)]
    tried = set()
    for active in _sets(n, tuple(i for i in range(n) if current[i] > 0.0)):
        if active in tried:
            continue
        tried.add(active)
        x = _solve_spd([[k[i][j] + extra if i == j else k[i][j] for j in active]
                        for i in active], [-b[i] for i in active])
        if x is None or min(x, default=0.0) < 0.0:
            continue
        solution = [0.0] * n
        for i, value in zip(active, x):
            solution[i] = value
        if all(b[i] + sum(k[i][j] * solution[j] for j in active) >= -tolerance
               for i in range(n) if i not in active):
            return solution
    return None


def _sets(n: int, first: tuple):
    """Yield the active sets to try: ``first``, then every set, the largest first."""
    yield first
    for size in range(n, -1, -1):
        yield from combinations(range(n), size)


def _solve_spd(a: List[List[float]], y: List[float]) -> Optional[List[float]]:
    """Return x of a x = y for a symmetric positive definite a (Cholesky); None if it is not."""
    n = len(y)
    low = [[0.0] * n for _ in range(n)]
    for i in range(n):
        li = low[i]
        for j in range(i + 1):
            lj = low[j]
            s = a[i][j]
            for m in range(j):
                s -= li[m] * lj[m]
            if i == j:
                if not s > 0.0:
                    return None
                li[i] = math.sqrt(s)
            else:
                li[j] = s / lj[j]
    z = [0.0] * n
    for i in range(n):
        s = y[i]
        for m in range(i):
            s -= low[i][m] * z[m]
        z[i] = s / low[i][i]
    for i in range(n - 1, -1, -1):
        s = z[i]
        for m in range(i + 1, n):
            s -= low[m][i] * z[m]
        z[i] = s / low[i][i]
    return z
