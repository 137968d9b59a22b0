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
One rigid body dragged by the mouse constraint: its state, target and the fixed-size step.

A call to ``MouseSimulation.step(dt)`` advances ``dt`` in ``substeps`` equal substeps h. Each
substep is symplectic Euler, as Box2D and Bounce order it:

1. velocities: gravity and the wrench (F / m, I_w^-1 tau), exponential damping, then the
   gyroscopic term w x (I w) by one implicit Newton step in the body frame;
2. the mouse constraint, when there is a target: the net impulse P = -K^-1 (a J V + b C) with
   |P| <= h F_max (``mouse_joint``, seed eqs. 1.1-1.10), applied as v += P / m and
   w += I_w^-1 (r x P); its position part may turn the body by at most ``MAX_CORRECTION_TURN``;
3. the floor, when a point of the body (a box's corner, a hull's vertex) is within its
   margin: sequential impulses on those points (``floor_contact.solve``), whose split
   impulses give the velocity that moves the positions;
4. positions: x += h v and the orientation rotated by w h, renormalized; a free body's by its
   gyroscopic step's own turn instead (``gyroscopic.free_rotation``), which keeps its world L.

Stages 1-2 are ``kernel.velocities``, 3-4 ``step``, on what ``step_plan`` prepared once per
settings and substep: plain floats, deterministic to the bit.
"""

import math
from typing import Optional, Tuple

from .algebra import Vector3
from .floor_contact import contact_points, solve as solve_floor, touching
from .kernel import stagger, velocities, ZERO
from .limits import MAX_STEP
from .settings import Settings
from .state import BodyState
from .step_plan import step_plan, StepPlan
from .target_motion import Guide, pull_point
from .target_stream import TargetStream
from .validation import finite_vector, scalar


class MouseSimulation:
    """
    The body, its settings and its target, advanced by ``step``.

    No target means a free body; the target can be set, moved, jumped or cleared between any two
    steps. Invalid settings or inputs raise ValueError and change nothing.
    """

    def __init__(self, settings: Settings, initial_state: BodyState = BodyState()) -> None:
        """Start at ``initial_state`` with no target."""
        initial_state = initial_state.validated()
        if isinstance(settings, Settings):
            settings.floor.check_state(initial_state.position, initial_state.orientation)
        self._initial_state = initial_state
        self.settings = settings
        self._state = self._initial_state
        self._target: Optional[Vector3] = None
        # The last substep's impulse P and its h: the constraint force P / h, divided when read.
        self._impulse: Tuple[Vector3, float] = (ZERO, 1.0)
        # The last step's impulse summed over its substeps, and its dt.
        self._tick_impulse: Tuple[Vector3, float] = (ZERO, 0.0)
        self._wrench: Tuple[Vector3, Vector3] = (ZERO, ZERO)
        self._friction_torque = 0.0
        # Simulated time (s): the sum of the steps taken; targets' arrival times are on it.
        self._time = 0.0
        self._stream = TargetStream()
        # The bounded-slew point the joint pulls to (None: not started, or no guide).
        self._guide: Optional[Guide] = None
        # False until the velocities of a given state have been moved back half a substep.
        self._staggered = False
        # The prepare stage of the steps (``step_plan``), made again when settings or h change.
        self._plan: Optional[StepPlan] = None
        # The last substep's floor contacts (the next substep's warm start), and the COM they
        # were measured from.
        self._contacts: list = []
        self._contact_origin: Vector3 = ZERO

    @property
    def settings(self) -> Settings:
        """Return the settings in force."""
        return self._settings

    @settings.setter
    def settings(self, settings: Settings) -> None:
        if not isinstance(settings, Settings):
            raise ValueError(f'settings must be a Settings, got {settings!r}')
        state = self._initial_state
        settings.floor.check_state(state.position, state.orientation)
        previous = getattr(self, '_settings', None)
        self._settings = settings
        if previous is not None and previous.constraint.anchor != settings.constraint.anchor:
            # A new anchor (a grab) is picked up where it is, as after a release: the old
            # anchor's guide would pull the new point to where the old one was.
            self._guide = None

    @property
    def state(self) -> BodyState:
        """Return the current state."""
        return self._state

    @property
    def initial_state(self) -> BodyState:
        """Return the state that ``reset`` returns to."""
        return self._initial_state

    @initial_state.setter
    def initial_state(self, state: BodyState) -> None:
        state = state.validated()
        self._settings.floor.check_state(state.position, state.orientation)
        self._initial_state = state

    @property
    def contacts(self) -> Tuple[Tuple[Vector3, float], ...]:
        """Return the last substep's contacts: (corner (m, at its start), normal impulse (N s))."""
        return tuple((point, impulse) for _, point, impulse
                     in contact_points(self._contact_origin, self._contacts))

    @property
    def contact_count(self) -> int:
        """Return how many of the body's points touched the floor in the last substep."""
        return len(self._contacts)

    @property
    def target(self) -> Optional[Vector3]:
        """Return the mouse position x_mouse in the world frame, or None for a free body."""
        return self._target

    @target.setter
    def target(self, target: Optional[Vector3]) -> None:
        self.set_target(target)

    def set_target(self, target: Optional[Vector3], *, time: Optional[float] = None,
                   stamped: bool = False) -> None:
        """
        Set the target at ``time`` (s of simulated time): its arrival, or its stamp if stamped.

        Timed targets form a stream whose velocity the joint follows with
        ``TargetMotion.feed_forward``, the stream's only reader: without it, a target is a jump
        (unfitted), as one without a time (``target = point``) is. None frees the body. A
        stamped target arrived now (``TargetStream``).
        """
        if target is None:
            self._target = self._guide = None
            self._stream.clear()
            return
        target = finite_vector('target', target)
        time = None if time is None or not self._settings.target_motion.feed_forward \
            else scalar('time', time)
        self._target = target
        self._stream.add(target, time, self._settings.target_motion.max_speed,
                         self._time if stamped else None)

    def shift_target_times(self, seconds: float) -> None:
        """Move the times of the targets taken so far by ``seconds`` (the core's clock moved)."""
        self._stream.shift(seconds)

    @property
    def time(self) -> float:
        """Return the simulated seconds so far: the sum of every step's dt."""
        return self._time

    @property
    def joint_target(self) -> Optional[Vector3]:
        """Return where the joint pulls the anchor now: the guide, or else the target."""
        if self._target is None:
            return None
        return self._target if self._guide is None else self._guide.position

    @property
    def target_velocity(self) -> Vector3:
        """Return the velocity estimated from the stream of timed targets (m/s)."""
        return self._stream.velocity

    @property
    def friction_torque(self) -> float:
        """Return the norm of the angular friction's torque in the last substep (N m)."""
        return self._friction_torque

    @property
    def wrench(self) -> Tuple[Vector3, Vector3]:
        """Return the external (force (N) through the COM, torque (N m)), world frame."""
        return self._wrench

    @wrench.setter
    def wrench(self, wrench: Tuple[Vector3, Vector3]) -> None:
        force, torque = wrench
        self._wrench = (finite_vector('wrench force', force),
                        finite_vector('wrench torque', torque))

    @property
    def constraint_force(self) -> Vector3:
        """Return the constraint force P / h of the last substep (N), zero without a target."""
        (ix, iy, iz), h = self._impulse
        return (ix / h, iy / h, iz / h)

    @property
    def tick_impulse(self) -> Tuple[Vector3, float]:
        """
        Return the last step's joint impulse summed over its substeps (N s), and its dt (s).

        What the joint gave the momentum, feed-forward and bound included: without damping,
        floor or start (``kernel.stagger``), m (v' - v) = sum P + (m g + F_wrench) dt exactly.
        """
        return self._tick_impulse

    def anchor_position(self) -> Vector3:
        """Return the anchor's world position x + R r_local."""
        return self._state.world_point(self._settings.constraint.anchor)

    def anchor_error(self) -> Optional[Vector3]:
        """Return C = x + r - x_mouse (eq. 1.1), or None without a target."""
        if self._target is None:
            return None
        a, t = self.anchor_position(), self._target
        return (a[0] - t[0], a[1] - t[1], a[2] - t[2])

    def configure(self, settings: Settings, initial_state: BodyState) -> None:
        """
        Replace the settings and the initial state together, checked as a pair.

        The initial state must suit the new settings' floor, whatever the old ones were; raise
        ValueError and change nothing otherwise.
        """
        if not isinstance(settings, Settings):
            raise ValueError(f'settings must be a Settings, got {settings!r}')
        initial_state = initial_state.validated()
        settings.floor.check_state(initial_state.position, initial_state.orientation)
        self._initial_state = initial_state
        self.settings = settings

    def set_state(self, state: BodyState) -> None:
        """Replace the current state (validated; the orientation is normalized)."""
        self._state = state.validated()
        self._staggered = False
        self._guide = None
        self._contacts = []

    def reset(self) -> None:
        """Return to the initial state and drop the target."""
        self._state = self._initial_state
        self._staggered = False
        self._target = None
        self._stream.clear()
        self._guide = None
        self._impulse = (ZERO, 1.0)
        self._tick_impulse = (ZERO, 0.0)
        self._friction_torque = 0.0
        self._contacts = []

    def kinetic_energy(self) -> float:
        """Return the body's kinetic energy (J)."""
        s, body = self._state, self._settings.body
        return body.kinetic_energy(s.linear_velocity, body.body_rate(s.orientation,
                                                                     s.angular_velocity))

    def angular_momentum(self) -> Vector3:
        """Return the angular momentum about the COM in the world frame (kg m^2/s)."""
        return self._settings.body.angular_momentum(self._state.orientation,
                                                    self._state.angular_velocity)

    def step(self, dt: float) -> BodyState:
        """Advance ``dt`` seconds in ``settings.substeps`` equal substeps; return the new state."""
        if type(dt) is not float or not 0.0 < dt <= MAX_STEP:
            # The check and its message; a float in range (every call of a running node) is
            # taken as it is, which is what the check would return.
            dt = scalar('dt', dt, above=0.0, at_most=MAX_STEP)
        settings = self._settings
        substeps = settings.substeps
        h = dt / substeps
        plan = self._plan
        if plan is None or plan.settings is not settings or plan.h != h:
            plan = self._plan = step_plan(settings, dt)  # checks h against MIN_STEP
        if not self._staggered:
            # The velocities of a new state move back half a substep, once (``kernel.stagger``).
            start = self._target if self._guide is None else self._guide.position
            self._state, self._friction_torque = stagger(
                settings, self._state, start, self._wrench, self._friction_torque, h)
            self._staggered = True
        cached = plan.coefficients
        wrench = self._wrench
        friction_torque = self._friction_torque
        floor = plan.floor
        (px, py, pz), q, v, w = self._state
        time = self._time
        # Decided once per step: a joint without a guide or feed-forward pulls at the target
        # itself, taken as still, in every substep (what ``pull_point`` returns for it).
        target = self._target
        moving = target is not None and plan.moving_target
        joint = None if target is None else (target, None)
        if target is not None and not moving:
            self._guide = None
        sum_x = sum_y = sum_z = 0.0
        for index in range(substeps):
            if moving:
                joint, self._guide = pull_point(
                    self._target, settings.target_motion, self._stream, self._guide,
                    settings.constraint.anchor, ((px, py, pz), q, v, w), time + index * h, h)
            touch = floor is not None and touching(floor, pz, q)
            v, w, impulse, friction_torque, turn = velocities(
                px, py, pz, q, v, w, h, cached, joint, wrench, friction_torque, touch)
            sum_x += impulse[0]
            sum_y += impulse[1]
            sum_z += impulse[2]
            if touch:
                body = settings.body
                origin = self._contact_origin = (px, py, pz)
                v, w, (v_move, w_move), self._contacts = solve_floor(
                    floor, origin, q, v, w, h, inverse_mass=body.inverse_mass,
                    inertia=body.inertia, inverse_inertia=body.inverse_inertia,
                    gravity=settings.gravity, warm=self._contacts)
            else:
                v_move, w_move = v, w
                if self._contacts:
                    self._contacts = []
            vx, vy, vz = v_move
            px += h * vx
            py += h * vy
            pz += h * vz
            # q = algebra.integrate_orientation(q, w, h), written out: called every substep,
            # the call and its tuples cost a tenth of the substep.
            if turn is None:
                wx, wy, wz = w_move
                speed = math.sqrt(wx * wx + wy * wy + wz * wz)
                half_angle = 0.5 * speed * h
                if half_angle < 1e-4:
                    scale = 0.5 * h * (1.0 - half_angle * half_angle / 6.0)
                else:
                    scale = math.sin(half_angle) / speed
                c = math.cos(half_angle)
                dx, dy, dz = wx * scale, wy * scale, wz * scale
            else:
                # A free body's own turn (``kernel.velocities``).
                dx, dy, dz, c = turn
            x, y, z, qw = q
            nx = c * x + dx * qw + dy * z - dz * y
            ny = c * y - dx * z + dy * qw + dz * x
            nz = c * z + dx * y - dy * x + dz * qw
            nw = c * qw - dx * x - dy * y - dz * z
            inv_norm = 1.0 / math.sqrt(nx * nx + ny * ny + nz * nz + nw * nw)
            q = (nx * inv_norm, ny * inv_norm, nz * inv_norm, nw * inv_norm)
        self._state = BodyState._make(((px, py, pz), q, v, w))
        self._impulse = (impulse, h)
        self._tick_impulse = ((sum_x, sum_y, sum_z), dt)
        self._friction_torque = friction_torque
        self._time = time + dt
        return self._state
