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

"""The robot's rows solved together (physics.robot_block): every condition met, as PGS finds."""

import math

import numpy as np
import pytest

from mouse_constraint_ros.description.robot_description import load_robot
from mouse_constraint_ros.physics import robot_rows
from mouse_constraint_ros.physics.robot_block import free_impulses, solve_block
from mouse_constraint_ros.physics.robot_rows import (FRICTION, HeldSets, joint_arrays,
                                                     LimitSettings, LOWER_LIMIT, MOUSE,
                                                     MOUSE_ROWS, prepare_rows, Rows, RowTable,
                                                     solve_rows, UPPER_LIMIT)
from test_support.robots import collection_urdf, double_pendulum


@pytest.fixture(scope='module')
def panda():
    """Return the Panda of the public collection: seven limited joints and a mimic pair."""
    return load_robot(collection_urdf('panda_description/urdf/panda.urdf').read_text())


def random_problem(seed: int):
    """Return a robot-like problem: M^-1, v, and the mouse's rows then joint rows of each kind."""
    rng = np.random.default_rng(seed)
    nv = int(rng.integers(3, 9))
    root = rng.normal(size=(nv, nv))
    inverse = np.linalg.inv(root @ root.T + 0.5 * np.eye(nv))
    v = rng.normal(size=nv)
    a, b, h = float(rng.uniform(0.2, 1.0)), 50.0, 1e-3
    jacobian, target = [rng.normal(size=(3, nv))], list(-(b / a) * rng.normal(size=3) * 0.01)
    lower, upper, kind = [-math.inf] * 3, [math.inf] * 3, [MOUSE] * 3
    for index in range(nv):
        row_kind = int(rng.integers(0, 3))
        if row_kind == 2:
            continue
        jacobian.append(np.eye(nv)[[index]])
        if row_kind == 0:  # a stop, either side, ahead of it or past it
            distance, upper_side = float(rng.uniform(-0.01, 0.01)), bool(rng.integers(0, 2))
            speed = distance / h if distance >= 0 else 0.2 * min(distance + 0.005, 0.0) / h
            target.append(speed if upper_side else -speed)
            lower.append(-math.inf if upper_side else 0.0)
            upper.append(0.0 if upper_side else math.inf)
            kind.append(UPPER_LIMIT if upper_side else LOWER_LIMIT)
        else:  # friction
            bound = float(rng.uniform(0.01, 1.0))
            target.append(0.0)
            lower.append(-bound)
            upper.append(bound)
            kind.append(FRICTION)
    count = len(target)
    rows = Rows(np.vstack(jacobian), np.array(target), lower, upper, list(range(count)),
                [-1 if row == LOWER_LIMIT else 1 if row == UPPER_LIMIT else 0 for row in kind],
                MOUSE_ROWS, a, math.inf)
    return inverse, v, rows


@pytest.mark.parametrize('seed', range(40))
def test_the_block_solve_meets_every_rows_condition(seed):
    inverse, v, rows = random_problem(seed)
    mobility = inverse @ rows.jacobian.T
    solved = solve_block(rows.jacobian, mobility, v, rows.target, rows.lower, rows.upper, 3,
                         rows.mass_scale, rows.bound, rows.first_guess)
    assert solved is not None
    impulse, _held = solved
    after = v + mobility @ impulse
    # The mouse at its soft fixed point: J v' + ((1 - a) / a) K P = -bias.
    a = rows.mass_scale
    mouse = rows.jacobian[:3]
    stiffness = mouse @ mobility[:, :3]
    residual = mouse @ after + (1.0 - a) / a * (stiffness @ impulse[:3]) - rows.target[:3]
    assert np.abs(residual).max() < 1e-8
    for row in range(3, rows.count):
        x, w = impulse[row], rows.jacobian[row] @ after - rows.target[row]
        low, high = rows.lower[row], rows.upper[row]
        assert low - 1e-9 <= x <= high + 1e-9
        if low + 1e-9 < x < high - 1e-9:
            assert abs(w) < 1e-8            # free: its velocity is its target's
        elif x <= low + 1e-9 and not math.isinf(low):
            assert w >= -1e-8               # at its least impulse: not pulled further
        else:
            assert w <= 1e-8


@pytest.mark.parametrize('seed', range(10))
def test_the_block_solve_agrees_with_many_sweeps_of_sequential_impulses(seed, monkeypatch):
    inverse, v, rows = random_problem(seed)
    block = v.copy()
    solve_rows(block, rows, inverse, 10, 1e-3)
    sweeps = v.copy()
    monkeypatch.setattr(robot_rows, 'solve_block', lambda *_arguments: None)  # no set: sweeps
    solve_rows(sweeps, rows, inverse, 5000, 1e-3)
    assert np.abs(block - sweeps).max() < 1e-6


def test_two_rows_on_one_joint_share_its_impulse_as_least_squares_would():
    # A stop's row and friction's on one joint: the system is singular, Cholesky's pivot
    # vanishes, and the answer is least squares' minimum-norm one.
    matrix = np.array([[2.0, 2.0, 0.5], [2.0, 2.0, 0.5], [0.5, 0.5, 1.0]])
    right = np.array([1.0, 1.0, 0.3])
    assert np.allclose(free_impulses(matrix, right),
                       np.linalg.lstsq(matrix, right, rcond=1e-10)[0], atol=1e-12)
    well_posed = np.array([[2.0, 0.3], [0.3, 1.0]])
    assert np.allclose(free_impulses(well_posed, right[:2]),
                       np.linalg.solve(well_posed, right[:2]), atol=1e-14)


def limited_pendulum():
    """Return the double pendulum with both joints held within +-0.5 rad, and its joints."""
    robot = load_robot(double_pendulum(kind='revolute', limit=(
        '<limit lower="-0.5" upper="0.5" effort="10" velocity="2"/>'
        '<dynamics friction="0.2"/>')))
    return robot.model, joint_arrays(robot.model)


def test_a_substep_picks_each_stop_near_friction_and_the_brakes_as_a_loop_over_joints_would():
    model, arrays = limited_pendulum()
    h, limits = 1e-3, LimitSettings(0.005, 0.2)
    table = RowTable(arrays, model.nv, h, limits)
    q = np.array([0.499, -0.52])       # the shoulder 1 mrad inside its upper stop, the elbow
    v = np.array([1.9, -0.1])          # 20 mrad past its lower; the shoulder near its speed
    rows = prepare_rows(table, q, v)
    expected = []                      # (kind, joint, target, lower, upper) by joint
    for joint, (position, speed) in enumerate(zip(q, v)):
        reach = 4 * limits.slop + 4 * h * abs(speed)
        for kind, distance, sign in ((LOWER_LIMIT, position + 0.5, -1.0),
                                     (UPPER_LIMIT, 0.5 - position, 1.0)):
            if distance <= reach:
                allowed = distance / h if distance >= 0 else \
                    limits.baumgarte * min(distance + limits.slop, 0.0) / h
                expected.append((kind, joint, sign * allowed,
                                 0.0 if kind == LOWER_LIMIT else -math.inf,
                                 math.inf if kind == LOWER_LIMIT else 0.0))
    for joint in range(2):
        expected.append((FRICTION, joint, 0.0, -h * 0.2, h * 0.2))
    expected.append((robot_rows.SPEED_FORWARD, 0, 2.0, -h * 10.0, 0.0))
    kinds, joints = table.kind[rows.picked], table.joint[rows.picked]
    picked = sorted(zip(kinds.tolist(), joints.tolist(), rows.target.tolist(),
                        rows.lower, rows.upper))
    expected = sorted(expected)
    assert [row[:2] for row in picked] == [row[:2] for row in expected]
    assert [row[2:] for row in picked] == [pytest.approx(row[2:], rel=1e-12) for row in expected]
    for row in range(rows.count):
        assert rows.jacobian[row].tolist() == np.eye(model.nv)[joints[row]].tolist()


def rows_one_by_one(model, q, v, h, limits):
    """Return (kind, joint, target, lower, upper) of each row, picked by a loop over joints."""
    rows = []
    positions = {}
    for joint in model.joints:
        index, speed = joint.v_index, abs(float(v[joint.v_index]))
        position = math.atan2(q[joint.q_index + 1], q[joint.q_index]) \
            if joint.kind == 'continuous' else float(q[joint.q_index])
        positions[joint.name] = position
        if joint.limited:
            reach = limits.slop * 4.0 + 4.0 * h * speed
            for bound, upper_side in ((joint.lower, False), (joint.upper, True)):
                distance = bound - position if upper_side else position - bound
                if distance <= reach:
                    allowed = distance / h if distance >= 0.0 else \
                        limits.baumgarte * min(distance + limits.slop, 0.0) / h
                    rows.append((UPPER_LIMIT, index, allowed, -math.inf, 0.0) if upper_side
                                else (LOWER_LIMIT, index, -allowed, 0.0, math.inf))
        if joint.friction > 0.0:
            rows.append((FRICTION, index, 0.0, -h * joint.friction, h * joint.friction))
        if math.isfinite(joint.velocity) and speed > 0.8 * joint.velocity:
            brake = h * joint.effort
            rows.append((robot_rows.SPEED_FORWARD, index, joint.velocity, -brake, 0.0)
                        if v[index] > 0.0 else
                        (robot_rows.SPEED_BACKWARD, index, -joint.velocity, 0.0, brake))
    for mimic in model.mimics:
        error = positions[mimic.follower.name] - (
            mimic.multiplier * positions[mimic.leader.name] + mimic.offset)
        rows.append((robot_rows.MIMIC, mimic.follower.v_index, -limits.baumgarte * error / h,
                     -math.inf, math.inf))
    return rows


@pytest.mark.parametrize('seed', range(30))
def test_the_table_picks_the_rows_a_loop_over_the_joints_picks(seed, panda):
    rng = np.random.default_rng(seed)
    model = panda.model
    arrays = joint_arrays(model)
    h, limits = 1e-3, LimitSettings(0.005, 0.2)
    table = RowTable(arrays, model.nv, h, limits)
    # Each joint anywhere from 0.05 rad (or m) beyond a stop to the middle, moving up to
    # twice its speed limit either way.
    q, v = np.zeros(model.nq), np.zeros(model.nv)
    for joint in model.joints:
        low, high = joint.lower, joint.upper
        q[joint.q_index] = rng.choice([rng.uniform(low - 0.01, low + 0.03),
                                       rng.uniform(high - 0.03, high + 0.01),
                                       rng.uniform(low, high)])
        v[joint.v_index] = rng.uniform(-2.0, 2.0) * min(joint.velocity, 10.0)
    rows = prepare_rows(table, q, v)
    kinds, joints = table.kind[rows.picked], table.joint[rows.picked]
    picked = sorted(zip(kinds.tolist(), joints.tolist(), rows.target.tolist(),
                        rows.lower, rows.upper))
    expected = sorted(rows_one_by_one(model, q, v, h, limits))
    assert [row[:2] for row in picked] == [row[:2] for row in expected]
    assert [row[2:] for row in picked] == [pytest.approx(row[2:], rel=1e-12, abs=1e-12)
                                           for row in expected]
    for row in range(rows.count):
        reference = np.zeros(model.nv)
        if kinds[row] == robot_rows.MIMIC:
            mimic = model.mimics[0]
            reference[mimic.follower.v_index] += 1.0
            reference[mimic.leader.v_index] -= mimic.multiplier
        else:
            reference[joints[row]] = 1.0
        assert rows.jacobian[row].tolist() == reference.tolist()


def test_a_substeps_held_set_is_the_next_ones_first_and_a_new_state_forgets_it():
    model, arrays = limited_pendulum()
    table = RowTable(arrays, model.nv, 1e-3, LimitSettings(0.005, 0.2))
    q, v = np.array([0.499, -0.52]), np.array([0.3, -0.1])
    rows = prepare_rows(table, q, v)
    held_sets = HeldSets(table.first_guess)
    assert held_sets.first(rows) == rows.first_guess
    held = [(-1, 1, 0)[k % 3] for k in range(rows.count)]
    held_sets.remember(rows, held)
    assert held_sets.first(rows) == held
    held_sets.clear()
    assert held_sets.first(rows) == rows.first_guess
    # A stop is first tried at its zero bound; friction, two-sided, free.
    guesses = dict(zip(table.kind[rows.picked].tolist(), rows.first_guess))
    assert guesses[LOWER_LIMIT] == -1 and guesses[UPPER_LIMIT] == 1 and guesses[FRICTION] == 0


def test_the_rows_read_q_and_v_as_they_are_only_where_they_are_the_joints_coordinates(panda):
    # A fixed arm of revolute and prismatic joints: q and v are its joints' coordinates. A
    # continuous joint (q holds its cos and sin) or a floating base (q and v lead with the base's)
    # has them elsewhere: the rows gather them by the joints' indices.
    assert joint_arrays(panda.model).coordinates
    assert not joint_arrays(load_robot(double_pendulum(kind='continuous')).model).coordinates
    limited = double_pendulum(kind='revolute', limit=(
        '<limit lower="-0.5" upper="0.5" effort="10" velocity="2"/>'))
    assert joint_arrays(load_robot(limited).model).coordinates
    massive_base = limited.replace('<link name="base"/>', '<link name="base">' + (
        '<inertial><mass value="0.5"/><inertia ixx="0.01" iyy="0.01" izz="0.01" ixy="0" '
        'ixz="0" iyz="0"/></inertial></link>'))
    assert not joint_arrays(load_robot(massive_base, base='floating').model).coordinates
