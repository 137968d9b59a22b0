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
URDF bodies on the floor against their closed forms.

A sphere rests on one point at its radius, a sphere and a cylinder launched sliding end up
rolling at 5/7 and 2/3 of the launch speed, and a mesh rests on its convex hull.

A uniform body of radius r sliding at v0 without spin on a floor with friction loses speed and
gains spin until it rolls (v = w r); the friction's angular impulse about the contact point is
zero, so m v0 r = m v r + I w, and v = v0 / (1 + I / (m r^2)): 5/7 for a solid sphere
(I = 2/5 m r^2), 2/3 for a solid cylinder about its axis (I = 1/2 m r^2).
"""

import math
from pathlib import Path

import numpy as np
import pytest

from mouse_constraint_ros.description.urdf_link import body_model
from mouse_constraint_ros.physics import BodyState, MouseConstraint, MouseSimulation, Settings
from mouse_constraint_ros.physics.floor import Floor
from test_support.meshes import geometry, mug, urdf, write

G = 9.80665
DT = 0.001
RADIUS = 0.05
DENSITY = 1000.0
ROOT = Path(__file__).resolve().parent.parent


def simulation(text: str, position, velocity=(0.0, 0.0, 0.0), **floor) -> MouseSimulation:
    """Return the URDF's body (inertia from DENSITY) on the floor, its COM at ``position``."""
    model = body_model(text, density=DENSITY)
    settings = Settings(model.rigid_body(), MouseConstraint(), gravity=(0.0, 0.0, -G),
                        substeps=2, floor=Floor(enabled=True,
                                                shape=model.geometry.collision_shape(), **floor))
    return MouseSimulation(settings, BodyState(position, linear_velocity=velocity))


def sphere() -> str:
    """Return a URDF sphere of RADIUS about its link frame, without <inertial>."""
    return urdf([geometry('sphere', radius=RADIUS)])


def cylinder() -> str:
    """Return a URDF cylinder of RADIUS and 0.1 m lying along y, without <inertial>."""
    return urdf([geometry('cylinder', radius=RADIUS, length=0.1, rpy=(math.pi / 2, 0.0, 0.0))])


def test_the_density_gives_the_closed_form_inertias():
    """Solid sphere 2/5 m r^2; solid cylinder 1/2 m r^2 about its axis, m (3 r^2 + l^2) / 12."""
    ball = body_model(sphere(), density=DENSITY)
    m = DENSITY * 4.0 / 3.0 * math.pi * RADIUS ** 3
    assert ball.mass == pytest.approx(m, rel=1e-12)
    assert ball.inertia == pytest.approx((0.4 * m * RADIUS ** 2, 0.0, 0.0,
                                          0.4 * m * RADIUS ** 2, 0.0, 0.4 * m * RADIUS ** 2),
                                         rel=1e-12, abs=1e-18)
    roller = body_model(cylinder(), density=DENSITY)
    m = DENSITY * math.pi * RADIUS ** 2 * 0.1
    across = m * (3.0 * RADIUS ** 2 + 0.1 ** 2) / 12.0
    assert roller.mass == pytest.approx(m, rel=1e-12)
    assert roller.inertia == pytest.approx((across, 0.0, 0.0, 0.5 * m * RADIUS ** 2, 0.0,
                                            across), rel=1e-12, abs=1e-18)


def test_a_sphere_rests_on_one_point_at_its_radius():
    """Dropped 5 cm: after 1 s it is still, on one contact, its centre r above the floor."""
    sim = simulation(sphere(), (0.0, 0.0, RADIUS + 0.05))
    for _ in range(1000):
        sim.step(DT)
    assert sim.contact_count == 1
    floor = sim.settings.floor
    assert sim.state.position[2] == pytest.approx(RADIUS, abs=floor.slop)
    assert math.hypot(*sim.state.linear_velocity) < 1e-4
    (point, impulse), = sim.contacts
    assert point[:2] == pytest.approx(sim.state.position[:2], abs=1e-12)
    assert impulse == pytest.approx(sim.settings.body.mass * G * DT / 2, rel=1e-6)


@pytest.mark.parametrize('shape, ratio', [(sphere, 5.0 / 7.0), (cylinder, 2.0 / 3.0)])
def test_a_body_launched_sliding_ends_rolling_at_its_closed_form_speed(shape, ratio):
    """v0 = 1 m/s without spin, friction 0.5: rolling (v = w r) at ratio v0 within 0.5 %."""
    sim = simulation(shape(), (0.0, 0.0, RADIUS), (1.0, 0.0, 0.0), friction=0.5)
    # Sliding lasts (1 - ratio) v0 / (mu g) < 0.07 s; then it rolls.
    for _ in range(300):
        sim.step(DT)
    v = sim.state.linear_velocity
    w = sim.state.angular_velocity
    assert v[0] == pytest.approx(ratio, rel=0.005)
    assert w[1] * RADIUS == pytest.approx(v[0], rel=0.005)
    assert abs(v[1]) < 1e-9 and abs(v[2]) < 1e-3
    assert sim.state.position[2] == pytest.approx(RADIUS, abs=sim.settings.floor.slop)


def test_a_mesh_rests_on_its_hull(tmp_path):
    """The mug, dropped upright: still on its base's rim, at most 8 contacts, none deep."""
    path = write(mug(), tmp_path / 'mug.stl')
    text = urdf([geometry('mesh', filename=str(path))])
    model = body_model(text, density=DENSITY)
    base = model.geometry.com[2]  # the COM's height above the mug's base (z = 0 of the mesh)
    assert 0.0 < base < 0.1
    sim = simulation(text, (0.0, 0.0, base + 0.01))
    for _ in range(1500):
        sim.step(DT)
    assert 3 <= sim.contact_count <= 8
    assert sim.state.position[2] == pytest.approx(base, abs=sim.settings.floor.slop)
    assert math.hypot(*sim.state.linear_velocity) < 1e-4
    assert math.hypot(*sim.state.angular_velocity) < 1e-3
    points = np.array([point for point, _ in sim.contacts])
    radii = np.hypot(points[:, 0] - sim.state.position[0], points[:, 1] - sim.state.position[1])
    assert radii == pytest.approx(0.04, rel=0.01)  # on the base's rim, MUG_RADIUS


def test_the_shipped_mug_mesh_is_the_one_the_code_makes(tmp_path):
    """config/mug.stl is ``python -m test_support.meshes config/mug.stl``'s output."""
    made = write(mug(), tmp_path / 'mug.stl')
    assert made.read_bytes() == (ROOT / 'config' / 'mug.stl').read_bytes()
