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
A robot's rigid-body model, built by Pinocchio from its URDF: what does not change as it moves.

Pinocchio (``pinocchio``, the ``pin`` wheels) parses the URDF, merges the links of fixed joints
into the link they hang from, and computes what the step needs: the joint-space mass matrix
M(q) (CRBA), gravity's and the Coriolis terms, the links' placements and Jacobians, and the
configuration's integration (a continuous joint's q is a unit complex number, a floating base's
a position and a unit quaternion). Nothing here is hand-written dynamics.

The model is Pinocchio's ``Model`` with the URDF's joint limits, damping and friction, read by
Pinocchio from ``<limit>`` and ``<dynamics>``, as ``RobotJoint`` records; ``RobotModel`` holds
them with the links' frame ids. The state that moves (q, v and the momentum) is
``robot_state.RobotState``; Pinocchio's ``Data``, its scratch space, belongs to the simulation.
"""

import math
from typing import Dict, NamedTuple, Optional, Sequence, Tuple

import numpy as np
import pinocchio

from .algebra import Quaternion, Vector3

FIXED_BASE = 'fixed'
FLOATING_BASE = 'floating'
BASES = (FIXED_BASE, FLOATING_BASE)


class RobotJoint(NamedTuple):
    """
    One moving joint: where it is in q and v, and its URDF limits and dynamics.

    :param name: the URDF joint's name (joint_states' name).
    :param q_index: its first coordinate in q (a continuous joint has two: cos and sin).
    :param v_index: its coordinate in v.
    :param kind: revolute, continuous or prismatic.
    :param lower: ``<limit lower>`` (rad or m); -inf for none.
    :param upper: ``<limit upper>``; +inf for none.
    :param velocity: ``<limit velocity>`` (rad/s or m/s); +inf for none.
    :param effort: ``<limit effort>`` (N m or N); +inf for none.
    :param damping: ``<dynamics damping>`` (N m s/rad or N s/m).
    :param friction: ``<dynamics friction>``: the Coulomb torque or force (N m or N).
    """

    name: str
    q_index: int
    v_index: int
    kind: str
    lower: float
    upper: float
    velocity: float
    effort: float
    damping: float
    friction: float

    @property
    def limited(self) -> bool:
        """Return whether the joint has position limits."""
        return math.isfinite(self.lower) or math.isfinite(self.upper)


class MimicJoint(NamedTuple):
    """A joint that follows another: q_follower = multiplier q_leader + offset."""

    follower: RobotJoint
    leader: RobotJoint
    multiplier: float
    offset: float


class RobotModel(NamedTuple):
    """
    What does not change as the robot moves: Pinocchio's model and the URDF's records.

    :param model: Pinocchio's ``Model`` (gravity is set per simulation, on its own copy).
    :param joints: the moving joints, in Pinocchio's order (depth first, as joint_states lists
        them).
    :param link_frames: each URDF link's name to its Pinocchio frame id (a link of a fixed
        joint is a frame on the link it is merged into).
    :param base: ``fixed`` or ``floating``.
    :param mass: the robot's total mass (kg).
    :param mimics: the joints that follow others (URDF ``<mimic>``).
    """

    model: pinocchio.Model
    joints: Tuple[RobotJoint, ...]
    link_frames: Dict[str, int]
    base: str
    mass: float
    mimics: Tuple[MimicJoint, ...] = ()

    @property
    def nq(self) -> int:
        """Return the size of q."""
        return self.model.nq

    @property
    def nv(self) -> int:
        """Return the size of v (the degrees of freedom)."""
        return self.model.nv

    @property
    def floating(self) -> bool:
        """Return whether the base is free (its pose and twist lead q and v)."""
        return self.base == FLOATING_BASE

    def configuration(self, positions: Sequence[float], *,
                      base: Optional[Tuple[Vector3, Quaternion]] = None) -> np.ndarray:
        """
        Return q of each moving joint's position, as ``robot_rows.joint_positions`` reads them.

        Unlike a starting state, a position is taken as it is (not brought within its limits):
        it is what was published.

        :param positions: each moving joint's position (rad or m), in ``joints`` order.
        :param base: a floating base's pose, (x y z, quaternion x y z w); None: at the origin.
        """
        if len(positions) != len(self.joints):
            raise ValueError(f'joint positions must be {len(self.joints)} numbers, got '
                             f'{len(positions)}')
        q = pinocchio.neutral(self.model)
        for joint, position in zip(self.joints, positions):
            if joint.kind == 'continuous':
                q[joint.q_index:joint.q_index + 2] = math.cos(position), math.sin(position)
            else:
                q[joint.q_index] = position
        if self.floating and base is not None:
            q[0:3], q[3:7] = base
        return q

    def with_link_at(self, q: np.ndarray, link: str, position: Vector3,
                     orientation: Quaternion,
                     data: Optional[pinocchio.Data] = None) -> np.ndarray:
        """
        Return ``q`` with its floating base moved so that ``link``'s frame is at a pose.

        The joints keep their positions; the base B becomes X L^-1 B, where L is the link's
        pose at ``q`` and X the pose asked for. A fixed base's ``q`` is returned as it is.

        :param q: the configuration.
        :param link: a link of the robot.
        :param position: where ``link``'s frame goes (m, world frame).
        :param orientation: its orientation there (x, y, z, w).
        :param data: Pinocchio's scratch space for this model (a new one if None).
        """
        if not self.floating:
            return q
        model = self.model
        data = model.createData() if data is None else data
        pinocchio.framesForwardKinematics(model, data, q)
        base = pinocchio.XYZQUATToSE3(q[0:7])
        moved = _placement(position, orientation) * data.oMf[self.link_frames[link]].inverse() \
            * base
        q = np.array(q, dtype=float)
        q[0:7] = pinocchio.SE3ToXYZQUAT(moved)
        return q

    def link_poses(self, q: np.ndarray,
                   data: Optional[pinocchio.Data] = None) -> Dict[str, Tuple[Vector3, Quaternion]]:
        """
        Return every link's pose at configuration ``q``: its frame's position and orientation.

        :param q: the configuration (``configuration``, or a state's).
        :param data: Pinocchio's scratch space for this model (a new one if None).
        :returns: each URDF link's name to (x y z (m), quaternion x y z w), world frame.
        """
        model = self.model
        data = model.createData() if data is None else data
        pinocchio.framesForwardKinematics(model, data, np.asarray(q, dtype=float))
        poses = {}
        for name, frame in self.link_frames.items():
            placement = data.oMf[frame]
            x, y, z, w = pinocchio.Quaternion(placement.rotation).coeffs()
            poses[name] = (tuple(float(c) for c in placement.translation),
                           (float(x), float(y), float(z), float(w)))
        return poses


def _placement(position: Vector3, orientation: Quaternion) -> pinocchio.SE3:
    x, y, z, w = orientation
    return pinocchio.SE3(pinocchio.Quaternion(w, x, y, z).toRotationMatrix(),
                         np.array(position, dtype=float))


def robot_model(text: str, *, base: str, base_position: Vector3 = (0.0, 0.0, 0.0),
                base_orientation: Quaternion = (0.0, 0.0, 0.0, 1.0),
                joint_kinds: Sequence[Tuple[str, str]] = (),
                mimics: Sequence[Tuple[str, str, float, float]] = ()) -> RobotModel:
    """
    Return the model of the URDF ``text``, checked beforehand (``description.robot_structure``).

    :param text: the URDF (XML).
    :param base: ``fixed``: the root link is placed at the base pose and stays; ``floating``:
        the root is free, and the base pose is where its state starts (``robot_state``).
    :param base_position: a fixed root's position in the world (m).
    :param base_orientation: a fixed root's orientation (x, y, z, w).
    :param joint_kinds: (joint name, URDF type) of the moving joints, to tell a continuous
        joint from a revolute one.
    :param mimics: (follower, leader, multiplier, offset) of each ``<mimic>`` joint: Pinocchio
        makes the follower a joint of its own, which a constraint row of the step then ties.
    """
    if base not in BASES:
        raise ValueError(f'base must be one of {", ".join(BASES)}, got {base!r}')
    try:
        if base == FLOATING_BASE:
            model = pinocchio.buildModelFromXML(text, pinocchio.JointModelFreeFlyer())
        else:
            model = pinocchio.buildModelFromXML(text)
    except (RuntimeError, ValueError) as error:
        first = str(error).strip().splitlines()[0] if str(error).strip() else type(error).__name__
        raise ValueError(f'Pinocchio could not build the robot: {first}') from None
    if base == FIXED_BASE:
        placement = _placement(base_position, base_orientation)
        for index in range(1, model.njoints):
            if model.parents[index] == 0:
                model.jointPlacements[index] = placement * model.jointPlacements[index]
        for frame in model.frames:
            if frame.parentJoint == 0 and frame.name != 'universe':
                frame.placement = placement * frame.placement
    kinds = dict(joint_kinds)
    first = 2 if base == FLOATING_BASE else 1
    joints = []
    for index in range(first, model.njoints):
        joint = model.joints[index]
        name = model.names[index]
        q, v = joint.idx_q, joint.idx_v
        kind = kinds.get(name, 'continuous' if joint.nq == 2 else 'revolute')
        lower, upper = -math.inf, math.inf
        if kind in ('revolute', 'prismatic'):
            lower, upper = float(model.lowerPositionLimit[q]), float(model.upperPositionLimit[q])
        velocity = float(model.velocityLimit[v]) or math.inf
        effort = float(model.effortLimit[v]) or math.inf
        joints.append(RobotJoint(name, q, v, kind, lower, upper, velocity, effort,
                                 float(model.damping[v]), float(model.friction[v])))
    links = {frame.name: frame_id for frame_id, frame in enumerate(model.frames)
             if frame.type == pinocchio.FrameType.BODY}
    mass = float(sum(inertia.mass for inertia in model.inertias))
    named = {joint.name: joint for joint in joints}
    tied = tuple(MimicJoint(named[follower], named[leader], float(multiplier), float(offset))
                 for follower, leader, multiplier, offset in mimics)
    return RobotModel(model, tuple(joints), links, base, mass, tied)
