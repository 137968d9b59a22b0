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
One rigid body dragged by the mouse constraint: settings, target and the fixed-size step.

A call to ``MouseSimulation.step(dt)`` advances ``dt`` in ``substeps`` equal substeps h. Each
substep is symplectic Euler, as Box2D and Bounce order it:

1. velocities: gravity and the external wrench's force F / m, then its torque's
   I_w^-1 tau, then exponential damping, then the gyroscopic term w x (I w) by one implicit
   Newton step in the body frame (``body.gyroscopic_step``);
2. the mouse constraint, when there is a target: the net impulse P = -K^-1 (a J V + b C) with
   |P| <= h F_max (``constraint`` module, seed eqs. 1.1-1.10), applied as v += P / m and
   w += I_w^-1 (r x P); its position part -K^-1 b C may turn the body by at most
   ``MAX_CORRECTION_TURN`` per substep;
3. positions: x += h v and the orientation rotated by w h, renormalized.

Everything is plain float arithmetic, deterministic to the bit for the same inputs.
"""

from dataclasses import dataclass
import math
from typing import Optional, Tuple

from .algebra import (cholesky, multiply, multiply_symmetric,
                      multiply_transposed, rotation_matrix, solve_cholesky, Vector3)
from .body import RigidBody
from .gyroscopic import gyroscopic_step, gyroscopic_step_diagonal
from .limits import MAX_ACCELERATION, MAX_CONDITION, MAX_STEP, MIN_STEP
from .mouse_joint import effective_mass, MouseConstraint
from .state import BodyState
from .target_motion import Guide, TargetMotion, TargetStream
from .validation import finite_vector, norm, scalar, shown

STANDARD_GRAVITY: Vector3 = (0.0, 0.0, -9.80665)
# The most a substep's position correction may turn the body (rad). The impulse is solved for
# the linearized constraint, which holds while the body turns little in a substep; a far target
# on a long lever arm would otherwise ask for a turn of radians per substep, the linear step
# would miss, and the missed error would pump energy in. Only corrections of large errors meet
# the limit; they then close at this turn per substep instead of at delta per substep.
MAX_CORRECTION_TURN = 0.2
# The leapfrog start kicks a soft spring back by its own acceleration only while the step
# resolves it (2 zeta omega h and (omega h)^2 below this); a stiffer one is started like rigid
# mode, since a first-order kick of a spring that settles within a step adds energy. Likewise
# damping: undone over h / 2 only while its rate times h is below this.
STIFF_START = 0.5
ZERO: Vector3 = (0.0, 0.0, 0.0)


@dataclass(frozen=True)
class Settings:
    """
    Everything the step depends on apart from the state and the target; replaced as a whole.

    :param body: mass and inertia.
    :param constraint: anchor and how stiffly it follows the target.
    :param gravity: gravitational acceleration in the world frame (m/s^2), of norm at most
        MAX_ACCELERATION (see ``limits``).
    :param linear_damping: rate c (1/s): v decays as exp(-c t) whatever the step size. Any
        rate >= 0 is valid: the factor exp(-c h) lies in [0, 1] and c h cannot overflow.
    :param angular_damping: the same for the angular velocity.

    The body and the constraint's anchor must suit each other: see ``check_lever``.
    :param substeps: equal substeps per ``step`` call (>= 1).
    :param target_motion: how the target handed to the joint moves (``target_motion``): the
        default hands the target over as given, with zero velocity (the seed's joint).
    """

    body: RigidBody
    constraint: MouseConstraint = MouseConstraint()
    gravity: Vector3 = STANDARD_GRAVITY
    linear_damping: float = 0.0
    angular_damping: float = 0.0
    substeps: int = 1
    target_motion: TargetMotion = TargetMotion()

    def __post_init__(self) -> None:
        """Validate every field; raise ValueError naming the first invalid one."""
        if not isinstance(self.body, RigidBody):
            raise ValueError(f'body must be a RigidBody, got {shown(self.body)}')
        if not isinstance(self.constraint, MouseConstraint):
            raise ValueError(f'constraint must be a MouseConstraint, got {shown(self.constraint)}')
        check_lever(self.body, self.constraint.anchor)
        gravity = finite_vector('gravity', self.gravity)
        if norm(gravity) > MAX_ACCELERATION:
            raise ValueError(
                f'gravity must be at most {MAX_ACCELERATION:g} m/s^2 (about the surface '
                f'gravity of a neutron star), got {shown(gravity)} of norm {norm(gravity):g}: '
                'beyond, the velocities it gives leave what the step keeps finite')
        object.__setattr__(self, 'gravity', gravity)
        object.__setattr__(self, 'linear_damping',
                           scalar('linear_damping', self.linear_damping, at_least=0.0))
        object.__setattr__(self, 'angular_damping',
                           scalar('angular_damping', self.angular_damping, at_least=0.0))
        if isinstance(self.substeps, bool) or not isinstance(self.substeps, int) \
                or self.substeps < 1:
            raise ValueError(f'substeps must be an integer >= 1, got {shown(self.substeps)}')
        if not isinstance(self.target_motion, TargetMotion):
            raise ValueError(
                f'target_motion must be a TargetMotion, got {shown(self.target_motion)}')


def check_lever(body: RigidBody, anchor: Vector3, *, body_name: str = 'body of mass') -> None:
    """
    Raise ValueError naming ``anchor`` if the effective mass K is too ill-conditioned to solve.

    K = m^-1 I3 + [r]x I_w^-1 [r]x^T has the eigenvalue 1 / m along r and at most
    1 / m + |r|^2 / I_min across it, in any orientation: its condition number is at most
    1 + m |r|^2 / I_min, which must not exceed MAX_CONDITION (see ``limits``). A point farther out
    would be held by a K that rounding makes singular, and its Cholesky factor would fail.

    :param body: the body.
    :param anchor: the anchor in the body frame (m).
    :param body_name: what the message calls the body, before its mass (naming the parameters
        its mass and inertia came from).
    """
    moments = body.principal_moments
    lever = norm(anchor)
    condition = 1.0 + body.mass * (lever / moments[0]) * lever
    if condition > MAX_CONDITION:
        reach = math.sqrt((MAX_CONDITION - 1.0) * moments[0] / body.mass)
        raise ValueError(
            f'anchor {shown(anchor)} is {lever:g} m from the COM, too far for the {body_name} '
            f'{body.mass:g} kg (smallest principal moment {moments[0]:g} kg m^2): the '
            f'effective mass K would have condition number {condition:g} > {MAX_CONDITION:g} '
            f'(1 + m |anchor|^2 / I_min), too ill-conditioned to solve; at most {reach:g} m')


class MouseSimulation:
    """
    The body, its settings and its target, advanced by ``step``.

    No target means a free body; the target can be set, moved, jumped or cleared between any two
    steps. Invalid settings or inputs raise ValueError and change nothing.
    """

    def __init__(self, settings: Settings, initial_state: BodyState = BodyState()) -> None:
        """Start at ``initial_state`` with no target."""
        self.settings = settings
        self._initial_state = initial_state.validated()
        self._state = self._initial_state
        self._target: Optional[Vector3] = None
        # The last substep's impulse P and its h: the constraint force P / h, divided when read.
        self._impulse: Tuple[Vector3, float] = (ZERO, 1.0)
        self._wrench: Tuple[Vector3, Vector3] = (ZERO, ZERO)
        self._friction_torque = 0.0
        # Simulated time (s): the sum of the steps taken; targets' arrival times are on it.
        self._time = 0.0
        self._stream = TargetStream()
        # The bounded-slew point the joint pulls to (None: not started, or no guide).
        self._guide: Optional[Guide] = None
        # False until the velocities of a given state have been moved back half a substep.
        self._staggered = False
        self._cache_for: Tuple[Optional[Settings], float] = (None, 0.0)
        self._cache: Tuple[float, ...] = ()
        # Whether the cached settings move the joint's target (a guide or feed-forward).
        self._moving_target = False

    @property
    def settings(self) -> Settings:
        """Return the settings in force."""
        return self._settings

    @settings.setter
    def settings(self, settings: Settings) -> None:
        if not isinstance(settings, Settings):
            raise ValueError(f'settings must be a Settings, got {settings!r}')
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
        self._initial_state = state.validated()

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
        Set the target, which arrived at ``time`` (s of simulated time, see ``time``).

        Timed targets form a stream whose velocity the joint follows with
        ``TargetMotion.feed_forward``; a target without a time (as ``target = point`` sets)
        is a jump. None frees the body. With ``stamped``, ``time`` is when the target was
        there (its stamp, in simulated time) and it arrived now: the stream is fitted on the
        stamps (``TargetStream``).
        """
        if target is None:
            self._target = None
            self._stream.clear()
            self._guide = None
            return
        target = finite_vector('target', target)
        if time is not None:
            time = scalar('time', time)
        self._target = target
        self._stream.add(target, time, self._settings.target_motion.max_speed,
                         self._time if stamped else None)

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

    def anchor_position(self) -> Vector3:
        """Return the anchor's world position x + R r_local."""
        return self._state.world_point(self._settings.constraint.anchor)

    def anchor_error(self) -> Optional[Vector3]:
        """Return C = x + r - x_mouse (eq. 1.1), or None without a target."""
        if self._target is None:
            return None
        a, t = self.anchor_position(), self._target
        return (a[0] - t[0], a[1] - t[1], a[2] - t[2])

    def set_state(self, state: BodyState) -> None:
        """Replace the current state (validated; the orientation is normalized)."""
        self._state = state.validated()
        self._staggered = False
        self._guide = None

    def reset(self) -> None:
        """Return to the initial state and drop the target."""
        self._state = self._initial_state
        self._staggered = False
        self._target = None
        self._stream.clear()
        self._guide = None
        self._impulse = (ZERO, 1.0)
        self._friction_torque = 0.0

    def kinetic_energy(self) -> float:
        """Return the body's kinetic energy (J)."""
        s = self._state
        rotation = rotation_matrix(s.orientation)
        w_body = multiply_transposed(s.angular_velocity, rotation)
        return self._settings.body.kinetic_energy(s.linear_velocity, w_body)

    def angular_momentum(self) -> Vector3:
        """Return the angular momentum about the COM in the world frame (kg m^2/s)."""
        s = self._state
        rotation = rotation_matrix(s.orientation)
        w_body = multiply_transposed(s.angular_velocity, rotation)
        return multiply(multiply_symmetric(w_body, self._settings.body.inertia), rotation)

    def step(self, dt: float) -> BodyState:
        """Advance ``dt`` seconds in ``settings.substeps`` equal substeps; return the new state."""
        if type(dt) is not float or not 0.0 < dt <= MAX_STEP:
            # The check and its message; a float in range (every call of a running node) is
            # taken as it is, which is what the check would return.
            dt = scalar('dt', dt, above=0.0, at_most=MAX_STEP)
        settings = self._settings
        substeps = settings.substeps
        h = dt / substeps
        cached_settings, cached_h = self._cache_for
        if cached_settings is not settings or cached_h != h:
            # Checked here only: a cached h has passed.
            if h < MIN_STEP:
                raise ValueError(
                    f'dt / substeps must be >= {MIN_STEP} s, got {dt!r} / {substeps}')
            self._cache = self._coefficients(settings, h)
            self._cache_for = (settings, h)
            motion = settings.target_motion
            self._moving_target = motion.feed_forward or motion.guided
        if not self._staggered:
            self._stagger(h)
        coefficients = self._cache
        (px, py, pz), q, v, w = self._state
        velocities = self._velocities
        time = self._time
        # Decided once per step: a joint without a guide or feed-forward pulls at the target
        # itself, taken as still, in every substep (what ``_joint_target`` returns for it).
        target = self._target
        moving = target is not None and self._moving_target
        if target is None:
            joint = None
        else:
            joint = (target, None)
            if not moving:
                self._guide = None
        for index in range(substeps):
            if moving:
                joint = self._joint_target(px, py, pz, q, v, w, time + index * h, h)
            v, w, impulse = velocities(px, py, pz, q, v, w, h, coefficients, joint)
            vx, vy, vz = v
            px += h * vx
            py += h * vy
            pz += h * vz
            # q = algebra.integrate_orientation(q, w, h), written out: called every substep,
            # the call and its tuples cost a tenth of the substep.
            wx, wy, wz = w
            speed = math.sqrt(wx * wx + wy * wy + wz * wz)
            half_angle = 0.5 * speed * h
            if half_angle < 1e-4:
                scale = 0.5 * h * (1.0 - half_angle * half_angle / 6.0)
            else:
                scale = math.sin(half_angle) / speed
            c = math.cos(half_angle)
            dx, dy, dz = wx * scale, wy * scale, wz * scale
            x, y, z, qw = q
            nx = c * x + dx * qw + dy * z - dz * y
            ny = c * y - dx * z + dy * qw + dz * x
            nz = c * z + dx * y - dy * x + dz * qw
            nw = c * qw - dx * x - dy * y - dz * z
            inv_norm = 1.0 / math.sqrt(nx * nx + ny * ny + nz * nz + nw * nw)
            q = (nx * inv_norm, ny * inv_norm, nz * inv_norm, nw * inv_norm)
        self._state = BodyState._make(((px, py, pz), q, v, w))
        self._impulse = (impulse, h)
        self._time = time + dt
        return self._state

    def _joint_target(self, px: float, py: float, pz: float, q, v: Vector3, w: Vector3,
                      time: float, h: float) -> Optional[Tuple[Vector3, Optional[Vector3]]]:
        """
        Return the point the joint pulls to over the substep from ``time``, and its velocity.

        The velocity is None unless the settings feed it forward. With a guide the point is the
        guide's position at ``time`` and the velocity the one that carries it over the substep,
        so that a rigid joint's error still decays as (1 - delta) per substep.
        """
        target = self._target
        if target is None:
            return None
        motion = self._settings.target_motion
        stream = self._stream
        if motion.feed_forward and stream.has_points():
            goal, goal_velocity = stream.predict(time)
        else:
            goal, goal_velocity = target, ZERO
        if not motion.guided:
            self._guide = None
            return goal, (goal_velocity if motion.feed_forward else None)
        guide = self._guide
        if guide is None:
            # Picked up where the anchor is, moving as it moves (within the speed bound).
            rx, ry, rz = multiply(self._settings.constraint.anchor, rotation_matrix(q))
            ux, uy, uz = (v[0] + w[1] * rz - w[2] * ry, v[1] + w[2] * rx - w[0] * rz,
                          v[2] + w[0] * ry - w[1] * rx)
            speed = math.sqrt(ux * ux + uy * uy + uz * uz)
            if speed > motion.max_speed:
                ux, uy, uz = (c * motion.max_speed / speed for c in (ux, uy, uz))
            guide = self._guide = Guide((px + rx, py + ry, pz + rz), (ux, uy, uz))
        position = guide.position
        guide.advance(goal, goal_velocity, h, motion.max_speed, motion.max_acceleration)
        return position, (guide.velocity if motion.feed_forward else None)

    def _stagger(self, h: float) -> None:
        """
        Move the velocities of a state given at time t back to t - h / 2, once, before stepping.

        Symplectic Euler is the leapfrog scheme with velocities at half steps: x(t + h) =
        x(t) + h v(t + h / 2). A state given with v(t), such as a body released at rest, starts
        it half a step out of phase, an O(h) error for the whole motion (0.164 mm RMS for the
        corner pendulum released 20 deg from hanging, 5 s at 1 kHz); starting from v(t - h / 2)
        makes it O(h^2) (0.021 mm; both printed by ``python -m bench.physics_figures``). The
        velocity stage is run backwards over h / 2 for that: gravity, damping, the gyroscopic
        term (the midpoint rule is time-symmetric, so the energy is kept) and the constraint's
        reaction, with soft mode's spring; rigid mode's Baumgarte correction is numerical and
        is left out. The published velocities are then the half-step ones, which are exactly
        the finite differences of the published poses.
        """
        (px, py, pz), q, v, w = self._state
        target = self._target if self._guide is None else self._guide.position
        joint = None if target is None else (target, None)
        v, w, _ = self._velocities(px, py, pz, q, v, w, -0.5 * h,
                                   self._coefficients(self._settings, -0.5 * h, start=True),
                                   joint)
        self._state = BodyState((px, py, pz), q, v, w)
        self._staggered = True

    def _velocities(self, px: float, py: float, pz: float, q, v: Vector3, w: Vector3, h: float,
                    coefficients: Tuple, joint: Optional[Tuple[Vector3, Optional[Vector3]]]):
        """
        Return the velocities after a substep's velocity stage, and the constraint impulse.

        :param joint: None for a free body, else the point the anchor is pulled to and the
            velocity it moves at (None: the seed's joint, which takes it as still).

        The hot path of the core: the algebra helpers (``rotation_matrix``, ``multiply``, ...)
        are written out inline here, in the same operation order, because a Python call and its
        tuples cost as much as the arithmetic they wrap.
        """
        (gx, gy, gz, linear_decay, angular_decay, a, b, max_impulse, max_turn_impulse, carry,
         kick, gyroscopic, inertia, joint_body) = coefficients
        # R(q), as algebra.rotation_matrix.
        x, y, z, qw = q
        xx, yy, zz = x * x, y * y, z * z
        xy, xz, yz = x * y, x * z, y * z
        wx, wy, wz = qw * x, qw * y, qw * z
        r00, r01, r02 = 1.0 - 2.0 * (yy + zz), 2.0 * (xy - wz), 2.0 * (xz + wy)
        r10, r11, r12 = 2.0 * (xy + wz), 1.0 - 2.0 * (xx + zz), 2.0 * (yz - wx)
        r20, r21, r22 = 2.0 * (xz - wy), 2.0 * (yz + wx), 1.0 - 2.0 * (xx + yy)
        (fx, fy, fz), torque = self._wrench
        vx = (v[0] + gx + kick * fx) * linear_decay
        vy = (v[1] + gy + kick * fy) * linear_decay
        vz = (v[2] + gz + kick * fz) * linear_decay
        # The body-frame angular velocity R^T w.
        wx, wy, wz = w
        w_body = (r00 * wx + r10 * wy + r20 * wz, r01 * wx + r11 * wy + r21 * wz,
                  r02 * wx + r12 * wy + r22 * wz)
        if torque != ZERO:
            # The torque's angular impulse, in the body frame: w += h I_b^-1 R^T tau.
            ax, ay, az = multiply_symmetric(
                multiply_transposed(torque, (r00, r01, r02, r10, r11, r12, r20, r21, r22)),
                self._settings.body.inverse_inertia)
            w_body = (w_body[0] + h * ax, w_body[1] + h * ay, w_body[2] + h * az)
        wbx, wby, wbz = gyroscopic(inertia, w_body, h)
        if joint is not None and max_turn_impulse > 0.0:
            # Angular friction: the angular impulse that stops the spin, I w, within its bound;
            # it scales w, as I w and w differ by the positive definite I.
            ixx, ixy, ixz, iyy, iyz, izz = self._settings.body.inertia
            lx = ixx * wbx + ixy * wby + ixz * wbz
            ly = ixy * wbx + iyy * wby + iyz * wbz
            lz = ixz * wbx + iyz * wby + izz * wbz
            spin = math.sqrt(lx * lx + ly * ly + lz * lz)
            if spin > 0.0:
                kept = max(0.0, 1.0 - max_turn_impulse / spin)
                self._friction_torque = spin * (1.0 - kept) / abs(h)
                wbx, wby, wbz = wbx * kept, wby * kept, wbz * kept
            else:
                self._friction_torque = 0.0
        elif h > 0.0:
            self._friction_torque = 0.0
        if joint is None:
            # w = R w_body, damped.
            return ((vx, vy, vz),
                    ((r00 * wbx + r01 * wby + r02 * wbz) * angular_decay,
                     (r10 * wbx + r11 * wby + r12 * wbz) * angular_decay,
                     (r20 * wbx + r21 * wby + r22 * wbz) * angular_decay),
                    ZERO)
        # The constraint is solved in the body frame, where K and the lever are constant:
        # with r = R r_b and I_w^-1 = R I_b^-1 R^T, K = R K_b R^T for
        # K_b = m^-1 I3 + [r_b]x I_b^-1 [r_b]x^T (eq. 1.10 in the body frame), so
        # P = R P_b with P_b = -K_b^-1 R^T (a J V + b C), and the angular velocity change
        # I_w^-1 (r x P) = R I_b^-1 [r_b]x P_b. K_b^-1 and I_b^-1 [r_b]x are computed once per
        # settings (``_coefficients``); rotations keep every norm below.
        (rbx, rby, rbz), (k00, k01, k02, k11, k12, k22), \
            (m00, m01, m02, m10, m11, m12, m20, m21, m22), inverse_mass = joint_body
        wbx *= angular_decay
        wby *= angular_decay
        wbz *= angular_decay
        (tx, ty, tz), target_velocity = joint
        # C = x + r - x_mouse (eq. 1.1) in the body frame: R^T (x - x_mouse) + r_b.
        dx, dy, dz = px - tx, py - ty, pz - tz
        cx = r00 * dx + r10 * dy + r20 * dz + rbx
        cy = r01 * dx + r11 * dy + r21 * dz + rby
        cz = r02 * dx + r12 * dy + r22 * dz + rbz
        if target_velocity is not None:
            # The joint follows the target's motion: J V - v_target is driven to zero.
            ux, uy, uz = vx - target_velocity[0], vy - target_velocity[1], \
                vz - target_velocity[2]
        else:
            ux, uy, uz = vx, vy, vz
        # J V = v + w x r (eq. 1.2), in the body frame R^T v + w_b x r_b.
        jvx = r00 * ux + r10 * uy + r20 * uz + wby * rbz - wbz * rby
        jvy = r01 * ux + r11 * uy + r21 * uz + wbz * rbx - wbx * rbz
        jvz = r02 * ux + r12 * uy + r22 * uz + wbx * rby - wby * rbx
        # The position correction -K^-1 b C, limited in the turn it asks of a substep.
        sx, sy, sz = -b * cx, -b * cy, -b * cz
        bx = k00 * sx + k01 * sy + k02 * sz
        by = k01 * sx + k11 * sy + k12 * sz
        bz = k02 * sx + k12 * sy + k22 * sz
        ax = m00 * bx + m01 * by + m02 * bz
        ay = m10 * bx + m11 * by + m12 * bz
        az = m20 * bx + m21 * by + m22 * bz
        turn = abs(h) * math.sqrt(ax * ax + ay * ay + az * az)
        if turn > MAX_CORRECTION_TURN:
            scale = MAX_CORRECTION_TURN / turn
            bx *= scale
            by *= scale
            bz *= scale
        if carry > 0.0:
            # Gravity feed-forward: the share 1 - a of this substep's g h that the spring's
            # velocity term leaves is removed too, so the weight does not sag a soft spring
            # (g / omega^2 otherwise); 1 - a = 0 in rigid mode, which carries it anyway.
            sx = -a * jvx - carry * (r00 * gx + r10 * gy + r20 * gz)
            sy = -a * jvy - carry * (r01 * gx + r11 * gy + r21 * gz)
            sz = -a * jvz - carry * (r02 * gx + r12 * gy + r22 * gz)
        else:
            sx, sy, sz = -a * jvx, -a * jvy, -a * jvz
        ix = k00 * sx + k01 * sy + k02 * sz + bx
        iy = k01 * sx + k11 * sy + k12 * sz + by
        iz = k02 * sx + k12 * sy + k22 * sz + bz
        norm = math.sqrt(ix * ix + iy * iy + iz * iz)
        if norm > max_impulse:
            scale = max_impulse / norm
            ix *= scale
            iy *= scale
            iz *= scale
        wbx += m00 * ix + m01 * iy + m02 * iz
        wby += m10 * ix + m11 * iy + m12 * iz
        wbz += m20 * ix + m21 * iy + m22 * iz
        # Back to the world frame: P = R P_b, w = R w_b.
        ix, iy, iz = (r00 * ix + r01 * iy + r02 * iz, r10 * ix + r11 * iy + r12 * iz,
                      r20 * ix + r21 * iy + r22 * iz)
        return ((vx + ix * inverse_mass, vy + iy * inverse_mass, vz + iz * inverse_mass),
                (r00 * wbx + r01 * wby + r02 * wbz, r10 * wbx + r11 * wby + r12 * wbz,
                 r20 * wbx + r21 * wby + r22 * wbz),
                (ix, iy, iz))

    @staticmethod
    def _coefficients(settings: Settings, h: float, start: bool = False) -> Tuple[float, ...]:
        """
        Return what a substep of ``h`` needs from ``settings``, computed once per change.

        :param h: the substep; negative for the backward half step of ``_stagger``.
        :param start: for ``_stagger``: the physical part of the constraint only (no Baumgarte
            correction; the spring's own acceleration).
        """
        gx, gy, gz = settings.gravity
        constraint = settings.constraint
        omega = 2.0 * math.pi * constraint.frequency_hz
        damping = 2.0 * constraint.damping_ratio * omega * abs(h)
        if not start:
            a, b = constraint.gains(h)
        elif constraint.rigid or max(damping, (omega * h) ** 2) > STIFF_START:
            # Rigid, or a spring too stiff for the step to resolve (it settles within one): the
            # constraint's reaction alone, which removes the anchor's velocity and adds no energy.
            a, b = 1.0, 0.0
        else:
            # The spring-damper's own acceleration -omega^2 C - 2 zeta omega dC/dt, applied
            # over h (< 0): a first-order kick, as running a damped spring backwards exactly
            # would amplify it exponentially.
            a, b = -damping, omega * omega * h
        body = settings.body
        return (gx * h, gy * h, gz * h, _decay(settings.linear_damping, h, start),
                _decay(settings.angular_damping, h, start), a, b,
                force_bound(settings) * abs(h),
                0.0 if start else friction_torque_bound(settings) * abs(h),
                1.0 - a if constraint.gravity_feed_forward and not start else 0.0,
                h * body.inverse_mass, *_gyroscopic(body),
                _body_frame_joint(body, constraint.anchor))


def weight_scale(settings: Settings) -> float:
    """Return m |g| (N), with the standard gravity's norm when gravity is zero."""
    gravity = norm(settings.gravity) or norm(STANDARD_GRAVITY)
    return settings.body.mass * gravity


def force_bound(settings: Settings) -> float:
    """Return the bound on the constraint force (N): max_force and max_force_per_weight m g."""
    constraint = settings.constraint
    if math.isinf(constraint.max_force_per_weight):
        return constraint.max_force
    return min(constraint.max_force, constraint.max_force_per_weight * weight_scale(settings))


def friction_torque_bound(settings: Settings) -> float:
    """Return the angular friction's torque bound c m |g| sqrt(I_mean / m) (N m)."""
    friction = settings.constraint.angular_friction
    if friction == 0.0:
        return 0.0
    body = settings.body
    gyration = math.sqrt(sum(body.principal_moments) / 3.0 / body.mass)
    return friction * weight_scale(settings) * gyration


def _gyroscopic(body: RigidBody) -> Tuple:
    """Return the gyroscopic step for ``body`` and its inertia argument, diagonal where it is."""
    ixx, ixy, ixz, iyy, iyz, izz = body.inertia
    if ixy == 0.0 and ixz == 0.0 and iyz == 0.0:
        return gyroscopic_step_diagonal, (ixx, iyy, izz)
    return gyroscopic_step, body.inertia


def _body_frame_joint(body: RigidBody, anchor: Vector3) -> Tuple:
    """
    Return what the body-frame constraint solve holds constant: r_b, K_b^-1, I_b^-1 [r_b]x, 1/m.

    K_b = m^-1 I3 + [r_b]x I_b^-1 [r_b]x^T is eq. 1.10 in the body frame (K = R K_b R^T); its
    inverse is built from its Cholesky factor, column by column, as a symmetric 6-tuple. The
    lever I_b^-1 [r_b]x maps an impulse P_b at the anchor to the angular velocity change
    I_b^-1 (r_b x P_b), row-major.
    """
    factor = cholesky(effective_mass(body.inverse_mass, body.inverse_inertia, anchor))
    c0 = solve_cholesky(factor, (1.0, 0.0, 0.0))
    c1 = solve_cholesky(factor, (0.0, 1.0, 0.0))
    c2 = solve_cholesky(factor, (0.0, 0.0, 1.0))
    a00, a01, a02, a11, a12, a22 = body.inverse_inertia
    rx, ry, rz = anchor
    lever = (a01 * rz - a02 * ry, a02 * rx - a00 * rz, a00 * ry - a01 * rx,
             a11 * rz - a12 * ry, a12 * rx - a01 * rz, a01 * ry - a11 * rx,
             a12 * rz - a22 * ry, a22 * rx - a02 * rz, a02 * ry - a12 * rx)
    return (anchor, (c0[0], c0[1], c0[2], c1[1], c1[2], c2[2]), lever, body.inverse_mass)


def _decay(rate: float, h: float, start: bool) -> float:
    """Return the factor exp(-rate h); at the start, 1 for damping the step cannot resolve."""
    if start and rate * abs(h) > STIFF_START:
        return 1.0
    return math.exp(-rate * h)
