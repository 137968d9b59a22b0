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

from mouse_constraint_ros.physics import robot_rows
from mouse_constraint_ros.physics.robot_block import first_set, solve_block
from mouse_constraint_ros.physics.robot_rows import (bounded_row, limit_row, mouse_rows,
                                                     solve_rows)


def random_problem(seed: int):
    """Return a robot-like problem: M, v, the mouse's rows and joint rows of every kind."""
    rng = np.random.default_rng(seed)
    nv = int(rng.integers(3, 9))
    root = rng.normal(size=(nv, nv))
    mass = root @ root.T + 0.5 * np.eye(nv)
    inverse = np.linalg.inv(mass)
    v = rng.normal(size=nv)
    mouse = mouse_rows(rng.normal(size=(3, nv)), inverse, rng.normal(size=3) * 0.01,
                       (float(rng.uniform(0.2, 1.0)), 50.0), math.inf)
    joints = []
    for index in range(nv):
        kind = rng.integers(0, 3)
        if kind == 0:
            joints.append(limit_row(index, inverse, float(rng.uniform(-0.01, 0.01)), 1e-3,
                                    0.005, 0.2, bool(rng.integers(0, 2))))
        elif kind == 1:
            joints.append(bounded_row(index, inverse, 0.0, float(rng.uniform(0.01, 1.0))))
    return inverse, v, mouse, joints


@pytest.mark.parametrize('seed', range(40))
def test_the_block_solve_meets_every_rows_condition(seed):
    inverse, v, mouse, joints = random_problem(seed)
    nv = v.shape[0]
    rows = [mouse.jacobian] + [np.eye(nv)[[row.index]] for row in joints]
    jacobian = np.vstack(rows)
    mobility = inverse @ jacobian.T
    target = np.concatenate((-mouse.bias, [row.target for row in joints]))
    lower = np.array([-math.inf] * 3 + [row.lower for row in joints])
    upper = np.array([math.inf] * 3 + [row.upper for row in joints])
    keys = [None] * 3 + [(number,) for number in range(len(joints))]
    solved = solve_block(jacobian, mobility, v, target, lower, upper, 3, mouse.mass_scale,
                         mouse.bound, first_set(keys, lower, upper, {}))
    assert solved is not None
    impulse, held = solved
    after = v + mobility @ impulse
    # The mouse at its soft fixed point: J v' + ((1 - a) / a) K P = -bias.
    a = mouse.mass_scale
    residual = mouse.jacobian @ after + (1.0 - a) / a * (mouse.stiffness @ impulse[:3]) \
        + mouse.bias
    assert np.abs(residual).max() < 1e-8
    for number, row in enumerate(joints):
        x, w = impulse[3 + number], after[row.index] - row.target
        assert row.lower - 1e-9 <= x <= row.upper + 1e-9
        if row.lower + 1e-9 < x < row.upper - 1e-9:
            assert abs(w) < 1e-8            # free: its velocity is its target's
        elif x <= row.lower + 1e-9 and not math.isinf(row.lower):
            assert w >= -1e-8               # at its least impulse: not pulled further
        else:
            assert w <= 1e-8


@pytest.mark.parametrize('seed', range(10))
def test_the_block_solve_agrees_with_many_sweeps_of_sequential_impulses(seed, monkeypatch):
    inverse, v, mouse, joints = random_problem(seed)
    block = v.copy()
    solve_rows(block, mouse, joints, 10)
    sweeps = v.copy()
    monkeypatch.setattr(robot_rows, '_block', lambda *_arguments: None)  # no set: sweeps
    solve_rows(sweeps, mouse, joints, 5000)
    assert np.abs(block - sweeps).max() < 1e-6
