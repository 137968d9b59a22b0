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
A robot's constraint rows in one substep: the mouse, the joint limits, friction, speed limits.

Every row acts on the joint-space velocity v through an impulse: a row with Jacobian J (k x nv)
and impulse lambda changes v by M^-1 J^T lambda, and the joint torques by J^T lambda / h. The
rows are solved by sequential impulses, in Box2D's phases:

1. prepare (``prepare_rows``): each row's J, W = M^-1 J^T and effective mass K^-1 = (J W)^-1,
   its bias and its impulse bounds, from the substep's q and M;
2. solve (``solve_rows``): ``iterations`` sweeps, each row's impulse change clamped so that its
   accumulated impulse stays within its bounds, applied to v as W d_lambda;
3. store: the accumulated impulses, as joint torques (``RowSolution.joint_impulse``) and the
   mouse's force.

The mouse rows are the note's constraint with the robot's Jacobian: C = x_anchor(q) - x_mouse,
J the anchor's point Jacobian (3 x nv) and K = J M^-1 J^T (the single body's eq. 1.10 is the
case of one free body). Their impulse is Box2D's soft step, P += -a K^-1 (J v + (b / a) C)
- (1 - a) P with |P| <= h F_max, which with the mouse alone is the single body's one-shot
P = -K^-1 (a J v + b C) (``mouse_joint``). A position limit is a one-sided row J = e_i whose
accumulated impulse pushes only away from the stop: ahead of the stop it lets the joint arrive
exactly at it in the substep (a speculative contact), past it by more than the slop it
corrects ``limit_baumgarte`` of the rest per substep. Joint friction is a row J = e_i with
|lambda| <= h f and target velocity zero; the speed limit is a row that holds |v_i| <= the
joint's ``velocity`` with at most its ``effort`` (a brake, as ODE's joint motor with FMax). A
mimic joint is a two-sided row J = e_i - k e_j holding q_i = k q_j + offset, its error
corrected as a limit's is.
"""

import math
from typing import List, NamedTuple, Optional

import numpy as np

from .robot_block import first_set, solve_block

# Eigenvalues of K below this fraction of its largest are directions the anchor cannot move.
RANK_TOLERANCE = 1e-9


class MouseRows(NamedTuple):
    """
    The mouse constraint's three rows, prepared.

    :param jacobian: J (3 x nv), the anchor's world-frame point Jacobian.
    :param mobility: W = M^-1 J^T (nv x 3).
    :param stiffness: K = J W (3 x 3), the inverse effective mass; sequential impulses take its
        pseudo-inverse (``effective_mass``).
    :param bias: (b / a) C (m/s), with a the mass scale.
    :param mass_scale: a (1 in rigid mode).
    :param bound: the largest impulse norm h F_max (N s).
    """

    jacobian: np.ndarray
    mobility: np.ndarray
    stiffness: np.ndarray
    bias: np.ndarray
    mass_scale: float
    bound: float


class JointRow(NamedTuple):
    """
    One joint's row, J = e_index: a limit's, friction's or the speed limit's.

    :param index: the joint's coordinate in v.
    :param mobility: W = M^-1 e_index (nv).
    :param effective_mass: 1 / (M^-1)_ii.
    :param target: the joint velocity the row aims at (rad/s or m/s).
    :param lower: the least accumulated impulse (N m s or N s).
    :param upper: the largest.
    :param limit: whether it is a position limit's row (its torque is the limit's).
    :param jacobian: a row on more than one joint (a mimic joint's, J = e_i - k e_j): its J (nv);
        None for J = e_index.
    """

    index: int
    mobility: np.ndarray
    effective_mass: float
    target: float
    lower: float
    upper: float
    limit: bool = False
    jacobian: Optional[np.ndarray] = None

    def velocity(self, v: np.ndarray) -> float:
        """Return the row's velocity J v."""
        return float(v[self.index]) if self.jacobian is None else float(self.jacobian @ v)


class RowSolution(NamedTuple):
    """What one substep's rows did: the joint impulses, the mouse's, and the set they held."""

    joint_impulse: np.ndarray
    mouse_impulse: np.ndarray
    limit_impulse: np.ndarray
    held: dict = {}


def row_key(row: JointRow) -> tuple:
    """Return what names a joint row from one substep to the next: its joint, kind and side."""
    return (row.index, row.limit, row.jacobian is not None, row.lower == 0.0, row.upper == 0.0)


def mouse_rows(jacobian: np.ndarray, inverse_mass: np.ndarray, error: np.ndarray,
               gains: tuple, bound: float) -> MouseRows:
    """
    Prepare the mouse's rows.

    :param jacobian: J (3 x nv).
    :param inverse_mass: M^-1 (nv x nv).
    :param error: C = anchor - target (m).
    :param gains: (a, b) of ``MouseConstraint.gains``.
    :param bound: h F_max (N s).
    """
    mobility = inverse_mass @ jacobian.T
    k = jacobian @ mobility
    a, b = gains
    return MouseRows(jacobian, mobility, 0.5 * (k + k.T), (b / a) * error, a, bound)


def effective_mass(mouse: MouseRows) -> np.ndarray:
    """
    Return the mouse's effective mass K^-1.

    K is singular along the directions the joints cannot move the anchor (a planar arm's
    normal, an arm at full stretch): the pseudo-inverse pulls along the others only.
    """
    return np.linalg.pinv(mouse.stiffness, rcond=RANK_TOLERANCE, hermitian=True)


def limit_row(index: int, inverse_mass: np.ndarray, distance: float, h: float, slop: float,
              baumgarte: float, upper_side: bool) -> JointRow:
    """
    Prepare a position limit's row.

    :param distance: how far the joint is inside its limit (negative: past it).
    :param upper_side: True for the upper limit (the impulse pushes down), False for the lower.
    """
    if distance >= 0.0:
        speed = distance / h  # may arrive at the stop, not beyond
    else:
        speed = baumgarte * min(distance + slop, 0.0) / h
    mobility = inverse_mass[:, index].copy()
    mass = 1.0 / mobility[index]
    if upper_side:
        return JointRow(index, mobility, mass, speed, -math.inf, 0.0, True)
    return JointRow(index, mobility, mass, -speed, 0.0, math.inf, True)


def bounded_row(index: int, inverse_mass: np.ndarray, target: float,
                bound: float) -> JointRow:
    """Prepare a row that drives joint ``index`` to ``target`` velocity with |impulse| <= bound."""
    mobility = inverse_mass[:, index].copy()
    return JointRow(index, mobility, 1.0 / mobility[index], target, -bound, bound)


def mimic_row(follower: int, leader: int, multiplier: float, error: float,
              inverse_mass: np.ndarray, h: float, baumgarte: float) -> JointRow:
    """
    Prepare a mimic joint's row: q_follower = multiplier q_leader + offset, held both ways.

    :param error: C = q_follower - (multiplier q_leader + offset) (rad or m).
    """
    jacobian = np.zeros(inverse_mass.shape[0])
    jacobian[follower] += 1.0
    jacobian[leader] -= multiplier
    mobility = inverse_mass @ jacobian
    return JointRow(follower, mobility, 1.0 / float(jacobian @ mobility),
                    -baumgarte * error / h, -math.inf, math.inf, False, jacobian)


def solve_rows(v: np.ndarray, mouse: Optional[MouseRows], joints: List[JointRow],
               iterations: int, last_held: Optional[dict] = None) -> RowSolution:
    """
    Solve the rows, changing ``v`` in place; return their impulses.

    The rows are solved together, exactly (``robot_block``), the last substep's held set tried
    first; if no set settles, by sequential impulses: ``iterations`` sweeps, each visiting the
    mouse's block, then each joint row. Either way a last pass of the joint rows alone gives the
    stops the last word where the mouse pulls against them.
    """
    nv = v.shape[0]
    accumulated = [0.0] * len(joints)
    mouse_total = np.zeros(3)
    held: dict = {}
    # One joint row alone: a sweep solves it exactly, with no system to set up.
    block = None
    if mouse is not None or len(joints) > 1:
        block = _block(v, mouse, joints, last_held or {})
    if block is not None:
        impulse, held = block
        mouse_rows = 3 if mouse is not None else 0
        if mouse is not None:
            mouse_total = impulse[:3]
            v += mouse.mobility @ mouse_total
        for number, row in enumerate(joints):
            accumulated[number] = float(impulse[mouse_rows + number])
            v += row.mobility * accumulated[number]
    else:
        inverse = None if mouse is None else effective_mass(mouse)
        for _ in range(iterations if joints else 1):
            if mouse is not None:
                mouse_total = _mouse_sweep(v, mouse, inverse, mouse_total)
            _joint_sweep(v, joints, accumulated)
    if mouse is not None and joints:
        for _ in range(iterations):
            if _settled(joints, accumulated, v):
                break
            _joint_sweep(v, joints, accumulated)
    joint_impulse = np.zeros(nv)
    limit_impulse = np.zeros(nv)
    for number, row in enumerate(joints):
        if row.jacobian is not None:
            joint_impulse += row.jacobian * accumulated[number]
            continue
        joint_impulse[row.index] += accumulated[number]
        if row.limit:
            limit_impulse[row.index] += accumulated[number]
    if mouse is not None:
        joint_impulse += mouse.jacobian.T @ mouse_total
    return RowSolution(joint_impulse, mouse_total, limit_impulse, held)


def _block(v: np.ndarray, mouse: Optional[MouseRows], joints: List[JointRow],
           last_held: dict):
    """Return the rows' impulses solved together and the held set by key, or None."""
    if mouse is None and not joints:
        return None
    jacobians, mobilities, targets, lowers, uppers, keys = [], [], [], [], [], []
    if mouse is not None:
        jacobians.append(mouse.jacobian)
        mobilities.append(mouse.mobility)
        targets.extend(-mouse.bias)
        lowers.extend([-math.inf] * 3)
        uppers.extend([math.inf] * 3)
        keys.extend([None] * 3)
    nv = v.shape[0]
    for row in joints:
        if row.jacobian is None:
            jacobian = np.zeros((1, nv))
            jacobian[0, row.index] = 1.0
        else:
            jacobian = row.jacobian[np.newaxis, :]
        jacobians.append(jacobian)
        mobilities.append(row.mobility[:, np.newaxis])
        targets.append(row.target)
        lowers.append(row.lower)
        uppers.append(row.upper)
        keys.append(row_key(row))
    lower, upper = np.array(lowers), np.array(uppers)
    mouse_rows = 3 if mouse is not None else 0
    solved = solve_block(
        np.vstack(jacobians), np.hstack(mobilities), v, np.array(targets), lower, upper,
        mouse_rows,
        mouse.mass_scale if mouse is not None else 1.0,
        mouse.bound if mouse is not None else math.inf, first_set(keys, lower, upper, last_held))
    if solved is None:
        return None
    impulse, held = solved
    return impulse, {key: int(state) for key, state in zip(keys, held) if key and state}


def _mouse_sweep(v: np.ndarray, mouse: MouseRows, inverse: np.ndarray,
                 total: np.ndarray) -> np.ndarray:
    """Visit the mouse's block once (``inverse``: its K^-1); return its accumulated impulse."""
    a = mouse.mass_scale
    change = -a * (inverse @ (mouse.jacobian @ v + mouse.bias)) - (1.0 - a) * total
    new = total + change
    size = float(np.linalg.norm(new))
    if size > mouse.bound:
        new *= mouse.bound / size
    v += mouse.mobility @ (new - total)
    return new


def _joint_sweep(v: np.ndarray, joints: List[JointRow], accumulated: List[float]) -> None:
    """Visit each joint row once, clamping its accumulated impulse to its bounds."""
    for number, row in enumerate(joints):
        change = row.effective_mass * (row.target - row.velocity(v))
        old = accumulated[number]
        new = min(max(old + change, row.lower), row.upper)
        if new != old:
            accumulated[number] = new
            v += row.mobility * (new - old)


def _settled(joints: List[JointRow], accumulated: List[float], v: np.ndarray) -> bool:
    """
    Return whether no joint row would change its impulse.

    One sweep is not always the answer: rows on coupled joints move each other's velocities.
    """
    for number, row in enumerate(joints):
        change = row.effective_mass * (row.target - row.velocity(v))
        new = min(max(accumulated[number] + change, row.lower), row.upper)
        if abs(new - accumulated[number]) > 1e-12 * max(1.0, abs(accumulated[number])):
            return False
    return True
