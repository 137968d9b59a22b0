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

Every row acts on the joint-space velocity v through an impulse: rows with Jacobian A (m x nv)
and impulses x change v by M^-1 A^T x, and the joint torques by A^T x / h. The phases, named as
Box2D's solvers name theirs:

1. prepare (``prepare_rows``): the substep's rows as arrays (``Rows``): A, each row's target
   velocity and impulse bounds and its number in the table (``RowTable``: what kind of row it
   is and on which joint), from the substep's q and v and the joints' constants
   (``JointArrays``, once per model);
2. solve (``solve_rows``): all rows together, exactly (``robot_block``), the last substep's
   held set tried first (``HeldSets``); if no set settles, sequential impulses
   (``robot_sweeps``);
3. store (``RowSolution``): the impulses as joint torques and the mouse's force.

The mouse rows are the note's constraint with the robot's Jacobian: C = x_anchor(q) - x_mouse,
J the anchor's point Jacobian (3 x nv) and K = J M^-1 J^T (the single body's eq. 1.10 is the
case of one free body). Their impulse is Box2D's soft step, P += -a K^-1 (J v + (b / a) C)
- (1 - a) P with |P| <= h F_max, which with the mouse alone is the single body's one-shot
P = -K^-1 (a J v + b C) (``mouse_joint``). A position limit is a one-sided row J = e_i whose
impulse pushes only away from the stop: ahead of the stop it lets the joint arrive exactly at
it in the substep (a speculative contact), past it by more than the slop it corrects
``limit_baumgarte`` of the rest per substep. Joint friction is a row J = e_i with
|lambda| <= h f and target velocity zero; the speed limit is a row that holds |v_i| <= the
joint's ``velocity`` with at most its ``effort`` (a brake, as ODE's joint motor with FMax). A
mimic joint is a two-sided row J = e_i - k e_j holding q_i = k q_j + offset, its error
corrected as a limit's is.

The rows are arrays, not a Python object per row, and no array operation runs on one row: one
pass over the joints in Python numbers picks them (a robot has tens of joints, and a NumPy call
on a handful of numbers costs more than a loop over them), a few array operations gather and
solve them.
"""

import math
from typing import List, NamedTuple, Optional, Sequence

import numpy as np

from .robot_block import solve_block
from .robot_model import RobotModel
from .robot_row_arrays import Rows
from .robot_sweeps import sweep_rows

# A joint's speed limit gets its row from this fraction of the limit on: the rows can push a
# joint faster within the substep, but not from far below its limit.
SPEED_ROW_FROM = 0.8
# A position limit gets its row within this many slops, plus this many substeps' travel, of
# its stop.
LIMIT_REACH_SLOPS = 4.0
LIMIT_REACH_SUBSTEPS = 4.0
# The mouse's rows lead A when it holds something.
MOUSE_ROWS = 3
# The most a joint may move in a substep while the mouse pulls (rad, or m for a prismatic
# joint), as the single body's ``kernel.MAX_CORRECTION_TURN`` bounds its turn: the mouse's
# impulse is bounded so that it alone moves no joint further (``travel_bound``), and the
# speeds it leaves are scaled down to it. The rows are solved for the substep's linearized
# constraint, which holds while the joints move little in it; near a singular pose (an arm at
# full stretch) or toward a target out of reach, a rigid mouse of unbounded force would ask for
# joint speeds of thousands of rad/s, and the free motion's Coriolis term (it grows as v^2)
# would run away. Only such pulls meet the bound: at 1 kHz and two substeps it is 100 rad/s,
# PhysX's default cap on an articulation joint's speed.
MAX_JOINT_TRAVEL = 0.05

# What a row holds: its kind.
MOUSE = -1
LOWER_LIMIT = 0
UPPER_LIMIT = 1
FRICTION = 2
SPEED_FORWARD = 3   # brakes a joint moving forward at its speed limit
SPEED_BACKWARD = 4  # brakes a joint moving backward at its speed limit
MIMIC = 5
# The joint rows' kinds, in the order ``RowTable`` stacks them after the mouse's.
JOINT_KINDS = (LOWER_LIMIT, UPPER_LIMIT, FRICTION, SPEED_FORWARD, SPEED_BACKWARD)


class JointArrays(NamedTuple):
    """
    The moving joints' constants the rows read, as arrays in the joints' order.

    :param v_index: each joint's coordinate in v.
    :param q_index: its first coordinate in q.
    :param limited: whether it has a finite lower or upper limit.
    :param lower: ``<limit lower>`` (rad or m), -inf for none.
    :param upper: ``<limit upper>``, +inf for none.
    :param friction: ``<dynamics friction>`` (N m or N).
    :param velocity: ``<limit velocity>`` (rad/s or m/s), +inf for none.
    :param effort: ``<limit effort>`` (N m or N).
    :param continuous: whether it is a continuous joint (q holds its cos and sin).
    :param any_continuous: whether any joint is continuous.
    :param coordinates: whether q and v are the joints' positions and velocities, in the joints'
        order (a fixed base and no continuous joint): the rows then read q and v as they are.
    :param mimic_follower: each mimic joint's follower, as a number in the joints' order.
    :param mimic_leader: its leader, likewise.
    :param mimic_multiplier: q_follower = multiplier q_leader + offset.
    :param mimic_offset: the offset (rad or m).
    """

    v_index: np.ndarray
    q_index: np.ndarray
    limited: np.ndarray
    lower: np.ndarray
    upper: np.ndarray
    friction: np.ndarray
    velocity: np.ndarray
    effort: np.ndarray
    continuous: np.ndarray
    any_continuous: bool
    coordinates: bool
    mimic_follower: np.ndarray
    mimic_leader: np.ndarray
    mimic_multiplier: np.ndarray
    mimic_offset: np.ndarray


def joint_arrays(model: RobotModel) -> JointArrays:
    """Return the joints' constants of ``model`` as arrays."""
    joints = model.joints
    number = {joint.name: position for position, joint in enumerate(joints)}

    def column(values, dtype=float) -> np.ndarray:
        return np.array(list(values), dtype=dtype)

    return JointArrays(
        v_index=column((j.v_index for j in joints), int),
        q_index=column((j.q_index for j in joints), int),
        limited=column((j.limited for j in joints), bool),
        lower=column(j.lower for j in joints),
        upper=column(j.upper for j in joints),
        friction=column(j.friction for j in joints),
        velocity=column(j.velocity for j in joints),
        effort=column(j.effort for j in joints),
        continuous=column((j.kind == 'continuous' for j in joints), bool),
        any_continuous=any(j.kind == 'continuous' for j in joints),
        coordinates=([j.q_index for j in joints] == list(range(model.nq))
                     and [j.v_index for j in joints] == list(range(model.nv))),
        mimic_follower=column((number[m.follower.name] for m in model.mimics), int),
        mimic_leader=column((number[m.leader.name] for m in model.mimics), int),
        mimic_multiplier=column(m.multiplier for m in model.mimics),
        mimic_offset=column(m.offset for m in model.mimics))


def joint_positions(arrays: JointArrays, q: np.ndarray) -> np.ndarray:
    """Return each moving joint's position (rad or m), a continuous joint's as its angle."""
    positions = q[arrays.q_index]
    if arrays.any_continuous:
        index = arrays.q_index[arrays.continuous]
        positions[arrays.continuous] = np.arctan2(q[index + 1], q[index])
    return positions


class LimitSettings(NamedTuple):
    """How the stops and mimic joints correct an error: ``RobotSettings``' part the rows read."""

    slop: float
    baumgarte: float


class MouseRows(NamedTuple):
    """
    The mouse constraint's three rows, before they join the joints'.

    :param jacobian: J (3 x nv), the anchor's world-frame point Jacobian.
    :param error: C = anchor - target (m).
    :param mass_scale: a of ``MouseConstraint.gains`` (1 in rigid mode).
    :param bias_factor: b of the gains (1/s): the rows aim at J v = -(b / a) C.
    :param bound: the largest impulse norm h F_max (N s).
    """

    jacobian: np.ndarray
    error: np.ndarray
    mass_scale: float
    bias_factor: float
    bound: float


class RowTable:
    """
    Every row the robot could have in a substep of length h; a substep picks some.

    The candidates, in order: the mouse's three, then each joint's lower stop, upper stop,
    friction, forward brake and backward brake (one block of joints per kind, in
    ``JOINT_KINDS`` order), then each mimic joint's. What does not change from one substep to
    the next is filled once: each row's J but the mouse's, its bounds, kind and joint, and the
    hold a new row is first tried at; ``prepare_rows`` picks the rows and finds their targets.

    :param arrays: the joints' constants.
    :param nv: the robot's degrees of freedom.
    :param h: the substep (s).
    :param limits: the stops' slop and correction.
    """

    def __init__(self, arrays: JointArrays, nv: int, h: float, limits: LimitSettings) -> None:
        """Fill every candidate's constant parts."""
        self.arrays, self.h, self.limits = arrays, h, limits
        joints = arrays.v_index.shape[0]
        mimics = arrays.mimic_follower.shape[0]
        self.count = MOUSE_ROWS + len(JOINT_KINDS) * joints + mimics
        kind_start = {kind: MOUSE_ROWS + number * joints
                      for number, kind in enumerate(JOINT_KINDS)}
        self.mimics = slice(self.count - mimics, self.count)
        inf, zeros, ones = math.inf, np.zeros(joints), np.ones(joints)
        brake, rub = h * arrays.effort, h * arrays.friction
        self.jacobian = np.zeros((self.count, nv))
        for kind in JOINT_KINDS:
            rows = np.arange(kind_start[kind], kind_start[kind] + joints)
            self.jacobian[rows, arrays.v_index] = 1.0
        follower = arrays.v_index[arrays.mimic_follower]
        leader = arrays.v_index[arrays.mimic_leader]
        mimic_rows = np.arange(self.mimics.start, self.count)
        self.jacobian[mimic_rows, follower] += 1.0
        self.jacobian[mimic_rows, leader] -= arrays.mimic_multiplier
        unbounded = np.full(MOUSE_ROWS, inf)
        lower = np.concatenate((-unbounded, zeros, -inf * ones, -rub, -brake, zeros,
                                np.full(mimics, -inf)))
        upper = np.concatenate((unbounded, inf * ones, zeros, rub, zeros, brake,
                                np.full(mimics, inf)))
        self.kind = np.concatenate((np.full(MOUSE_ROWS, MOUSE),
                                    np.repeat(JOINT_KINDS, joints).astype(int),
                                    np.full(mimics, MIMIC)))
        self.joint = np.concatenate((np.full(MOUSE_ROWS, -1),
                                     np.tile(arrays.v_index, len(JOINT_KINDS)), follower))
        # A one-sided row (a stop, a brake of unbounded effort) is first tried held at its zero
        # bound (not pushing), any other row free.
        first_guess = np.where((lower == 0.0) & np.isinf(upper), -1,
                               np.where((upper == 0.0) & np.isinf(lower), 1, 0))
        # Each row's bounds and first hold, as Python numbers: the picked rows' are gathered,
        # and the solvers read them, one at a time.
        self.lower: List[float] = lower.tolist()
        self.upper: List[float] = upper.tolist()
        self.first_guess: List[int] = first_guess.tolist()
        # What a substep reads to pick its rows, as Python numbers: a joint's checks cost less
        # so than as array operations (a robot has tens of joints, not thousands). Plain tuples
        # (a named tuple unpacks slower), each named where the loop of ``prepare_rows`` unpacks
        # it: stops (joint, lower_row, upper_row, lower, upper), brakes (joint, forward_row,
        # backward_row, limit, speed_from), mimic rows (row, follower, leader, multiplier,
        # offset); joints by their number, rows by theirs in the table.
        number = range(joints)
        self.stops = [(joint, kind_start[LOWER_LIMIT] + joint, kind_start[UPPER_LIMIT] + joint,
                       float(arrays.lower[joint]), float(arrays.upper[joint]))
                      for joint in number if arrays.limited[joint]]
        self.friction_rows = [kind_start[FRICTION] + joint for joint in number
                              if arrays.friction[joint] > 0.0]
        self.brakes = [(joint, kind_start[SPEED_FORWARD] + joint,
                        kind_start[SPEED_BACKWARD] + joint, float(arrays.velocity[joint]),
                        SPEED_ROW_FROM * float(arrays.velocity[joint]))
                       for joint in number if math.isfinite(arrays.velocity[joint])]
        self.mimic_rows = [(row, int(follower), int(leader), float(multiplier), float(offset))
                           for row, follower, leader, multiplier, offset in zip(
                               range(self.mimics.start, self.count), arrays.mimic_follower,
                               arrays.mimic_leader, arrays.mimic_multiplier,
                               arrays.mimic_offset)]
        self.reach = limits.slop * LIMIT_REACH_SLOPS
        self.reach_per_speed = LIMIT_REACH_SUBSTEPS * h


def stop_speed(distance: float, limits: LimitSettings, h: float) -> float:
    """
    Return the speed a stop's row allows toward it, ``distance`` from it (negative: past it).

    Ahead of the stop: arrive at it in the substep; past it by more than the slop: back out by
    ``baumgarte`` of the rest per substep.
    """
    if distance >= 0.0:
        return distance / h
    return limits.baumgarte * min(distance + limits.slop, 0.0) / h


def prepare_rows(table: RowTable, q: np.ndarray, v: np.ndarray,
                 mouse: Optional[MouseRows] = None) -> Rows:
    """
    Return the substep's rows: the mouse's, each stop near, friction, the brakes, mimic joints.

    A stop's row comes within four slops plus four substeps' travel of it; a brake's from
    ``SPEED_ROW_FROM`` of the speed limit on.

    :param table: every row the robot could have, for this substep length.
    :param q: the configuration.
    :param v: the velocity the rows start from.
    :param mouse: the mouse's rows, or None when it holds nothing.
    """
    arrays, h, limits = table.arrays, table.h, table.limits
    if arrays.coordinates:
        positions, velocities = q.tolist(), v.tolist()
    else:
        positions = joint_positions(arrays, q).tolist()
        velocities = v.take(arrays.v_index).tolist()
    picked, targets = [], []
    if mouse is not None:
        table.jacobian[:MOUSE_ROWS] = mouse.jacobian
        picked.extend(range(MOUSE_ROWS))
        targets.extend((mouse.error * (-mouse.bias_factor / mouse.mass_scale)).tolist())
    # the stops near (the upper ones' rows after every lower one's, as the table holds them)
    upper_rows, upper_targets = [], []
    reach, reach_per_speed = table.reach, table.reach_per_speed
    for joint, lower_row, upper_row, lower, upper in table.stops:
        position = positions[joint]
        near = reach_per_speed * abs(velocities[joint]) + reach
        if position - lower <= near:
            picked.append(lower_row)
            targets.append(-stop_speed(position - lower, limits, h))
        if upper - position <= near:
            upper_rows.append(upper_row)
            upper_targets.append(stop_speed(upper - position, limits, h))
    picked += upper_rows
    targets += upper_targets
    picked += table.friction_rows
    targets += [0.0] * len(table.friction_rows)
    # the brakes: forward ones' rows, then backward ones'
    backward_rows, backward_targets = [], []
    for joint, forward_row, backward_row, limit, speed_from in table.brakes:
        speed = velocities[joint]
        if speed > speed_from:
            picked.append(forward_row)
            targets.append(limit)
        elif speed < -speed_from:
            backward_rows.append(backward_row)
            backward_targets.append(-limit)
    picked += backward_rows
    targets += backward_targets
    correction = -limits.baumgarte / h
    for row, follower, leader, multiplier, offset in table.mimic_rows:
        picked.append(row)
        targets.append(
            (positions[follower] - (multiplier * positions[leader] + offset)) * correction)
    lower, upper, first_guess = table.lower, table.upper, table.first_guess
    picked_rows = (table.jacobian.take(picked, 0), np.array(targets, dtype=float),
                   [lower[row] for row in picked], [upper[row] for row in picked], picked,
                   [first_guess[row] for row in picked])
    if mouse is None:
        return Rows(*picked_rows)
    return Rows(*picked_rows, MOUSE_ROWS, mouse.mass_scale, mouse.bound)


class HeldSets:
    """
    Which bound each row of the table held at the last substep's end: the next solve's first set.

    -1: held at its least impulse, 0: free, +1: held at its largest. A row the last substep did
    not have is tried at its ``first_guess``. Python numbers, as the block solve reads them.

    :param first_guess: each row's hold when nothing is known of it (``RowTable.first_guess``).
    """

    def __init__(self, first_guess: Sequence[int]) -> None:
        """Start knowing nothing."""
        self._first_guess: List[int] = list(first_guess)
        self._held = list(self._first_guess)

    def clear(self) -> None:
        """Forget every row's hold (a new state)."""
        self._held[:] = self._first_guess

    def first(self, rows: Rows) -> List[int]:
        """Return the set to try first for ``rows``: each row's last hold, else its guess."""
        held = self._held
        return [held[row] for row in rows.picked]

    def remember(self, rows: Rows, held: Sequence[int]) -> None:
        """Keep ``held``, each row's hold, for the next substep; forget the rest."""
        table_held = self._held
        table_held[:] = self._first_guess
        for row, hold in zip(rows.picked, held):
            table_held[row] = hold


def travel_bound(mouse_mobility: np.ndarray, h: float) -> float:
    """
    Return the largest mouse impulse norm (N s) that moves no joint by more than the travel.

    A mouse impulse P changes v by W P (W = M^-1 J^T, ``mouse_mobility``), each joint's speed
    by at most |W|_F |P|: |P| <= MAX_JOINT_TRAVEL / (h |W|_F) keeps each joint's move in the
    substep within ``MAX_JOINT_TRAVEL``.
    """
    size = math.sqrt(float(np.square(mouse_mobility).sum()))
    return MAX_JOINT_TRAVEL / (h * size) if size > 0.0 else math.inf


class RowSolution(NamedTuple):
    """
    What one substep's rows did.

    :param joint_impulse: A^T x, the impulses on each coordinate of v (N m s or N s).
    :param mouse_impulse: the mouse's impulse P (N s), world frame.
    """

    joint_impulse: np.ndarray
    mouse_impulse: np.ndarray


def solve_rows(v: np.ndarray, rows: Rows, inverse_mass: np.ndarray, iterations: int, h: float,
               held_sets: Optional[HeldSets] = None) -> RowSolution:
    """
    Solve the rows, changing ``v`` in place; return their impulses.

    The rows are solved together, exactly (``robot_block``), the last substep's held set tried
    first; if no set settles, by sequential impulses (``robot_sweeps``): ``iterations`` sweeps,
    each visiting the mouse's block, then each joint row, and a last pass of the joint rows
    alone that gives the stops the last word where the mouse pulls against them. The mouse's
    impulse is bounded by its force bound and by ``travel_bound``.

    :param h: the substep (s).
    """
    if not rows.picked:
        if held_sets is not None:
            held_sets.clear()
        return RowSolution(np.zeros(v.shape[0]), np.zeros(MOUSE_ROWS))
    jacobian = rows.jacobian
    mobility = inverse_mass.dot(jacobian.T)
    warm = held_sets.first(rows) if held_sets is not None else rows.first_guess
    bound = rows.bound
    if rows.mouse_rows:
        bound = min(bound, travel_bound(mobility[:, :MOUSE_ROWS], h))
    solved = solve_block(jacobian, mobility, v, rows.target, rows.lower, rows.upper,
                         rows.mouse_rows, rows.mass_scale, bound, warm)
    if solved is not None:
        impulse, held = solved
        v += mobility.dot(impulse)
        if held_sets is not None:
            held_sets.remember(rows, held)
    else:
        impulse = sweep_rows(v, rows._replace(bound=bound), mobility, iterations)
        if held_sets is not None:  # no set settled: the next substep starts from its guesses
            held_sets.clear()
    return RowSolution(impulse.dot(jacobian),
                       impulse[:MOUSE_ROWS].copy() if rows.mouse_rows else np.zeros(MOUSE_ROWS))
