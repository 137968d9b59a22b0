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
The floor's scenarios on the shipped configuration's body and rate, shared by tests and bench.

``rest`` puts the box on the floor, ``slide`` pushes it along it, ``drop`` lets it fall flat,
``elastic_drift`` lets it bounce flat for good, ``held_down`` pulls its grabbed corner into the
floor and ``tumble`` drops it spinning and records its energy. The body (mass, box_size), rate,
substeps and gravity are read from config/params.yaml, and the floor's settings from it where
it has them (else the core's).
"""

import dataclasses
import math
from pathlib import Path
from typing import Any, Dict, List, NamedTuple, Tuple

import numpy as np
import yaml

from mouse_constraint_ros.physics import BodyState, MouseConstraint, MouseSimulation, RigidBody
from mouse_constraint_ros.physics import Settings
from mouse_constraint_ros.physics.floor import Floor

PARAMS_FILE = Path(__file__).resolve().parent.parent / 'config' / 'params.yaml'
# A step's gain of vertical speed over free fall's (m/s) above which the floor pushed.
IMPACT_SPEED = 1e-9
# The floor's settings as config/params.yaml names them.
FLOOR_PARAMETERS = {'floor_height': 'height', 'friction': 'friction',
                    'restitution': 'restitution', 'contact_iterations': 'iterations',
                    'contact_margin': 'margin', 'contact_slop': 'slop',
                    'restitution_threshold': 'restitution_threshold'}


def shipped() -> Dict[str, Any]:
    """Return the parameters of config/params.yaml as shipped, parsed from the real file."""
    return dict(yaml.safe_load(PARAMS_FILE.read_text())['/**']['ros__parameters'])


class World(NamedTuple):
    """The shipped body and rate with a floor."""

    mass: float
    box: Tuple[float, float, float]
    dt: float
    substeps: int
    gravity: Tuple[float, float, float]
    floor: Floor

    @property
    def half_height(self) -> float:
        """Return half the box's height (m): the COM's height above the floor, lying flat."""
        return 0.5 * self.box[2]

    def simulation(self, state: BodyState, *, constraint: MouseConstraint = MouseConstraint(),
                   **floor: Any) -> MouseSimulation:
        """Return a simulation of the box from ``state``, the floor's settings overridden."""
        body = RigidBody.solid_box(self.mass, self.box)
        settings = Settings(body, constraint, gravity=self.gravity, substeps=self.substeps,
                            floor=dataclasses.replace(self.floor, **floor))
        return MouseSimulation(settings, state)

    def energy(self, sim: MouseSimulation) -> float:
        """Return kinetic plus potential energy in J, the potential from the floor's height."""
        g = -self.gravity[2]
        return sim.kinetic_energy() + self.mass * g * (sim.state.position[2] - self.floor.height)


def world() -> World:
    """Return the shipped configuration's body, rate and floor (floor on)."""
    values = shipped()
    floor = {field: float(values[name]) if field != 'iterations' else int(values[name])
             for name, field in FLOOR_PARAMETERS.items() if name in values}
    box = tuple(float(e) for e in values['box_size'])
    return World(float(values['mass']), box, 1.0 / float(values['rate_hz']),
                 int(values['substeps']), tuple(float(g) for g in values['gravity']),
                 Floor(enabled=True, box_size=box, **floor))


def depth(w: World, sim: MouseSimulation) -> float:
    """Return the box's penetration into the floor (m; 0 when above it)."""
    return max(0.0, sim.settings.floor.depth(sim.state.position, sim.state.orientation))


class Rest(NamedTuple):
    """A box put on the floor: its motion after ``settle`` s and over the hold after."""

    speed: float
    spin: float
    penetration: float
    moved: float
    contacts: int


def rest(w: World, *, settle: float = 1.0, hold: float = 10.0, drop: float = 0.01,
         tilt_deg: float = 2.0) -> Rest:
    """Put the box ``drop`` m above the floor tilted ``tilt_deg`` about x; let it settle."""
    half = math.radians(tilt_deg) / 2.0
    lift = 0.5 * (w.box[1] * math.sin(2 * half) + w.box[2] * math.cos(2 * half))
    sim = w.simulation(BodyState((0.0, 0.0, w.floor.height + lift + drop),
                                 (math.sin(half), 0.0, 0.0, math.cos(half))))
    for _ in range(round(settle / w.dt)):
        sim.step(w.dt)
    state = sim.state
    start = np.array(state.position)
    deepest, moved = depth(w, sim), 0.0
    for _ in range(round(hold / w.dt)):
        sim.step(w.dt)
        deepest = max(deepest, depth(w, sim))
        moved = max(moved, float(np.linalg.norm(np.array(sim.state.position) - start)))
    return Rest(math.hypot(*state.linear_velocity), math.hypot(*state.angular_velocity),
                deepest, moved, sim.contact_count)


def resting(w: World, **floor: Any) -> MouseSimulation:
    """Return the box lying flat on the floor, at rest, after 0.2 s."""
    sim = w.simulation(BodyState((0.0, 0.0, w.floor.height + w.half_height)), **floor)
    for _ in range(round(0.2 / w.dt)):
        sim.step(w.dt)
    return sim


def slide(w: World, force: float, *, seconds: float = 2.0) -> Tuple[float, float]:
    """
    Push the resting box along x by ``force`` N through its COM for ``seconds``.

    Return the acceleration fitted over the push's last three quarters (m/s^2) and how far the
    box moved (m).
    """
    sim = resting(w)
    start = sim.state.position[0]
    sim.wrench = ((force, 0.0, 0.0), (0.0, 0.0, 0.0))
    steps = round(seconds / w.dt)
    path = np.empty(steps)
    for i in range(steps):
        path[i] = sim.step(w.dt).position[0] - start
    times = w.dt * np.arange(1, steps + 1)
    tail = steps // 4
    acceleration = 2.0 * np.polyfit(times[tail:], path[tail:], 2)[0]
    return float(acceleration), float(path[-1])


def drop(w: World, *, height: float = 0.5, restitution: float = 0.5,
         seconds: float = 1.5) -> Tuple[float, List[float]]:
    """
    Drop the box flat from ``height`` m (its bottom face above the floor).

    Return the peak height of the bottom face between the first impact and the second, and
    that height over time (m).
    """
    sim = w.simulation(BodyState((0.0, 0.0, w.floor.height + w.half_height + height)),
                       restitution=restitution)
    bottom = []
    for _ in range(round(seconds / w.dt)):
        sim.step(w.dt)
        bottom.append(sim.state.position[2] - w.half_height - w.floor.height)
    bottom = np.array(bottom)
    rising = np.nonzero(np.diff(bottom) > 0.0)[0]
    if len(rising) == 0:
        return 0.0, list(bottom)
    first = rising[0]
    after = bottom[first:]
    falling = np.nonzero(np.diff(after) < 0.0)[0]
    end = falling[0] + 1 if len(falling) else len(after)
    return float(after[:end].max()), list(bottom)


def elastic_drift(w: World, *, height: float = 0.5,
                  seconds: float = 30.0) -> Tuple[float, MouseSimulation]:
    """
    Drop the box flat from ``height`` m, restitution 1 and no threshold: it bounces for good.

    Return the farthest its COM strayed sideways from where it fell (m) over ``seconds``, and
    the simulation at the end.
    """
    sim = w.simulation(BodyState((0.0, 0.0, w.floor.height + w.half_height + height)),
                       restitution=1.0, restitution_threshold=0.0)
    drift = 0.0
    for _ in range(round(seconds / w.dt)):
        x, y, _ = sim.step(w.dt).position
        drift = max(drift, math.hypot(x, y))
    return drift, sim


def held_down(w: World, *, depth_below: float = 0.5, seconds: float = 3.0) -> float:
    """
    Grab the resting box's corner, pull it ``depth_below`` m into the floor; return the deepest.

    The joint is the shipped one: rigid, max_force_per_weight and angular_friction from
    config/params.yaml.
    """
    values = shipped()
    constraint = MouseConstraint(
        anchor=tuple(float(c) for c in values['anchor']),
        baumgarte=float(values['baumgarte']),
        max_force_per_weight=float(values['max_force_per_weight']),
        angular_friction=float(values['angular_friction']))
    sim = w.simulation(BodyState((0.0, 0.0, w.floor.height + w.half_height)),
                       constraint=constraint)
    anchor = sim.anchor_position()
    sim.target = (anchor[0], anchor[1], w.floor.height - depth_below)
    deepest = 0.0
    for _ in range(round(seconds / w.dt)):
        sim.step(w.dt)
        deepest = max(deepest, depth(w, sim))
    return deepest


def tumble(w: World, *, height: float, orientation, spin, restitution: float,
           friction: float, seconds: float = 2.0) -> Tuple[List[float], int]:
    """
    Drop the box from ``height`` m (COM above the floor) turned and spinning; record E per step.

    Return the energies (kinetic + potential, J) after every step and the index of the first
    step in which the floor pushed (the first impact), or -1 if it never did. The floor is the
    only thing that pushes the box up, so that is the first step whose vertical velocity came
    out above free fall's: its contacts may be gone by the step's last substep (a box that
    bounces off one corner within a substep), which ``contacts`` reports.
    """
    sim = w.simulation(BodyState((0.0, 0.0, w.floor.height + height), orientation,
                                 (0.0, 0.0, 0.0), spin),
                       restitution=restitution, friction=friction)
    energies, first = [], -1
    falling = w.gravity[2] * w.dt
    vz = None
    for i in range(round(seconds / w.dt)):
        sim.step(w.dt)
        energies.append(w.energy(sim))
        # The first step also moves the given velocities back half a substep: not compared.
        if first < 0 and vz is not None \
                and sim.state.linear_velocity[2] - vz > falling + IMPACT_SPEED:
            first = i
        vz = sim.state.linear_velocity[2]
    return energies, first
