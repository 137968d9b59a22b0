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
A robot's rows by sequential impulses: the answer when no active set settles.

``robot_block`` solves the rows together and almost always settles; where it does not (within
its tries), Box2D's solve phase takes the substep: sweeps that visit the mouse's three rows as
one block (its impulse from the pseudo-inverse of K, clamped to the force bound by its norm),
then each joint row, each row's accumulated impulse clamped to its bounds and the change
applied to v at once. A last pass over the joint rows alone gives the stops the last word where
the mouse pulls against them.
"""

import numpy as np

from .robot_row_arrays import Rows

# Eigenvalues of K below this fraction of its largest are directions the anchor cannot move.
RANK_TOLERANCE = 1e-9
# A joint row's impulse change below this fraction of its impulse: the row is settled.
SETTLED = 1e-12


def sweep_rows(v: np.ndarray, rows: Rows, mobility: np.ndarray,
               iterations: int) -> np.ndarray:
    """
    Solve ``rows`` by ``iterations`` sweeps, changing ``v``; return their impulses x.

    :param mobility: W = M^-1 A^T (nv x m).
    """
    count, lead = rows.count, rows.mouse_rows
    jacobian = rows.jacobian
    impulse = np.zeros(count)
    # Each row's effective mass 1 / (A_r M^-1 A_r^T).
    diagonal = np.einsum('ij,ji->i', jacobian, mobility)
    inverse = None
    if lead:
        stiffness = jacobian[:lead] @ mobility[:, :lead]
        inverse = np.linalg.pinv(0.5 * (stiffness + stiffness.T), rcond=RANK_TOLERANCE,
                                 hermitian=True)
    for _ in range(iterations if count > lead else 1):
        if lead:
            _mouse_sweep(v, rows, mobility, inverse, impulse)
        _joint_sweep(v, rows, mobility, diagonal, impulse)
    if lead and count > lead:
        for _ in range(iterations):
            if not _joint_sweep(v, rows, mobility, diagonal, impulse):
                break
    return impulse


def _mouse_sweep(v: np.ndarray, rows: Rows, mobility: np.ndarray, inverse: np.ndarray,
                 impulse: np.ndarray) -> None:
    """Visit the mouse's block once (``inverse``: its K^-1), with Box2D's soft step."""
    a = rows.mass_scale
    total = impulse[:3]
    velocity = rows.jacobian[:3] @ v - rows.target[:3]
    new = total - a * (inverse @ velocity) - (1.0 - a) * total
    size = float(np.linalg.norm(new))
    if size > rows.bound:
        new *= rows.bound / size
    v += mobility[:, :3] @ (new - total)
    impulse[:3] = new


def _joint_sweep(v: np.ndarray, rows: Rows, mobility: np.ndarray, diagonal: np.ndarray,
                 impulse: np.ndarray) -> bool:
    """Visit each joint row once, clamping its impulse to its bounds; return if any changed."""
    changed = False
    for row in range(rows.mouse_rows, rows.count):
        if diagonal[row] <= 0.0:
            continue
        old = impulse[row]
        change = (rows.target[row] - float(rows.jacobian[row] @ v)) / diagonal[row]
        new = min(max(old + change, rows.lower[row]), rows.upper[row])
        if abs(new - old) > SETTLED * max(1.0, abs(old)):
            changed = True
        if new != old:
            impulse[row] = new
            v += mobility[:, row] * (new - old)
    return changed
