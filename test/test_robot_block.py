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
from mouse_constraint_ros.physics.robot_rows import (FRICTION, joint_arrays, LimitSettings,
                                                     LOWER_LIMIT, MOUSE, MOUSE_ROWS,
                                                     prepare_rows, Rows, RowTable, solve_rows,
                                                     UPPER_LIMIT)
from test_support.robots import double_pendulum


def random_problem(seed: int):
    """Return a robot-like problem: M^-1, v, and the mouse's rows then joint rows of each kind."""
    rng = np.random.default_rng(seed)
    nv = int(rng.integers(3, 9))
    root = rng.normal(size=(nv, nv))
    inverse = np.linalg.inv(root @ root.T + 0.5 * np.eye(nv))
    v = rng.normal(size=nv)
    a, b, h = float(rng.uniform(0.2, 1.0)), 50.0, 1e-3
    jacobian, target = [rng.normal(size=(3, nv))], list(-(b / a) * rng.normal(size=3) * 0.01)
    lower, upper, kind, joint = [-math.inf] * 3, [math.inf] * 3, [MOUSE] * 3, [-1] * 3
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
        joint.append(index)
    count = len(target)
    rows = Rows(np.vstack(jacobian), np.array(target), np.array(lower), np.array(upper),
                np.array(kind), np.array(joint), np.arange(count),
                np.where(np.array(kind) == LOWER_LIMIT, -1,
                         np.where(np.array(kind) == UPPER_LIMIT, 1, 0)),
                slice(3, 3), MOUSE_ROWS, a, math.inf)
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
    solve_rows(block, rows, inverse, 10)
    sweeps = v.copy()
    monkeypatch.setattr(robot_rows, 'solve_block', lambda *_arguments: None)  # no set: sweeps
    solve_rows(sweeps, rows, inverse, 5000)
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
    picked = sorted(zip(rows.kind.tolist(), rows.joint.tolist(), rows.target.tolist(),
                        rows.lower.tolist(), rows.upper.tolist()))
    expected = sorted(expected)
    assert [row[:2] for row in picked] == [row[:2] for row in expected]
    assert [row[2:] for row in picked] == [pytest.approx(row[2:], rel=1e-12) for row in expected]
    stops = rows.kind[rows.limit_rows]
    assert sorted(stops.tolist()) == [LOWER_LIMIT, UPPER_LIMIT]
    for row in range(rows.count):
        assert rows.jacobian[row].tolist() == np.eye(model.nv)[rows.joint[row]].tolist()
