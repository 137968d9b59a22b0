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
A box rests on the floor whatever its mass and inertia; an implausible inertia is warned about.

With m r^2 / I far from 1 (a heavy body with a small inertia, a URDF written in grams) every
contact row's effective mass is that of turning the body, far from the mass its weight asks the
contacts to carry, and sequential sweeps alone let the body sink and creep, a heavy enough
one through the floor. The normal
rows solved as a block and the pushing contacts held at once (``normal_block``,
``floor_sticking``) hold it. Each case runs the node's shipped floor (config/params.yaml) in
lockstep: 1 kHz, two substeps, its slop.
"""

import math
from typing import List

import numpy as np
import pytest
from scipy.spatial.transform import Rotation

from mouse_constraint_ros.description.urdf_link import body_model
from mouse_constraint_ros.node.body_loads import BodyLoads
from mouse_constraint_ros.physics import BodyState, floor_sticking, MouseSimulation
from test_support.mouse_feel import configured

EDGE = 0.1  # the box's edge (m)
SOLID = 1.0 / 6.0 * EDGE * EDGE  # a solid cube's I / m (kg m^2 per kg)

# (mass (kg), inertia (kg m^2)): a URDF in grams and heavy boxes with a small inertia, the same
# masses with a consistent inertia, and the reverse (pybullet's cube_small: 0.1 kg of inertia 1
# on a 5 cm cube, here 10 cm).
CASES = [(500.0, 0.00083), (1e4, 0.01), (1e6, 0.01), (1e12, 0.01),
         (500.0, 500.0 * SOLID), (1e4, 1e4 * SOLID), (1e12, 1e12 * SOLID), (0.1, 1.0)]


def simulation(mass: float, inertia: float, *, tilt: float = 0.0,
               drop: float = 0.0) -> MouseSimulation:
    """Return the shipped node's simulation of the box, its lowest point ``drop`` m up."""
    config = configured({'mass': mass, 'inertia': [inertia, 0.0, 0.0, inertia, 0.0, inertia],
                         'box_size': [EDGE] * 3, 'anchor': [EDGE / 2] * 3})
    settings = config.settings
    orientation = tuple(Rotation.from_rotvec((math.radians(tilt), 0.0, 0.0)).as_quat())
    lowest = settings.floor.shape.reach(Rotation.from_quat(orientation).as_matrix().ravel())
    start = BodyState((0.0, 0.0, settings.floor.height + lowest + drop), orientation)
    return MouseSimulation(settings, start)


def corners(sim: MouseSimulation) -> np.ndarray:
    """Return the box's eight corners in the world (m)."""
    signs = np.array([(x, y, z) for x in (-1, 1) for y in (-1, 1) for z in (-1, 1)])
    return np.array([sim.state.world_point(tuple(0.5 * EDGE * s)) for s in signs])


def run(sim: MouseSimulation, seconds: float) -> List[np.ndarray]:
    """Step ``seconds`` at the shipped 1 kHz; return the corners after each step."""
    return [corners(sim) for _ in range(round(seconds * 1000)) if sim.step(1e-3)]


@pytest.mark.parametrize('mass, inertia', CASES)
def test_a_box_placed_on_the_floor_rests_whatever_its_inertia(mass, inertia):
    """Placed flat: no corner sinks more than the slop, none moves 1 % of it in 3 s."""
    sim = simulation(mass, inertia)
    slop = sim.settings.floor.slop
    start = corners(sim)
    path = run(sim, 3.0)
    deepest = max(sim.settings.floor.height - float(c[:, 2].min()) for c in path)
    assert deepest <= slop
    assert max(float(np.linalg.norm(c - start, axis=1).max()) for c in path) <= 0.01 * slop


@pytest.mark.parametrize('mass, inertia', CASES[:4])
@pytest.mark.parametrize('tilt, drop', [(0.0, 0.1), (10.0, 0.0)])
def test_a_heavy_box_of_small_inertia_lands_and_comes_to_rest(mass, inertia, tilt, drop):
    """Dropped 0.1 m, or tipped 10 deg onto its face: above the slop, still from 2 s on."""
    sim = simulation(mass, inertia, tilt=tilt, drop=drop)
    slop = sim.settings.floor.slop
    path = run(sim, 3.0)
    assert max(sim.settings.floor.height - float(c[:, 2].min()) for c in path) <= slop
    last = path[-1000:]
    assert max(float(np.linalg.norm(c - last[0], axis=1).max()) for c in last) <= 0.01 * slop


def test_the_rounding_of_a_heavy_box_s_impulses_is_not_taken_for_motion(monkeypatch):
    """
    At rest, 1e12 kg on 0.01 kg m^2: the sweeps settle, none leaves the contacts to be held.

    Its contacts carry some 1e9 N s a substep, whose last bits move a corner by 1e-7 m/s: a
    sweep that changes them by no more than their rounding has converged, and the pushing
    contacts are not solved again at once (``floor_sticking``) in any substep.
    """
    sim = simulation(1e12, 0.01)
    run(sim, 0.1)
    held = []
    stick = floor_sticking.stick
    monkeypatch.setattr(floor_sticking, 'stick',
                        lambda *arguments: held.append(arguments) or stick(*arguments))
    run(sim, 0.1)
    assert held == []


def brick(mass: float, inertia: float, edge: float = EDGE) -> str:
    """Return a one-link URDF: a box of ``edge`` with this <inertial>."""
    return (f'<robot name="r"><link name="brick"><inertial><mass value="{mass}"/>'
            f'<inertia ixx="{inertia}" ixy="0" ixz="0" iyy="{inertia}" iyz="0" '
            f'izz="{inertia}"/></inertial><collision><geometry><box size="{edge} {edge} '
            f'{edge}"/></geometry></collision></link></robot>')


def test_an_inertia_written_in_grams_is_warned_about_naming_the_link():
    """500 g written as 500 with the inertia of 0.5 kg: one line, the link and grams named."""
    notes = body_model(brick(500.0, 0.5 * SOLID)).notes
    assert len(notes) == 1 and '\n' not in notes[0]
    assert "link 'brick'" in notes[0] and 'grams' in notes[0] and 'too small' in notes[0]


def test_a_placeholder_inertia_on_a_small_body_is_warned_about():
    """A 5 cm cube of 0.1 kg with inertia 1 (pybullet's cube_small): radius of gyration 3.9 m."""
    notes = body_model(brick(0.1, 1.0, 0.05)).notes
    assert len(notes) == 1 and 'too large' in notes[0] and 'placeholder' in notes[0]


@pytest.mark.parametrize('mass, inertia', [(500.0, 500.0 * SOLID), (2.0, 2.0 * SOLID / 4.0),
                                           (2.0, 2.0 * SOLID * 4.0)])
def test_a_plausible_inertia_is_not_warned_about(mass, inertia):
    """The solid cube's, a mass concentrated at the COM, a hollow one: no warning."""
    assert body_model(brick(mass, inertia)).notes == ()


def test_the_node_logs_the_warning_when_it_loads_the_body():
    """``BodyLoads`` logs a loaded body's notes as warnings, once per load."""
    lines: List[str] = []

    class Logger:
        def warning(self, line: str) -> None:
            lines.append(line)

        def info(self, line: str) -> None:
            pass

    class Node:
        def get_logger(self) -> Logger:
            return Logger()

    loads = BodyLoads(Node(), lambda config, changes: None)
    loads.now(brick(500.0, 0.5 * SOLID), '', 0.0)
    loads.now(brick(500.0, 0.5 * SOLID), '', 0.0)
    assert len(lines) == 1 and "link 'brick'" in lines[0]
    loads.now(brick(0.5, 0.5 * SOLID), '', 0.0)
    assert len(lines) == 1
