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
The prepare stage of a step: what its substeps take from the settings, computed once per change.

As Box2D splits a joint into a prepare and a solve stage, ``MouseSimulation.step`` takes a
``StepPlan`` made once per settings and substep length: the velocity stage's coefficients
(``coefficients``, read by ``kernel.velocities``), the floor's (``floor.coefficients``), and
whether the joint's target moves within a step (a guide or the feed-forward:
``target_motion.pull_point`` then runs every substep). The settings are immutable, so a plan
made for the same settings object and the same substep still holds.
"""

import math
from typing import NamedTuple, Optional, Tuple

import numpy as np

from .algebra import cholesky, solve_cholesky, Vector3
from .body import RigidBody
from .floor import coefficients as floor_coefficients
from .gyroscopic import gyroscopic_step, gyroscopic_step_diagonal
from .limits import MIN_STEP
from .mouse_joint import effective_mass
from .settings import follow_force, force_bound, friction_torque_bound, Settings

# The leapfrog start kicks a soft spring back by its own acceleration only while the step
# resolves it (2 zeta omega h and (omega h)^2 below this); a stiffer one is started like rigid
# mode, since a first-order kick of a spring that settles within a step adds energy. Likewise
# damping: undone over h / 2 only while its rate times h is below this.
STIFF_START = 0.5


class StepPlan(NamedTuple):
    """What the substeps of ``h`` take from ``settings``."""

    settings: Settings
    h: float
    coefficients: Tuple[float, ...]
    moving_target: bool
    floor: Optional[Tuple]


def step_plan(settings: Settings, dt: float) -> StepPlan:
    """
    Return the plan of a step of ``dt`` in ``settings.substeps`` substeps.

    :raises ValueError: a substep shorter than ``MIN_STEP``.
    """
    substeps = settings.substeps
    h = dt / substeps
    if h < MIN_STEP:
        raise ValueError(f'dt / substeps must be >= {MIN_STEP} s, got {dt!r} / {substeps}')
    motion = settings.target_motion
    return StepPlan(settings, h, coefficients(settings, h),
                    motion.feed_forward or motion.guided, floor_coefficients(settings.floor))


def coefficients(settings: Settings, h: float, start: bool = False) -> Tuple[float, ...]:
    """
    Return what a substep of ``h`` needs from ``settings``, computed once per change.

    :param h: the substep; negative for the backward half step that starts a new state.
    :param start: for that start: the physical part of the constraint only
        (no Baumgarte correction; the spring's own acceleration).
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
            math.inf if start else follow_force(settings) * abs(h),
            math.inf if start else 2.0 * settings.target_motion.max_acceleration,
            0.0 if start else friction_torque_bound(settings) * abs(h),
            1.0 - a if constraint.gravity_feed_forward and not start else 0.0,
            h * body.inverse_mass, *_gyroscopic(body),
            _body_frame_joint(body, constraint.anchor), body.inertia, body.inverse_inertia,
            spin_axis(body, constraint.anchor))


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


def spin_axis(body: RigidBody, anchor: Vector3) -> Optional[Tuple]:
    """
    Return what the angular friction holds constant, in the body frame; None without a line.

    n is the unit vector from the COM to the anchor: the line through both, the axis a hung
    body spins about. The friction is the velocity row w . n = 0 (``kernel.velocities``). With
    the anchor held, its angular impulse lambda n turns the body about the anchor: by
    lambda I_A^-1 n, for I_A = I + m (|r|^2 I3 - r r^T) the inertia about the anchor, the COM
    moving by r x (lambda I_A^-1 n) and the joint carrying the impulse m r x I_A^-1 n lambda;
    the row's effective mass is 1 / (n . I_A^-1 n). On a free body the same impulse turns it
    by lambda I^-1 n, of effective mass 1 / (n . I^-1 n).

    :returns: n (three floats), 1 / (n . I_A^-1 n), I_A^-1 n, m r x I_A^-1 n,
        1 / (n . I^-1 n), I^-1 n; None for an anchor at the COM, which has no such line (the
        friction then stops the whole spin).
    """
    r = np.array(anchor, dtype=float)
    lever = float(np.linalg.norm(r))
    if lever == 0.0:
        return None
    n = r / lever
    inertia = _matrix(body.inertia)
    about_anchor = inertia + body.mass * (lever * lever * np.eye(3) - np.outer(r, r))
    pinned = np.linalg.solve(about_anchor, n)
    free = np.linalg.solve(inertia, n)
    reaction = body.mass * np.cross(r, pinned)
    return (*(float(c) for c in n), 1.0 / float(n @ pinned), _floats(pinned),
            _floats(reaction), 1.0 / float(n @ free), _floats(free))


def _matrix(s: Tuple[float, ...]) -> np.ndarray:
    """Return the symmetric 6-tuple (xx, xy, xz, yy, yz, zz) as a 3x3 array."""
    xx, xy, xz, yy, yz, zz = s
    return np.array([[xx, xy, xz], [xy, yy, yz], [xz, yz, zz]])


def _floats(v: np.ndarray) -> Vector3:
    """Return a 3-vector as a tuple of Python floats (the kernel's arithmetic is on floats)."""
    return (float(v[0]), float(v[1]), float(v[2]))


def _decay(rate: float, h: float, start: bool) -> float:
    """Return the factor exp(-rate h); at the start, 1 for damping the step cannot resolve."""
    if start and rate * abs(h) > STIFF_START:
        return 1.0
    return math.exp(-rate * h)
