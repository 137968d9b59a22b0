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
A robot dragged by the mouse constraint on any of its links: its state, target and step.

The state is the configuration q and the generalized momentum p = M(q) v. A substep h is
symplectic Euler on Hamilton's equations, the momentum first:

1. free motion: p' = p + h (C(q, v*)^T v* - g(q) - D v*), v* = M(q)^-1 p', solved by one
   fixed-point pass from M(q)^-1 p plus the last substep's change of the free motion (D: the
   joints' ``<dynamics damping>``, implicit);
   then the ``linear_damping`` and ``angular_damping`` rates, exp(-c h);
2. the rows (``robot_rows``): the mouse on its link, the position limits near their stops,
   joint friction, the speed limits and the mimic joints, on v* with M(q), solved together by
   active sets (``robot_block``; sequential impulses where no set settles); while the mouse
   pulls, no coordinate of v* moves more than ``robot_rows.MAX_JOINT_TRAVEL`` in the substep;
3. positions: q' = q (+) h v* (Pinocchio's ``integrate``; the sum where every joint's q is a
   vector space), and p' = M(q) v* kept.

The velocity-dependent term is the one that makes this conserve energy: d(M v)/dt =
tau - C v - g + dM/dt v, and dM/dt = C + C^T (Pinocchio's C), so dp/dt = tau + C^T v - g. Taken
implicitly in v*, as symplectic Euler takes the momentum, the energy of a free swing oscillates
within O(h) of its start instead of drifting. Plain semi-implicit Euler on v,
v' = v + h M^-1 (tau - C v - g), gains a fraction of the energy every swing
(docs/robots.md has the figures). As the single body's (``kernel.stagger``), a new state's
momentum is moved back half a substep first, which makes the positions second-order accurate.
"""

import math
from typing import Dict, NamedTuple, Optional, Sequence, Tuple

import numpy as np
import pinocchio

from scipy.linalg import lapack

from .mouse_joint import MouseConstraint
from .robot_model import RobotModel
from .robot_rows import (HeldSets, joint_arrays, joint_positions, LimitSettings,
                         MAX_JOINT_TRAVEL, MouseRows, prepare_rows, RowSolution, RowTable,
                         solve_rows)
from .robot_state import RobotSettings, RobotState
from .state import BodyState
from .validation import finite_vector, scalar

WORLD_ALIGNED = pinocchio.ReferenceFrame.LOCAL_WORLD_ALIGNED
# The free motion's fixed-point passes from M^-1 p where there is no last change to start from.
FIXED_POINT_PASSES = 2


class FreeChange(NamedTuple):
    """A substep's change of the velocity by the free motion: v* - M^-1 p, and the substep h."""

    h: float
    change: np.ndarray


def skew(r: np.ndarray) -> np.ndarray:
    """Return [r]x, the cross product's matrix."""
    x, y, z = r.tolist()
    return np.array(((0.0, -z, y), (z, 0.0, -x), (-y, x, 0.0)))


def returns_whole(model: pinocchio.Model, data: pinocchio.Data) -> bool:
    """
    Return whether this Pinocchio's CRBA and M^-1 come back whole, or their upper triangle only.

    Pinocchio 4 returns both triangles; earlier releases fill the upper one. Read once, at a
    configuration away from the neutral one (where a symmetric M there is symmetric everywhere:
    M(q) is analytic in q).
    """
    q = pinocchio.integrate(model, pinocchio.neutral(model),
                            np.random.default_rng(0).uniform(-1.0, 1.0, model.nv))
    mass = pinocchio.crba(model, data, q)
    inverse = pinocchio.computeMinverse(model, data, q)
    return bool(np.array_equal(mass, mass.T) and np.array_equal(inverse, inverse.T))


class RobotSimulation:
    """
    The robot, its settings, its grab and its target, advanced by ``step``.

    :param model: the robot (``robot_model``).
    :param settings: the step's settings.
    :param initial_state: where ``reset`` returns to.
    """

    def __init__(self, model: RobotModel, settings: RobotSettings,
                 initial_state: RobotState) -> None:
        """Start at ``initial_state``, nothing grabbed."""
        self.model = model
        self._data = model.model.createData()
        self._lower = np.tri(model.nv, k=-1, dtype=bool)
        self._mirrored = not returns_whole(model.model, self._data)
        # Every joint's q a vector space (no continuous joint, no floating base): Pinocchio's
        # integrate is then q + dq, the same sum in the same floating point, and the sum skips a
        # call into it a substep.
        self._additive = model.nq == model.nv
        self._joints = joint_arrays(model)
        self._damping = np.zeros(model.nv)
        self._damping[self._joints.v_index] = [joint.damping for joint in model.joints]
        self._damped = bool(self._damping.any())
        self._held: Optional[HeldSets] = None
        self._initial_state = self._checked(initial_state)
        self._settings = settings
        self._take_settings()
        self._target: Optional[np.ndarray] = None
        self._anchor: Optional[Tuple[int, np.ndarray]] = None
        self._wrench = (np.zeros(3), np.zeros(3))
        self._wrenched = False
        self._time = 0.0
        self.reset()

    # --- configuration ----------------------------------------------------------------------
    @property
    def settings(self) -> RobotSettings:
        """Return the settings in force."""
        return self._settings

    @settings.setter
    def settings(self, settings: RobotSettings) -> None:
        if not isinstance(settings, RobotSettings):
            raise ValueError(f'settings must be a RobotSettings, got {settings!r}')
        self._settings = settings
        self._take_settings()

    def _take_settings(self) -> None:
        """Take the settings' gravity, and the body damping's rate per coordinate of v."""
        self._rates = self._decay()
        self._decaying = bool(self._rates.any())
        self._limits = LimitSettings(self._settings.limit_slop, self._settings.limit_baumgarte)
        self._table: Optional[RowTable] = None
        # By substep length h: the mouse's gains and force bound, and h D.
        self._gains: Dict[float, Tuple[float, float, float]] = {}
        self._damping_matrices: Dict[float, np.ndarray] = {}
        self.model.model.gravity.linear = np.array(self._settings.gravity, dtype=float)

    def _checked(self, state: RobotState) -> RobotState:
        q = np.array(state.q, dtype=float)
        v = np.array(state.v, dtype=float)
        if q.shape != (self.model.nq,) or v.shape != (self.model.nv,):
            raise ValueError(f'a state needs q of {self.model.nq} and v of {self.model.nv} '
                             f'numbers, got {q.shape} and {v.shape}')
        if not (np.all(np.isfinite(q)) and np.all(np.isfinite(v))):
            raise ValueError('a state must be finite')
        return RobotState(pinocchio.normalize(self.model.model, q), v)

    @property
    def initial_state(self) -> RobotState:
        """Return the state that ``reset`` returns to."""
        return self._initial_state

    @initial_state.setter
    def initial_state(self, state: RobotState) -> None:
        self._initial_state = self._checked(state)

    def set_state(self, state: RobotState) -> None:
        """Replace the current state (checked; its momentum is staggered at the next step)."""
        state = self._checked(state)
        self._set_configuration(state.q)
        self._p = self._mass_matrix @ state.v
        self._v = state.v.copy()
        self._staggered = False
        self._free_change: Optional[FreeChange] = None
        if self._held is not None:
            self._held.clear()

    def reset(self) -> None:
        """Return to the initial state; drop the target and the grab's target."""
        self.set_state(self._initial_state)
        self._target = None
        self._mouse_impulse = (np.zeros(3), 1.0)
        self._tick_mouse_impulse = ((0.0, 0.0, 0.0), 0.0)
        self._tick_torque = np.zeros(self.model.nv)

    # --- inputs -------------------------------------------------------------------------------
    def grab(self, link: str, point: Sequence[float]) -> None:
        """Hold ``point`` (m, in ``link``'s frame) of ``link`` with the mouse constraint."""
        if link not in self.model.link_frames:
            raise ValueError(f'the robot has no link {link!r}')
        self._anchor = (self.model.link_frames[link], np.array(finite_vector('anchor', point)))

    @property
    def anchor(self) -> Optional[Tuple[str, Tuple[float, ...]]]:
        """Return the grabbed link's name and the point held (its frame), or None."""
        if self._anchor is None:
            return None
        frame, point = self._anchor
        return self.model.model.frames[frame].name, tuple(float(x) for x in point)

    @property
    def target(self) -> Optional[Tuple[float, ...]]:
        """Return the target the anchor is pulled to (m, world), or None."""
        return None if self._target is None else tuple(float(x) for x in self._target)

    @target.setter
    def target(self, target: Optional[Sequence[float]]) -> None:
        self._target = None if target is None else np.array(finite_vector('target', target))

    @property
    def wrench(self) -> Tuple[Tuple[float, ...], Tuple[float, ...]]:
        """Return the external force (N) and torque (N m) on the tracked link, world frame."""
        return tuple(self._wrench[0]), tuple(self._wrench[1])

    def set_wrench(self, force: Sequence[float], torque: Sequence[float],
                   link: str) -> None:
        """Apply ``force`` at ``link``'s frame origin and ``torque`` on it (world frame)."""
        if link not in self.model.link_frames:
            raise ValueError(f'the robot has no link {link!r}')
        self._wrench_frame = self.model.link_frames[link]
        self._wrench = (np.array(finite_vector('wrench force', force)),
                        np.array(finite_vector('wrench torque', torque)))
        self._wrenched = bool(self._wrench[0].any() or self._wrench[1].any())

    # --- readings -----------------------------------------------------------------------------
    @property
    def time(self) -> float:
        """Return the simulated seconds so far."""
        return self._time

    @property
    def state(self) -> RobotState:
        """Return q and v = M(q)^-1 p."""
        return RobotState(self._q.copy(), self._v.copy())

    def joint_positions(self) -> Tuple[float, ...]:
        """Return each moving joint's position (rad or m)."""
        return tuple(joint_positions(self._joints, self._q).tolist())

    def joint_velocities(self) -> Tuple[float, ...]:
        """Return each moving joint's velocity (rad/s or m/s)."""
        return tuple(self._v[self._joints.v_index].tolist())

    def joint_efforts(self) -> Tuple[float, ...]:
        """Return each joint's torque (N m or N) from the constraint rows, the last step's."""
        return tuple(self._tick_torque[self._joints.v_index].tolist())

    @property
    def tick_impulse(self) -> Tuple[Tuple[float, float, float], float]:
        """Return the mouse's impulse summed over the last step's substeps (N s), and its dt."""
        return self._tick_mouse_impulse

    @property
    def constraint_force(self) -> Tuple[float, float, float]:
        """Return the mouse constraint's force P / h of the last substep (N), world frame."""
        impulse, h = self._mouse_impulse
        return tuple(float(x) / h for x in impulse)

    def link_state(self, link: str) -> BodyState:
        """Return ``link``'s frame: pose and velocities of its origin, world frame."""
        frame = self.model.link_frames[link]
        model, data = self.model.model, self._data
        pinocchio.forwardKinematics(model, data, self._q, self._v)
        pose = pinocchio.SE3ToXYZQUAT(pinocchio.updateFramePlacement(model, data, frame))
        twist = pinocchio.getFrameVelocity(model, data, frame, WORLD_ALIGNED).vector
        x, y, z, qx, qy, qz, qw = pose.tolist()
        vx, vy, vz, wx, wy, wz = twist.tolist()
        return BodyState((x, y, z), (qx, qy, qz, qw), (vx, vy, vz), (wx, wy, wz))

    def link_placements(self) -> dict:
        """Return every link's (position, rotation matrix) in the world."""
        model, data = self.model.model, self._data
        pinocchio.framesForwardKinematics(model, data, self._q)
        return {name: (data.oMf[frame].translation.copy(), data.oMf[frame].rotation.copy())
                for name, frame in self.model.link_frames.items()}

    def link_poses(self) -> dict:
        """Return every link's (position, orientation (x, y, z, w)) in the world, as tuples."""
        return self.model.link_poses(self._q, self._data)

    def anchor_position(self) -> Optional[np.ndarray]:
        """Return the anchor's world position, or None when nothing is grabbed."""
        if self._anchor is None:
            return None
        frame, point = self._anchor
        pinocchio.framesForwardKinematics(self.model.model, self._data, self._q)
        return self._data.oMf[frame].act(point)

    def energy(self) -> float:
        """Return the robot's energy: kinetic plus gravity's potential (J)."""
        model, data = self.model.model, self._data
        v = self._v
        return float(pinocchio.computeKineticEnergy(model, data, self._q, v)
                     + pinocchio.computePotentialEnergy(model, data, self._q))

    # --- the step -----------------------------------------------------------------------------
    def _coriolis_rate(self, q: np.ndarray, v: np.ndarray) -> np.ndarray:
        """Return C(q, v)^T v, the velocity-dependent part of dp/dt."""
        return v.dot(pinocchio.computeCoriolisMatrix(self.model.model, self._data, q, v))

    def _load(self, q: np.ndarray) -> np.ndarray:
        """Return -dp/dt's part that depends on q alone: g(q) - the wrench's torques."""
        model, data = self.model.model, self._data
        load = pinocchio.computeGeneralizedGravity(model, data, q)
        if self._wrenched:
            force, torque = self._wrench
            pinocchio.computeJointJacobians(model, data, q)
            jacobian = pinocchio.getFrameJacobian(model, data, self._wrench_frame, WORLD_ALIGNED)
            load = load - jacobian.T @ np.concatenate((force, torque))
        return load

    def step(self, dt: float) -> RobotState:
        """Advance ``dt`` seconds in ``settings.substeps`` substeps; return the new state."""
        self.advance(dt)
        return self.state

    def advance(self, dt: float) -> None:
        """Advance ``dt`` seconds in ``settings.substeps`` substeps."""
        if type(dt) is not float or not 0.0 < dt <= 1.0:  # a float within (0, 1] is checked
            dt = scalar('dt', dt, above=0.0, at_most=1.0)
        settings = self._settings
        h = dt / settings.substeps
        if not self._staggered:
            q, v = self._q, self._v
            rate = self._coriolis_rate(q, v) - self._load(q) - self._damping * v
            self._p = self._p - 0.5 * h * rate
            self._v = self._inverse_mass.dot(self._p)
            self._staggered = True
        solution = self._substep(h)
        torque_sum, mouse_sum = solution.joint_impulse, solution.mouse_impulse
        for _ in range(settings.substeps - 1):
            solution = self._substep(h)
            torque_sum = torque_sum + solution.joint_impulse
            mouse_sum = mouse_sum + solution.mouse_impulse
        self._tick_mouse_impulse = (tuple(mouse_sum.tolist()), dt)
        self._tick_torque = torque_sum / dt
        self._time += dt

    def _decay(self) -> np.ndarray:
        """Return the body damping's rate per coordinate of v (1/s)."""
        settings = self._settings
        rates = np.zeros(self.model.nv)
        if self.model.floating:
            rates[0:3] = settings.linear_damping
            rates[3:6] = settings.angular_damping
        for joint in self.model.joints:
            rates[joint.v_index] = settings.linear_damping if joint.kind == 'prismatic' \
                else settings.angular_damping
        return rates

    def _set_configuration(self, q: np.ndarray) -> None:
        """Move to ``q``: M(q) and its inverse with it, whole."""
        self._q = q
        model, data = self.model.model, self._data
        # M by the CRBA, and M^-1 by Pinocchio's articulated-body recursion: one call instead of
        # factoring M. Where Pinocchio fills their upper triangle only, it is mirrored.
        mass = pinocchio.crba(model, data, q).copy()
        inverse = pinocchio.computeMinverse(model, data, q).copy()
        if self._mirrored:
            np.copyto(mass, mass.T, where=self._lower)
            np.copyto(inverse, inverse.T, where=self._lower)
        self._mass_matrix, self._inverse_mass = mass, inverse

    def _substep_damping(self, h: float) -> np.ndarray:
        """Return h D, the joints' damping over a substep, as a diagonal matrix."""
        matrix = self._damping_matrices.get(h)
        if matrix is None:
            matrix = self._damping_matrices[h] = np.diag(h * self._damping)
        return matrix

    def _free_velocity(self, h: float) -> np.ndarray:
        """
        Return v* of the free motion: p + h (C(q, v*)^T v* - g - D v*) = M v*, by fixed point.

        One pass, from M^-1 p plus the last substep's change of the free motion (which varies
        smoothly: the rows act after it): that guess is within O(h^2) of v*, and one pass from
        it within O(h^3), as two passes from M^-1 p are; one pass from M^-1 p alone is O(h^2)
        off, and the swing's energy drifts. Two passes from M^-1 p where there is no last change
        (a new state, a new h). With joint damping D
        the system M + h D is solved (Cholesky, LAPACK through SciPy), else M^-1 applies.
        """
        q, start = self._q, self._v
        last = self._free_change
        if last is not None and last.h == h:
            v, passes = start + last.change, 1
        else:
            v, passes = start, FIXED_POINT_PASSES
        load = self._load(q) if self._wrenched else pinocchio.computeGeneralizedGravity(
            self.model.model, self._data, q)
        pushed = self._p - h * load
        damped = self._damped
        if damped:
            damped_mass = self._mass_matrix + self._substep_damping(h)
        for _ in range(passes):
            momentum = pushed + h * self._coriolis_rate(q, v)
            if not damped:
                v = self._inverse_mass.dot(momentum)
                continue
            _, v, info = lapack.dposv(damped_mass, momentum)
            if info != 0:  # M + h D is positive definite: only a broken M gets here
                v = np.linalg.solve(damped_mass, momentum)
        self._free_change = FreeChange(h, v - start)
        return v

    def _substep(self, h: float) -> RowSolution:
        # 1. free motion: the momentum, implicit in the velocity it moves the positions with.
        v = self._free_velocity(h)
        if self._decaying:
            v = v * np.exp(-self._rates * h)
        # 2. the rows, on v with M(q).
        q = self._q
        table = self._table
        if table is None or table.h != h:
            table = self._table = RowTable(self._joints, self.model.nv, h, self._limits)
            self._held = HeldSets(table.first_guess)
        mouse = None if self._target is None else self._mouse_rows(q, h)
        rows = prepare_rows(table, q, v, mouse)
        solution = solve_rows(v, rows, self._inverse_mass, self._settings.iterations, h,
                              self._held)
        self._mouse_impulse = (solution.mouse_impulse, h)
        if rows.mouse_rows:
            # The mouse pulls on: no coordinate of v may move more than the travel a substep.
            travel = h * float(np.abs(v).max())
            if travel > MAX_JOINT_TRAVEL:
                v *= MAX_JOINT_TRAVEL / travel
        # 3. positions, and the momentum carried at the new configuration.
        self._p = self._mass_matrix.dot(v)
        step = h * v
        self._set_configuration(q + step if self._additive
                                else pinocchio.integrate(self.model.model, q, step))
        self._v = self._inverse_mass.dot(self._p)
        return solution

    def _mouse_rows(self, q: np.ndarray, h: float) -> Optional[MouseRows]:
        """Return the mouse's rows at ``q``, or None when it holds nothing or has no target."""
        if self._target is None or self._anchor is None:
            return None
        model, data = self.model.model, self._data
        frame, point = self._anchor
        pinocchio.computeJointJacobians(model, data, q)
        placement = pinocchio.updateFramePlacement(model, data, frame)
        lever = placement.rotation.dot(point)
        jacobian6 = pinocchio.getFrameJacobian(model, data, frame, WORLD_ALIGNED)
        jacobian = jacobian6[:3] - skew(lever).dot(jacobian6[3:])
        error = placement.translation + lever - self._target
        return MouseRows(jacobian, error, *self._mouse_gains(h))

    def _mouse_gains(self, h: float) -> Tuple[float, float, float]:
        """Return the mouse's a, b (``MouseConstraint.gains``) and h F_max for substeps of h."""
        gains = self._gains.get(h)
        if gains is None:
            a, b = self._settings.constraint.gains(h)
            gains = self._gains[h] = (a, b, h * self.force_bound())
        return gains

    def force_bound(self) -> float:
        """Return the bound on the constraint force (N): max_force and max_force_per_weight."""
        constraint: MouseConstraint = self._settings.constraint
        if math.isinf(constraint.max_force_per_weight):
            return constraint.max_force
        weight = self.model.mass * (float(np.linalg.norm(self._settings.gravity)) or 9.80665)
        return min(constraint.max_force, constraint.max_force_per_weight * weight)
