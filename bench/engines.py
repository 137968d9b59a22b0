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
The same scene in each engine: one box, one point of it pinned to a movable target.

Every engine class offers the same four things, so that the accuracy and drag benchmarks run one
loop and one set of metrics over all of them:

- ``step()`` advances one tick;
- ``set_target(point)`` moves the target the anchor is pulled to;
- ``read()`` returns the COM position, orientation (x, y, z, w), linear and angular velocity
  (both world frame) as one 13-vector;
- ``timing_loop()`` returns ``loop(n)``, which makes n ticks by calling the engine's own step
  function straight from a Python for loop, and nothing else.

Peers are set up as close to ours as each allows: the same mass and inertia (set explicitly, not
derived from a collision shape), no damping, no sleeping, no collision, the engine's own fixed
timestep equal to the tick, and a point-to-point (ball) constraint from the same body point.
"""

from typing import List, Optional, Sequence, Tuple

import numpy as np

from mouse_constraint_ros.physics import (BodyState, MouseConstraint, MouseSimulation, RigidBody,
                                          Settings)

Vector3 = Tuple[float, float, float]


def _xyz(values: Sequence[float]) -> str:
    return ' '.join(format(float(v), '.17g') for v in values)


def _rotate(q: Sequence[float], v: Sequence[float]) -> np.ndarray:
    """Rotate ``v`` by the unit quaternion ``q`` given as (x, y, z, w)."""
    x, y, z, w = q
    u = np.array([x, y, z])
    v = np.asarray(v, dtype=float)
    return v + 2.0 * np.cross(u, np.cross(u, v) + w * v)


def record(engine, ticks: int, targets: Optional[np.ndarray] = None) -> np.ndarray:
    """
    Run ``ticks`` ticks and return the states read before the first and after each one.

    With ``targets`` (ticks x 3), the target is set to ``targets[i]`` before tick i.
    """
    states = np.empty((ticks + 1, 13))
    states[0] = engine.read()
    step, read = engine.step, engine.read
    for i in range(ticks):
        if targets is not None:
            engine.set_target(tuple(targets[i]))
        step()
        states[i + 1] = read()
    return states


def anchor_positions(states: np.ndarray, anchor: Vector3) -> np.ndarray:
    """Return the world positions of the body point ``anchor`` for recorded ``states``."""
    q = states[:, 3:7]
    u, w = q[:, :3], q[:, 3:4]
    a = np.broadcast_to(np.asarray(anchor, dtype=float), u.shape)
    return states[:, :3] + a + 2.0 * np.cross(u, np.cross(u, a) + w * a)


def energies(states: np.ndarray, body: RigidBody, gravity: Vector3) -> np.ndarray:
    """Return the total energy, kinetic + potential m g.x (J), of recorded ``states``."""
    q = states[:, 3:7]
    u, s = -q[:, :3], q[:, 3:4]
    w = states[:, 10:13]
    w_body = w + 2.0 * np.cross(u, np.cross(u, w) + s * w)
    xx, xy, xz, yy, yz, zz = body.inertia
    inertia = np.array([[xx, xy, xz], [xy, yy, yz], [xz, yz, zz]])
    v = states[:, 7:10]
    kinetic = 0.5 * body.mass * np.sum(v * v, axis=1) \
        + 0.5 * np.einsum('ij,jk,ik->i', w_body, inertia, w_body)
    return kinetic - body.mass * states[:, :3] @ np.asarray(gravity, dtype=float)


def _diagonal(body: RigidBody) -> Vector3:
    ixx, ixy, ixz, iyy, iyz, izz = body.inertia
    if ixy or ixz or iyz:
        raise ValueError('the peers are set up for a body with a diagonal inertia only')
    return (ixx, iyy, izz)


class Ours:
    """Our ``MouseSimulation``, ticked by ``step(h)`` with ``settings.substeps`` substeps."""

    name = 'ours'

    def __init__(self, settings: Settings, state: BodyState, target: Optional[Vector3],
                 h: float) -> None:
        self.sim = MouseSimulation(settings, state)
        self.sim.target = target
        self.h = h

    def step(self) -> None:
        self.sim.step(self.h)

    def set_target(self, target: Vector3) -> None:
        self.sim.target = target

    def close(self) -> None:
        pass

    def read(self) -> np.ndarray:
        s = self.sim.state
        return np.array(s.position + s.orientation + s.linear_velocity + s.angular_velocity)

    def timing_loop(self):
        step, h = self.sim.step, self.h

        def loop(n: int) -> None:
            for _ in range(n):
                step(h)
        return loop


def ours(body: RigidBody, constraint: MouseConstraint, gravity: Vector3, state: BodyState,
         target: Optional[Vector3], h: float, substeps: int = 1,
         angular_damping: float = 0.0) -> Ours:
    """Return our simulation of ``body`` held by ``constraint``, ticking ``h`` seconds."""
    settings = Settings(body, constraint, gravity=gravity, substeps=substeps,
                        angular_damping=angular_damping)
    return Ours(settings, state, target, h)


class PyBulletBox:
    """
    PyBullet in DIRECT mode: the box and a JOINT_POINT2POINT user constraint to a world point.

    ``maximal`` selects a btRigidBody with a btPoint2PointConstraint (useMaximalCoordinates), the
    pair Bullet's own mouse picking uses, instead of the default btMultiBody with a
    btMultiBodyPoint2Point. The constraint's force
    limit is raised from PyBullet's default 500 N to ``max_force``, as ours is unlimited; the
    solver settings (50 iterations, ERP) are PyBullet's defaults.
    """

    def __init__(self, pybullet, body: RigidBody, extents: Vector3, anchor: Vector3,
                 gravity: Vector3, state: BodyState, target: Vector3, h: float,
                 maximal: bool = False, max_force: float = 1e9) -> None:
        p = self.p = pybullet
        self.client = cid = p.connect(p.DIRECT)
        p.resetSimulation(physicsClientId=cid)
        p.setGravity(*gravity, physicsClientId=cid)
        p.setPhysicsEngineParameter(fixedTimeStep=h, numSubSteps=0, physicsClientId=cid)
        shape = p.createCollisionShape(p.GEOM_BOX, halfExtents=[0.5 * e for e in extents],
                                       physicsClientId=cid)
        self.body = p.createMultiBody(
            baseMass=body.mass, baseCollisionShapeIndex=shape, basePosition=state.position,
            baseOrientation=state.orientation, useMaximalCoordinates=maximal,
            physicsClientId=cid)
        p.changeDynamics(self.body, -1, mass=body.mass, linearDamping=0.0, angularDamping=0.0,
                         localInertiaDiagonal=_diagonal(body),
                         activationState=p.ACTIVATION_STATE_DISABLE_SLEEPING,
                         physicsClientId=cid)
        p.setCollisionFilterGroupMask(self.body, -1, 0, 0, physicsClientId=cid)
        p.resetBaseVelocity(self.body, state.linear_velocity, state.angular_velocity,
                            physicsClientId=cid)
        # A rigid body cannot be constrained to the world (-1) itself, and changeConstraint does
        # not move a rigid body's pivot: pin it to a static body instead, placed at the target.
        self.pivot_body = -1
        if maximal:
            self.pivot_body = p.createMultiBody(baseMass=0.0, basePosition=target,
                                                useMaximalCoordinates=True, physicsClientId=cid)
        self.constraint = p.createConstraint(
            self.body, -1, self.pivot_body, -1, p.JOINT_POINT2POINT, [0.0, 0.0, 0.0], anchor,
            [0.0, 0.0, 0.0] if maximal else target, physicsClientId=cid)
        p.changeConstraint(self.constraint, maxForce=max_force, physicsClientId=cid)
        self.name = 'PyBullet ' + ('rigid body' if maximal else 'multibody')

    def step(self) -> None:
        self.p.stepSimulation(physicsClientId=self.client)

    def set_target(self, target: Vector3) -> None:
        if self.pivot_body >= 0:
            self.p.resetBasePositionAndOrientation(self.pivot_body, target, (0.0, 0.0, 0.0, 1.0),
                                                   physicsClientId=self.client)
        else:
            self.p.changeConstraint(self.constraint, jointChildPivot=target,
                                    physicsClientId=self.client)

    def read(self) -> np.ndarray:
        p, cid = self.p, self.client
        position, orientation = p.getBasePositionAndOrientation(self.body, physicsClientId=cid)
        linear, angular = p.getBaseVelocity(self.body, physicsClientId=cid)
        return np.array(position + orientation + linear + angular)

    def timing_loop(self):
        step, cid = self.p.stepSimulation, self.client

        def loop(n: int) -> None:
            for _ in range(n):
                step(physicsClientId=cid)
        return loop

    def close(self) -> None:
        self.p.disconnect(physicsClientId=self.client)


# MuJoCo's warnings (e.g. a simulation found unstable and reset), captured instead of going to
# stderr and to a MUJOCO_LOG.TXT in the working directory.
MUJOCO_WARNINGS: List[str] = []


class MuJoCoBox:
    """
    MuJoCo: the box on a free joint and a ``connect`` equality to the world or a mocap body.

    With ``mocap`` the constraint's second body is a mocap body placed at the anchor, which
    ``set_target`` moves; without, it is the world. MuJoCo takes the second body's point from
    the initial configuration (qpos0), so the anchor must start on the target in the world case.
    ``solref`` is (timeconst, dampratio); MuJoCo's default is (0.02, 1) and, unless refsafe is
    disabled, it raises a timeconst below 2 timesteps to 2 timesteps. Integrator: MuJoCo's
    default semi-implicit Euler, which updates velocities then positions as ours does.
    """

    def __init__(self, mujoco, body: RigidBody, anchor: Vector3, gravity: Vector3,
                 state: BodyState, target: Vector3, h: float,
                 solref: Tuple[float, float] = (0.02, 1.0), mocap: bool = False) -> None:
        self.mujoco = mujoco
        mujoco.set_mju_user_warning(MUJOCO_WARNINGS.append)
        self._first_warning = len(MUJOCO_WARNINGS)
        x, y, z, w = state.orientation
        anchor_world = np.add(state.position, _rotate(state.orientation, anchor))
        if mocap:
            pivot_body = f'<body name="target" mocap="true" pos="{_xyz(anchor_world)}"/>'
            second = 'body2="target"'
        else:
            if np.linalg.norm(anchor_world - np.asarray(target)) > 1e-12:
                raise ValueError('without mocap the anchor must start on the target')
            pivot_body, second = '', ''
        xml = f"""
<mujoco>
  <option timestep="{h!r}" gravity="{_xyz(gravity)}"/>
  <worldbody>
    <body name="box" pos="{_xyz(state.position)}" quat="{_xyz((w, x, y, z))}">
      <freejoint/>
      <inertial pos="0 0 0" mass="{body.mass!r}" diaginertia="{_xyz(_diagonal(body))}"/>
    </body>
    {pivot_body}
  </worldbody>
  <equality>
    <connect body1="box" {second} anchor="{_xyz(anchor)}" solref="{_xyz(solref)}"/>
  </equality>
</mujoco>"""
        self.model = mujoco.MjModel.from_xml_string(xml)
        self.data = mujoco.MjData(self.model)
        q = state.orientation
        w_body = _rotate((-q[0], -q[1], -q[2], q[3]), state.angular_velocity)
        self.data.qvel[:] = np.concatenate([state.linear_velocity, w_body])
        self.mocap = mocap
        if mocap:
            self.set_target(target)
        self.name = f'MuJoCo connect, solref {solref[0]:g}'

    def step(self) -> None:
        self.mujoco.mj_step(self.model, self.data)

    def set_target(self, target: Vector3) -> None:
        self.data.mocap_pos[0] = target

    def warnings(self) -> List[str]:
        """Return MuJoCo's warnings since this model was made."""
        return MUJOCO_WARNINGS[self._first_warning:]

    def read(self) -> np.ndarray:
        qpos, qvel = self.data.qpos, self.data.qvel
        q = (qpos[4], qpos[5], qpos[6], qpos[3])
        return np.concatenate([qpos[:3], q, qvel[:3], _rotate(q, qvel[3:6])])

    def timing_loop(self):
        step, model, data = self.mujoco.mj_step, self.model, self.data

        def loop(n: int) -> None:
            for _ in range(n):
                step(model, data)
        return loop

    def close(self) -> None:
        pass
