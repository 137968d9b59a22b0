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

Sequential impulses (``robot_sweeps``) visit the rows one at a time; a robot at its stops and
held by the mouse couples them all through M^-1, and each sweep costs a Python call per row.
Here the rows are stacked, A (m x nv) with the mouse's three first, and solved as one mixed
complementarity problem in their impulses x:

    w = D x - r,   D = A M^-1 A^T (+ the mouse's compliance),   r = target - A v,

each row either free (w_i = 0, its impulse within its bounds) or held at a bound (x_i at lo_i
with w_i >= 0, or at hi_i with w_i <= 0). The free rows' equations are solved by LAPACK through
SciPy: Cholesky (``dposv``) where the free block of D is well conditioned, else least squares
(``dgelsd``, the minimum-norm answer where D is singular: the mouse's K along a direction the
joints cannot move its anchor, or two rows on one joint). A violated bound holds its row, a held
row that pulls the wrong way is freed, and the set is tried again, the most violated row first;
the last substep's set is tried first. The mouse's rows are Box2D's soft step at its fixed
point, J v + ((1 - a) / a) K P = -bias, so its block of D is K / a; its norm bound |P| <= h
F_max, when it binds, scales P onto the bound and holds it there. A set that does not settle
within ``MAX_TRIES`` returns None, and sequential impulses take the substep.
"""

import math
from typing import Dict, List, Optional, Tuple

import numpy as np
from scipy.linalg import lapack

# Active sets tried before the solve gives up (each costs one linear solve).
MAX_TRIES = 12
# How far a row may miss its condition and still count as met (relative to the rhs scale).
TOLERANCE = 1e-9
# Singular values of a free block below this fraction of its largest are taken as zero.
RANK_TOLERANCE = 1e-10
# A Cholesky pivot below this fraction of its row's diagonal: the row nearly repeats others
# (least squares, not Cholesky, answers).
PIVOT_TOLERANCE = 1e-9


def solve_block(jacobian: np.ndarray, mobility: np.ndarray, v: np.ndarray,
                target: np.ndarray, lower: List[float], upper: List[float], mouse_rows: int,
                mass_scale: float, bound: float, warm: List[int]
                ) -> Optional[Tuple[np.ndarray, List[int]]]:
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
        (``robot_rows.HeldSets``).
    """
    delassus = jacobian.dot(mobility)
    if mouse_rows and mass_scale != 1.0:
        delassus[:mouse_rows, :mouse_rows] /= mass_scale
    rhs = target - jacobian.dot(v)
    # The set's bookkeeping is in Python numbers: a substep has a handful of rows, and a
    # NumPy call on one costs more than a Python loop over them.
    count, diagonal = len(lower), delassus.diagonal().tolist()
    held = list(warm)
    held[:mouse_rows] = [0] * mouse_rows
    tolerance = TOLERANCE * max(1.0, max(map(abs, rhs.tolist())), max(diagonal))
    # Each held row's impulse at its bound; the free rows' are solved for (with no row held,
    # the first solve gives them all).
    if any(held):
        impulse = np.array([lower[row] if hold < 0 else upper[row] if hold > 0 else 0.0
                            for row, hold in enumerate(held)])
    first_free = 0  # the mouse's rows, once on their norm bound, are no longer solved for
    for _ in range(MAX_TRIES):
        free = [row for row in range(first_free, count) if held[row] == 0]
        if len(free) == count:  # no row held: the whole system
            impulse = free_impulses(delassus, rhs, diagonal)
        elif free:
            rows_free = delassus.take(free, 0)
            right = rhs.take(free)
            # The held rows' impulses push the free rows too, unless all are zero (a stop held
            # at its bound pushes nothing).
            if first_free or any(held[row] and (lower[row] if held[row] < 0 else upper[row])
                                 for row in range(count)):
                impulse.put(free, 0.0)
                right = right - rows_free.dot(impulse)
            impulse.put(free, free_impulses(rows_free.take(free, 1), right,
                                            [diagonal[row] for row in free]))
        if mouse_rows and not first_free:
            size = math.hypot(*impulse[:mouse_rows].tolist())
            if size > bound:
                impulse[:mouse_rows] *= bound / size
                first_free = mouse_rows
                continue
        # A free row's residual is zero by its solve: with no row held, only the bounds count.
        residual = None if len(free) == count else (delassus.dot(impulse) - rhs).tolist()
        change = most_violated(impulse.tolist(), residual, held, lower, upper, mouse_rows,
                               tolerance)
        if change is None:
            return impulse, held
        row, side = change
        held[row] = side
        if side:
            impulse[row] = lower[row] if side < 0 else upper[row]
    return None


_WORKSPACE: Dict[int, Tuple[int, int]] = {}


def free_impulses(matrix: np.ndarray, right: np.ndarray,
                  diagonal: Optional[List[float]] = None) -> np.ndarray:
    """
    Return x with matrix x = right: the free rows' impulses, a new array.

    ``matrix`` is symmetric positive semi-definite (a block of A M^-1 A^T, the mouse's scaled).
    Cholesky answers where no row nearly repeats the others; least squares, its minimum-norm
    answer, where one does.

    :param diagonal: ``matrix``'s diagonal as Python numbers, where the caller has it.
    """
    size = right.shape[0]
    if size == 1:
        pivot = matrix[0, 0]
        return right / pivot if pivot > 0.0 else np.zeros(1)
    factor, solution, info = lapack.dposv(matrix, right)
    if diagonal is None:
        diagonal = matrix.diagonal().tolist()
    if info == 0 and all(pivot * pivot >= PIVOT_TOLERANCE * entry for pivot, entry
                         in zip(factor.diagonal().tolist(), diagonal)):
        return solution
    if size not in _WORKSPACE:
        work, iwork, _ = lapack.dgelsd_lwork(size, size, 1, RANK_TOLERANCE)
        _WORKSPACE[size] = (int(work), int(iwork))
    work, iwork = _WORKSPACE[size]
    solution, _, _, info = lapack.dgelsd(matrix, right, work, iwork, RANK_TOLERANCE)
    if info != 0:  # the SVD did not converge: NumPy's least squares says why, or answers
        return np.linalg.lstsq(matrix, right, rcond=RANK_TOLERANCE)[0]
    return solution


def most_violated(impulse: List[float], residual: Optional[List[float]], held: List[int],
                  lower: List[float], upper: List[float], mouse_rows: int,
                  tolerance: float) -> Optional[Tuple[int, int]]:
    """
    Return (row, its new hold) of the joint row that breaks its condition most, or None.

    A free row breaks it by leaving its bounds (it is then held at the bound it passed); a held
    row by pulling the wrong way, its residual w = D x - r of the wrong sign (w < 0 at its least
    impulse, w > 0 at its largest: held * w > 0; it is then freed). Of rows that break it
    equally, the first. ``residual`` is read for held rows only (None: no row is held).
    """
    worst, change = tolerance, None
    for row in range(mouse_rows, len(held)):
        hold = held[row]
        if hold:
            if hold * residual[row] > worst:
                worst, change = hold * residual[row], (row, 0)
            continue
        below, above = lower[row] - impulse[row], impulse[row] - upper[row]
        if below > worst and below >= above:
            worst, change = below, (row, -1)
        elif above > worst:
            worst, change = above, (row, 1)
    return change
