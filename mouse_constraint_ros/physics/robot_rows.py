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

# Eigenvalues of K below this fraction of its largest are directions the anchor cannot move.
RANK_TOLERANCE = 1e-9


class MouseRows(NamedTuple):
    """
    The mouse constraint's three rows, prepared.

    :param jacobian: J (3 x nv), the anchor's world-frame point Jacobian.
    :param mobility: W = M^-1 J^T (nv x 3).
    :param effective_mass: K^-1 = (J W)^-1 (3 x 3).
    :param bias: (b / a) C (m/s), with a the mass scale.
    :param mass_scale: a (1 in rigid mode).
    :param bound: the largest impulse norm h F_max (N s).
    """

    jacobian: np.ndarray
    mobility: np.ndarray
    effective_mass: np.ndarray
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
    """What one substep's rows did: the joint impulses and the mouse's impulse."""

    joint_impulse: np.ndarray
    mouse_impulse: np.ndarray
    limit_impulse: np.ndarray


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
    # K is singular along the directions the joints cannot move the anchor (a planar arm's
    # normal, an arm at full stretch): the pseudo-inverse pulls along the others only.
    effective_mass = np.linalg.pinv(0.5 * (k + k.T), rcond=RANK_TOLERANCE, hermitian=True)
    return MouseRows(jacobian, mobility, effective_mass, (b / a) * error, a, bound)


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
               iterations: int) -> RowSolution:
    """
    Solve the rows by sequential impulses, changing ``v`` in place; return their impulses.

    The mouse alone is solved once, exactly (its three rows as a block); with joint rows, each
    sweep visits the mouse block, then each joint row.
    """
    nv = v.shape[0]
    joint_impulse = np.zeros(nv)
    limit_impulse = np.zeros(nv)
    mouse_total = np.zeros(3)
    accumulated = [0.0] * len(joints)
    sweeps = iterations if joints else 1
    for _ in range(sweeps):
        if mouse is not None:
            a = mouse.mass_scale
            change = -a * (mouse.effective_mass @ (mouse.jacobian @ v + mouse.bias)) \
                - (1.0 - a) * mouse_total
            total = mouse_total + change
            size = float(np.linalg.norm(total))
            if size > mouse.bound:
                total *= mouse.bound / size
            change = total - mouse_total
            mouse_total = total
            v += mouse.mobility @ change
        for number, row in enumerate(joints):
            change = row.effective_mass * (row.target - row.velocity(v))
            old = accumulated[number]
            new = min(max(old + change, row.lower), row.upper)
            if new != old:
                accumulated[number] = new
                v += row.mobility * (new - old)
        if mouse is None and sweeps > 1 and _settled(joints, accumulated, v):
            break
    if mouse is not None:
        # The stops have the last word: a sweep of the joint rows alone, so that the mouse's
        # pull is what gives way where the two disagree.
        for _ in range(sweeps):
            for number, row in enumerate(joints):
                change = row.effective_mass * (row.target - row.velocity(v))
                old = accumulated[number]
                new = min(max(old + change, row.lower), row.upper)
                if new != old:
                    accumulated[number] = new
                    v += row.mobility * (new - old)
            if _settled(joints, accumulated, v):
                break
    for number, row in enumerate(joints):
        if row.jacobian is not None:
            joint_impulse += row.jacobian * accumulated[number]
            continue
        joint_impulse[row.index] += accumulated[number]
        if row.limit:
            limit_impulse[row.index] += accumulated[number]
    if mouse is not None:
        joint_impulse += mouse.jacobian.T @ mouse_total
    return RowSolution(joint_impulse, mouse_total, limit_impulse)


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
