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
A curved many-vertex hull on the floor: it rests, slides, and its shortcuts answer exactly.

It comes to rest and slides as Coulomb says; the block solve meets the complementarity
conditions and the kept candidates answer as every vertex does.

The hull is the benchmark's (``bench.node_hull``): 500 Fibonacci points on an ellipsoid, every
one a vertex, so it rests on a facet of a few millimetres whose vertices' normal rows differ by
little, the case sequential impulses alone settle slowly.
"""

import math

import numpy as np
import pytest
from scipy.spatial.transform import Rotation

from mouse_constraint_ros.description.urdf_link import body_model
from mouse_constraint_ros.physics import BodyState, MouseConstraint, MouseSimulation, Settings
from mouse_constraint_ros.physics import floor_contact, normal_block
from mouse_constraint_ros.physics.floor import Floor
from mouse_constraint_ros.physics.hull_vertices import HullVertices, MAX_VERTEX_CONTACTS, spread
from test_support.meshes import ellipsoid_hull, geometry, urdf, write

G = 9.80665
DT = 0.001
AXES = (0.1, 0.07, 0.05)
VERTICES = 500
DENSITY = 1000.0


@pytest.fixture(scope='module')
def hull(tmp_path_factory):
    """Return the hull body's model (URDF mesh weighed at DENSITY)."""
    mesh = write(ellipsoid_hull(VERTICES, AXES), tmp_path_factory.mktemp('hull') / 'hull.stl')
    return body_model(urdf([geometry('mesh', filename=str(mesh))], link='hull'),
                      density=DENSITY)


def on_floor(model, **floor) -> MouseSimulation:
    """Return the hull put down 1 mm above the floor, its smallest axis vertical."""
    settings = Settings(model.rigid_body(), MouseConstraint(), gravity=(0.0, 0.0, -G),
                        substeps=2, floor=Floor(enabled=True,
                                                shape=model.geometry.collision_shape(), **floor))
    return MouseSimulation(settings, BodyState((0.0, 0.0, AXES[2] + 0.001)))


def test_the_hull_comes_to_rest_and_every_later_solve_converges(hull, monkeypatch):
    """After 3 s the hull is still to 1e-12 and each substep's sweeps converge."""
    sim = on_floor(hull)
    for _ in range(3000):
        sim.step(DT)
    outcomes = []
    sweeps = floor_contact._sweeps

    def counted(*args):
        velocities, converged = sweeps(*args)
        outcomes.append(converged)
        return velocities, converged

    monkeypatch.setattr(floor_contact, '_sweeps', counted)
    heights = []
    for _ in range(1000):
        heights.append(sim.step(DT).position[2])
    state = sim.state
    assert math.hypot(*state.angular_velocity) < 1e-12
    assert math.hypot(*state.linear_velocity) < 1e-12
    assert max(heights) - min(heights) < 1e-12
    assert len(outcomes) == 2000 and all(outcomes)
    # Resting on its facet: the contacts carry the weight.
    assert sum(impulse for _, impulse in sim.contacts) == pytest.approx(
        hull.mass * G * DT / 2, rel=1e-9)


@pytest.mark.parametrize('ratio', [1.5, 3.0])
def test_the_hull_pushed_above_the_friction_bound_slides_at_f_minus_mu_m_g(hull, ratio):
    """F = ratio mu m g through the COM: the resting hull slides at (F - mu m g) / m."""
    sim = on_floor(hull)
    for _ in range(3000):
        sim.step(DT)
    mu = sim.settings.floor.friction
    force = ratio * mu * hull.mass * G
    start = sim.state.position[0]
    sim.wrench = ((force, 0.0, 0.0), (0.0, 0.0, 0.0))
    steps = 1000
    path = np.array([sim.step(DT).position[0] - start for _ in range(steps)])
    times = DT * np.arange(1, steps + 1)
    acceleration = 2.0 * np.polyfit(times[steps // 4:], path[steps // 4:], 2)[0]
    assert acceleration == pytest.approx((force - mu * hull.mass * G) / hull.mass, rel=0.02)


def rows_for(points, inverse_inertia, goals, impulses):
    """Return ``floor_contact.Rows``-shaped rows for world offsets ``points`` (m)."""
    rows = []
    for (rx, ry, rz), goal, impulse in zip(points, goals, impulses):
        nx, ny, nz = inverse_inertia @ np.array((ry, -rx, 0.0))
        rows.append([0, rx, ry, rz, 0.0, nx, ny, nz, 0, 0, 0, 0, 0, 0,
                     0.0, 0.0, 0.0, 0.0, goal, impulse, 0.0, 0.0, None])
    return rows


@pytest.mark.parametrize('seed', range(40))
def test_the_block_solve_meets_every_complementarity_condition(seed):
    """Random contacts, velocities and warm impulses: P >= 0, u >= goal, P (u - goal) = 0."""
    rng = np.random.default_rng(seed)
    n = int(rng.integers(2, normal_block.MOST_CONTACTS + 1))
    im = 1.0 / rng.uniform(0.1, 5.0)
    root = rng.normal(size=(3, 3))
    inverse_inertia = np.linalg.inv(root @ root.T * 0.01 + 0.002 * np.eye(3))
    points = rng.uniform(-0.1, 0.1, size=(n, 3))
    goals = np.where(rng.random(n) < 0.3, -rng.uniform(0.0, 2.0, n), 0.0)
    warm = np.where(rng.random(n) < 0.5, rng.uniform(0.0, 0.01, n), 0.0)
    rows = rows_for(points, inverse_inertia, goals, warm)
    vz, wx, wy = rng.normal(scale=0.5, size=3)
    weights = (im, inverse_inertia[0, 0], inverse_inertia[0, 1], inverse_inertia[1, 1])
    result = normal_block.impulses(rows, vz, wx, wy, weights, 1e-9, [])
    assert result is not None
    change = np.array(result) - warm
    k = np.array([[im + a[2] * b[5] - a[1] * b[6] for b in rows] for a in rows])
    u = np.array([vz + wx * r[2] - wy * r[1] for r in rows]) + k @ change
    assert min(result) >= 0.0
    assert np.all(u - goals >= -1e-9)
    assert np.all(np.array(result) * np.abs(u - goals) <= 1e-9 * (1.0 + np.array(result)))


def test_four_coplanar_contacts_share_the_load_evenly():
    """A square of four contacts under the COM (K singular): each carries a quarter."""
    points = [(x, y, -0.05) for x in (-0.1, 0.1) for y in (-0.1, 0.1)]
    rows = rows_for(points, np.diag([20.0, 30.0, 40.0]), [0.0] * 4, [0.0] * 4)
    im = 0.5
    result = normal_block.impulses(rows, -1.0, 0.0, 0.0, (im, 20.0, 0.0, 30.0), 1e-12, [])
    assert result == pytest.approx([1.0 / (4 * im)] * 4, rel=1e-6)


def reference_near(points, row, ceiling, band):
    """Return what ``HullVertices.near`` returns, from every vertex read afresh."""
    heights = points[:, 0] * row[0] + points[:, 1] * row[1] + points[:, 2] * row[2]
    chosen = np.flatnonzero(heights <= min(ceiling, float(heights.min()) + band))
    near = list(zip(chosen.tolist(), heights[chosen].tolist()))
    return spread(points, near, row) if len(near) > MAX_VERTEX_CONTACTS else near


def test_the_kept_candidates_answer_as_every_vertex_does(hull):
    """A turning walk of rotations: ``near`` and ``lowest`` equal a fresh full read, to the bit."""
    shape = hull.geometry.collision_shape()
    vertices = HullVertices(shape.hull.points, shape.bound)
    reads = 0
    read = vertices._read

    def counted(row):
        nonlocal reads
        if vertices._row != row:
            reads += 1
        return read(row)

    vertices._read = counted
    rng = np.random.default_rng(7)
    rotation = Rotation.identity()
    calls = 3000
    for step in range(calls):
        # Mostly slow turns (a body rocking), now and then a jump.
        turn = rng.normal(scale=0.3 if step % 500 == 499 else 2e-4, size=3)
        rotation = Rotation.from_rotvec(turn) * rotation
        row = tuple(float(c) for c in rotation.as_matrix()[2])
        # A resting body's band (the slop and a little), now and then a falling body's.
        band = 0.01 if step % 100 == 99 else float(rng.uniform(0.0005, 0.0006))
        ceiling = float(rng.uniform(-0.02, 0.1))
        assert vertices.near(row, ceiling, band) == reference_near(
            shape.hull.points, row, ceiling, band)
        expected = shape.hull.points @ np.array(row)
        assert vertices.lowest(row) == float(min(
            shape.hull.points[:, 0] * row[0] + shape.hull.points[:, 1] * row[1]
            + shape.hull.points[:, 2] * row[2]))
        assert vertices.lowest(row) == pytest.approx(float(expected.min()), abs=1e-15)
    # The candidates answered most calls: every vertex was read for a few.
    assert reads < calls // 4
