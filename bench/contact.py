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
The floor: rest, slide and drop in the core, PyBullet and MuJoCo, with the time per step.

The shipped box (config/params.yaml: 2 kg, 0.4 x 0.2 x 0.1 m) on a floor at z = 0, gravity
9.80665 m/s^2, friction 0.5. Every engine steps at the shipped tick (1 kHz); ours with the
shipped 2 substeps per tick and the core's contact defaults, the peers with theirs.

- rest: put 1 cm above the floor tilted 2 deg about x; after 1 s, jitter is the largest
  distance of the COM from where it was at 1 s over the next ``HOLD`` s (m), and the speed at
  the end; penetration: the deepest the lowest corner goes over the hold.
- slide: resting flat, started at 1 m/s along x with restitution 0: the stopping distance
  against v^2 / (2 mu g) = 0.102 m.
- drop: flat from 0.5 m (the bottom face's height) with restitution 0.5: the first rebound's
  peak of the COM, less half the box's height, against e^2 h = 0.125 m (a box that lands
  tilted, as Bullet's does, turns some of the bounce into spin).
- us / step: one tick of the resting box, the median of interleaved rounds.

Bullet combines two bodies' friction and restitution by multiplication, so the plane gets 1 and
the box the coefficient; it bounces above its restitution velocity threshold (set to 0.5 m/s as
ours). MuJoCo's contacts are soft: restitution is not a parameter, so the drop uses the damping
ratio of its contact spring that gives e = 0.5 for a linear spring,
zeta = -ln e / sqrt(pi^2 + ln^2 e) (solref (0.005, 0.2155)); rest and slide use its default
solref. Command: ``python -m bench.contact`` prints the section as JSON.
"""

import json
import math
import sys
import time

from bench import common
import numpy as np

from mouse_constraint_ros.physics import BodyState
from test_support import floor_scenarios

FRICTION = 0.5
HOLD = 10.0
QUICK_HOLD = 2.0
SLIDE_SPEED = 1.0
DROP = 0.5
RESTITUTION = 0.5
TILT_DEGREES = 2.0
LIFT = 0.01


def _tilted() -> tuple:
    half = math.radians(TILT_DEGREES) / 2.0
    return (math.sin(half), 0.0, 0.0, math.cos(half))


class Ours:
    """The core with the shipped floor."""

    name = 'ours'

    def __init__(self, world, state: BodyState, restitution: float) -> None:
        self.world = world
        self.sim = world.simulation(state, restitution=restitution, friction=FRICTION)

    def step(self) -> None:
        self.sim.step(self.world.dt)

    def read(self):
        s = self.sim.state
        return s.position, s.orientation, s.linear_velocity


class Bullet:
    """PyBullet in DIRECT mode: a box and a static plane, one stepSimulation per tick."""

    name = 'PyBullet'

    def __init__(self, pybullet, world, state: BodyState, restitution: float) -> None:
        p = self.p = pybullet
        self.cid = cid = p.connect(p.DIRECT)
        p.setGravity(*world.gravity, physicsClientId=cid)
        p.setPhysicsEngineParameter(fixedTimeStep=world.dt, numSubSteps=0,
                                    restitutionVelocityThreshold=0.5, physicsClientId=cid)
        plane = p.createMultiBody(0.0, p.createCollisionShape(p.GEOM_PLANE, physicsClientId=cid),
                                  physicsClientId=cid)
        p.changeDynamics(plane, -1, lateralFriction=1.0, restitution=1.0, physicsClientId=cid)
        shape = p.createCollisionShape(p.GEOM_BOX, halfExtents=[0.5 * e for e in world.box],
                                       physicsClientId=cid)
        self.body = p.createMultiBody(world.mass, shape, basePosition=state.position,
                                      baseOrientation=state.orientation, physicsClientId=cid)
        p.changeDynamics(self.body, -1, lateralFriction=FRICTION, restitution=restitution,
                         linearDamping=0.0, angularDamping=0.0,
                         activationState=p.ACTIVATION_STATE_DISABLE_SLEEPING,
                         physicsClientId=cid)
        p.resetBaseVelocity(self.body, state.linear_velocity, state.angular_velocity,
                            physicsClientId=cid)

    def step(self) -> None:
        self.p.stepSimulation(physicsClientId=self.cid)

    def read(self):
        position, orientation = self.p.getBasePositionAndOrientation(self.body,
                                                                     physicsClientId=self.cid)
        linear, _ = self.p.getBaseVelocity(self.body, physicsClientId=self.cid)
        return position, orientation, linear

    def close(self) -> None:
        self.p.disconnect(physicsClientId=self.cid)


class MuJoCo:
    """MuJoCo: the box on a free joint over a plane, one mj_step per tick."""

    name = 'MuJoCo'

    def __init__(self, mujoco, world, state: BodyState, restitution: float) -> None:
        self.mujoco = mujoco
        x, y, z, w = state.orientation
        if restitution > 0.0:
            log = math.log(restitution)
            solref = f'solref="0.005 {-log / math.sqrt(math.pi ** 2 + log ** 2):.4f}"'
        else:
            solref = ''
        half = ' '.join(repr(0.5 * e) for e in world.box)
        xml = f"""
<mujoco>
  <option timestep="{world.dt!r}" gravity="{' '.join(repr(g) for g in world.gravity)}"/>
  <worldbody>
    <geom type="plane" size="5 5 0.1" friction="{FRICTION} 0.005 0.0001" {solref}/>
    <body pos="{' '.join(repr(c) for c in state.position)}" quat="{w!r} {x!r} {y!r} {z!r}">
      <freejoint/>
      <geom type="box" size="{half}" mass="{world.mass!r}" friction="{FRICTION} 0.005 0.0001"
            {solref}/>
    </body>
  </worldbody>
</mujoco>"""
        self.model = mujoco.MjModel.from_xml_string(xml)
        self.data = mujoco.MjData(self.model)
        self.data.qvel[:3] = state.linear_velocity

    def step(self) -> None:
        self.mujoco.mj_step(self.model, self.data)

    def read(self):
        qpos = self.data.qpos
        return qpos[:3], (qpos[4], qpos[5], qpos[6], qpos[3]), self.data.qvel[:3]

    def close(self) -> None:
        pass


def _factories():
    """Return (name, factory(world, state, restitution)) for ours and the installed peers."""
    factories = [('ours', lambda world, state, e: Ours(world, state, e))]
    pybullet = common.import_peer('pybullet')
    if pybullet is not None:
        factories.append(('PyBullet', lambda world, state, e: Bullet(pybullet, world, state, e)))
    mujoco = common.import_peer('mujoco')
    if mujoco is not None:
        factories.append(('MuJoCo', lambda world, state, e: MuJoCo(mujoco, world, state, e)))
    return factories


def _lowest(world, position, orientation) -> float:
    """Return the lowest corner's height above the floor (m)."""
    floor = world.floor
    return -floor.depth(tuple(float(c) for c in position), tuple(float(c) for c in orientation))


def _rest(world, factory, hold: float) -> dict:
    lift = 0.5 * (world.box[1] * math.sin(math.radians(TILT_DEGREES))
                  + world.box[2] * math.cos(math.radians(TILT_DEGREES)))
    engine = factory(world, BodyState((0.0, 0.0, lift + LIFT), _tilted()), 0.0)
    for _ in range(round(1.0 / world.dt)):
        engine.step()
    start = np.array(engine.read()[0], dtype=float)
    jitter, deepest = 0.0, 0.0
    began = time.perf_counter()
    for _ in range(round(hold / world.dt)):
        engine.step()
        position, orientation, _ = engine.read()
        jitter = max(jitter, float(np.linalg.norm(np.array(position, dtype=float) - start)))
        deepest = max(deepest, -_lowest(world, position, orientation))
    per_step = (time.perf_counter() - began) / round(hold / world.dt)
    speed = float(np.linalg.norm(np.array(engine.read()[2], dtype=float)))
    getattr(engine, 'close', lambda: None)()
    return {'jitter_um': 1e6 * jitter, 'rest_speed': speed, 'penetration_mm': 1e3 * deepest,
            'read_us': 1e6 * per_step}


def _slide(world, factory) -> dict:
    engine = factory(world, BodyState((0.0, 0.0, world.half_height), (0.0, 0.0, 0.0, 1.0),
                                      (SLIDE_SPEED, 0.0, 0.0)), 0.0)
    for _ in range(round(1.0 / world.dt)):
        engine.step()
    distance = float(engine.read()[0][0])
    getattr(engine, 'close', lambda: None)()
    exact = SLIDE_SPEED ** 2 / (2.0 * FRICTION * -world.gravity[2])
    return {'stop_mm': 1e3 * distance, 'stop_error_pct': 100.0 * (distance / exact - 1.0)}


def _drop(world, factory) -> dict:
    engine = factory(world, BodyState((0.0, 0.0, world.half_height + DROP)), RESTITUTION)
    heights = []
    for _ in range(round(1.2 / world.dt)):
        engine.step()
        heights.append(float(engine.read()[0][2]) - world.half_height - world.floor.height)
    getattr(engine, 'close', lambda: None)()
    heights = np.array(heights)
    rising = np.nonzero(np.diff(heights) > 1e-6)[0]
    peak = float(heights[rising[0]:].max()) if len(rising) else 0.0
    exact = RESTITUTION ** 2 * DROP
    return {'rebound_mm': 1e3 * peak, 'rebound_error_pct': 100.0 * (peak / exact - 1.0)}


def _step_cost(world, factories, quick: bool) -> dict:
    """Return the median us per tick of each engine's resting box, interleaved rounds."""
    engines, loops = {}, {}
    for name, factory in factories:
        engine = factory(world, BodyState((0.0, 0.0, world.half_height)), 0.0)
        for _ in range(200):
            engine.step()
        engines[name] = engine

        def loop(n: int, step=engine.step) -> None:
            for _ in range(n):
                step()
        loops[name] = loop
    times = common.time_interleaved(loops, 3 if quick else 9, 0.1 if quick else 0.2)
    for engine in engines.values():
        getattr(engine, 'close', lambda: None)()
    return {name: common.median(values) for name, values in times.items()}


def run(quick: bool = False) -> dict:
    start = time.perf_counter()
    world = floor_scenarios.world()
    factories = _factories()
    hold = QUICK_HOLD if quick else HOLD
    costs = _step_cost(world, factories, quick)
    rows = []
    for name, factory in factories:
        row = {'engine': name}
        row.update(_rest(world, factory, hold))
        row.update(_slide(world, factory))
        row.update(_drop(world, factory))
        row['step_us'] = costs[name]
        rows.append(row)
    notes = [f'{peer} is not installed here: its row is skipped.'
             for peer in ('pybullet', 'mujoco') if common.import_peer(peer) is None]
    notes += [
        f'jitter: the largest distance of the COM over {hold:g} s from where it was 1 s after '
        'being put down; rest speed: |v| at the end; penetration: deepest lowest corner over '
        'the hold.',
        f'stop: distance slid from {SLIDE_SPEED:g} m/s with friction {FRICTION:g}, exact '
        f'{1e3 * SLIDE_SPEED ** 2 / (2.0 * FRICTION * -world.gravity[2]):.1f} mm; rebound: '
        f'first peak of the COM less half the height after a flat drop from {DROP:g} m with '
        f'restitution {RESTITUTION:g}, exact {1e3 * RESTITUTION ** 2 * DROP:.0f} mm.',
        'us / step: one tick of the box resting on the floor (ours: 2 substeps), median of '
        'interleaved rounds; the peers step in C/C++ behind one Python call.',
    ]
    return {
        'title': 'The floor: rest, slide and drop against PyBullet and MuJoCo',
        'text': ('Command: `python -m bench.contact`. The shipped box (2 kg, 0.4 x 0.2 x 0.1 m) '
                 'at 1 kHz on a floor at z = 0; ours with the shipped substeps and the contact '
                 'defaults of the core, the peers with theirs (docs/contact.md).'),
        'columns': [['engine', 'engine', ''], ['jitter_um', 'rest jitter (um)', '.3g'],
                    ['rest_speed', 'rest speed (m/s)', '.2g'],
                    ['penetration_mm', 'penetration (mm)', '.3g'],
                    ['stop_mm', 'stop (mm)', '.1f'], ['stop_error_pct', 'stop error (%)', '+.1f'],
                    ['rebound_mm', 'rebound (mm)', '.1f'],
                    ['rebound_error_pct', 'rebound error (%)', '+.1f'],
                    ['step_us', 'us / step', '.2f']],
        'rows': rows,
        'notes': notes,
        'elapsed_s': time.perf_counter() - start,
    }


if __name__ == '__main__':
    json.dump(run(quick='--quick' in sys.argv), sys.stdout, indent=2)
    print()
