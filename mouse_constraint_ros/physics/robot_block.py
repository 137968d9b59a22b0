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
A robot's rows of one substep solved together, exactly, by trying active sets.

Sequential impulses (``robot_rows.solve_rows``) visit the rows one at a time; a robot at its
stops and held by the mouse couples them all through M^-1, and each sweep costs a Python call
per row. Here the rows are stacked, A (m x nv) with the mouse's three first, and solved as one
mixed complementarity problem in their impulses x:

    w = D x - r,   D = A M^-1 A^T (+ the mouse's compliance),   r = target - A v,

each row either free (w_i = 0, its impulse within its bounds) or held at a bound (x_i at lo_i
with w_i >= 0, or at hi_i with w_i <= 0). The free rows' equations are solved by least squares
(``numpy.linalg.lstsq``: the minimum-norm answer where D is singular, as the mouse's K is along
a direction the joints cannot move its anchor), a violated bound holds its row, a held row that
pulls the wrong way is freed, and the set is tried again, the most violated row first; the last
substep's set is tried first. The mouse's rows are Box2D's soft step at its fixed point,
J v + ((1 - a) / a) K P = -bias, so its block of D is K / a; its norm bound |P| <= h F_max,
when it binds, scales P onto the bound and holds it there. A set that does not settle within
``MAX_TRIES`` returns None, and sequential impulses take the substep.
"""

from typing import List, Optional, Tuple

import numpy as np

# Active sets tried before the solve gives up (each costs one least-squares solve).
MAX_TRIES = 12
# How far a row may miss its condition and still count as met (relative to the rhs scale).
TOLERANCE = 1e-9


def solve_block(jacobian: np.ndarray, mobility: np.ndarray, v: np.ndarray,
                target: np.ndarray, lower: np.ndarray, upper: np.ndarray, mouse_rows: int,
                mass_scale: float, bound: float, warm: np.ndarray
                ) -> Optional[Tuple[np.ndarray, np.ndarray]]:
    """
    Return the rows' impulses x and the set they settled on, or None if no set settled.

    :param jacobian: A (m x nv): the mouse's three rows first (if any), then the joint rows.
    :param mobility: W = M^-1 A^T (nv x m).
    :param v: the velocity before the rows (nv).
    :param target: each row's target velocity (the mouse's: -bias).
    :param lower: each row's least impulse (-inf for none).
    :param upper: each row's largest impulse (+inf for none).
    :param mouse_rows: 3 when the mouse's rows lead A, else 0.
    :param mass_scale: the mouse's a (its block of D is K / a).
    :param bound: the mouse impulse's largest norm h F_max.
    :param warm: the set to try first: -1 held at lo, 0 free, +1 held at hi, per row
        (``first_set``).
    """
    rows = jacobian.shape[0]
    delassus = jacobian @ mobility
    if mouse_rows:
        delassus[:3, :3] /= mass_scale
    rhs = target - jacobian @ v
    held = warm.copy()
    held[:mouse_rows] = 0
    impulse = np.zeros(rows)
    mouse_held = False
    mouse_impulse = np.zeros(3)
    scale = max(1.0, float(np.abs(rhs).max(initial=0.0)),
                float(np.abs(delassus).max(initial=0.0)))
    tolerance = TOLERANCE * scale
    for _ in range(MAX_TRIES):
        impulse = np.where(held < 0, lower, np.where(held > 0, upper, 0.0))
        if mouse_held:
            impulse[:3] = mouse_impulse
        free = held == 0
        if mouse_held:
            free[:3] = False
        count = int(free.sum())
        if count == 1:  # one equation: its own division, as least squares would give it
            row = int(np.flatnonzero(free)[0])
            impulse[row] = 0.0
            diagonal = delassus[row, row]
            impulse[row] = (rhs[row] - delassus[row] @ impulse) / diagonal \
                if diagonal > 0.0 else 0.0
        elif count:
            fixed = ~free
            rows_free = delassus[free]
            right = rhs[free] - rows_free[:, fixed] @ impulse[fixed]
            impulse[free] = np.linalg.lstsq(rows_free[:, free], right, rcond=1e-10)[0]
        if mouse_rows and not mouse_held:
            size = float(np.linalg.norm(impulse[:3]))
            if size > bound:
                mouse_impulse = impulse[:3] * (bound / size)
                mouse_held = True
                continue
        change = _most_violated(impulse, delassus @ impulse - rhs, held, lower, upper,
                                mouse_rows, tolerance)
        if change is None:
            return impulse, held
        row, side = change
        held[row] = side
    return None


def _most_violated(impulse: np.ndarray, residual: np.ndarray, held: np.ndarray,
                   lower: np.ndarray, upper: np.ndarray, mouse_rows: int,
                   tolerance: float) -> Optional[Tuple[int, int]]:
    """Return (row, its new hold) of the row that breaks its condition most, or None."""
    worst, change = tolerance, None
    for row in range(mouse_rows, impulse.shape[0]):
        state = held[row]
        if state == 0:
            below, above = lower[row] - impulse[row], impulse[row] - upper[row]
            if below > worst:
                worst, change = below, (row, -1)
            if above > worst:
                worst, change = above, (row, 1)
        elif state < 0 and -residual[row] > worst:
            worst, change = -residual[row], (row, 0)
        elif state > 0 and residual[row] > worst:
            worst, change = residual[row], (row, 0)
    return change


def first_set(keys: List[tuple], lower: np.ndarray, upper: np.ndarray, last: dict) -> np.ndarray:
    """
    Return the set to try first: the last substep's hold of a row it had, else a guess.

    A one-sided row (a stop, a brake) is guessed held at its zero bound (not pushing), any
    other free.

    :param keys: each row's key (``robot_rows.row_key``), None for the mouse's.
    :param last: the last substep's holds by key.
    """
    held = np.zeros(len(keys), dtype=int)
    for row, key in enumerate(keys):
        if key is not None and key in last:
            held[row] = last[key]
        elif lower[row] == 0.0 and np.isinf(upper[row]):
            held[row] = -1
        elif upper[row] == 0.0 and np.isinf(lower[row]):
            held[row] = 1
    return held
