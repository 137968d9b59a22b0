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
The step kernel: one substep's velocity stage, and the start that staggers a new state.

``velocities`` applies, in this order, gravity and the external wrench, exponential damping, the
gyroscopic term (``gyroscopic``), the mouse constraint's impulse P = -K^-1 (a J V + b C),
|P| <= h F_max (``mouse_joint``, seed eqs. 1.1-1.10) and the angular friction while a target is
held, on the coefficients ``step_plan.coefficients`` computes once per settings and substep.
``simulation.MouseSimulation`` calls it.

The angular friction acts on the spin about the line from the anchor to the COM alone: the
velocity row w . n = 0, its torque bounded by ``settings.friction_torque_bound``, solved after
the joint with the effective mass of the body turning about its anchor, the joint carrying the
reaction (``step_plan.spin_axis``). The joint's rows and this one together are then solved:
a hung body's spin about its hanging line dies down, and its swing, a turn about an axis across
that line, is the compound pendulum's, its energy kept. Friction on the whole spin (as Box2D's
2D mouse joint damps its one angular velocity, the swing's too) holds a small swing still: at
0.25 the bound is above the shipped corner pendulum's gravity torque below 7 degrees.

The force bound F_max (``force_bound``: ``max_force``, ``max_force_per_weight`` body weights)
lets a rigid joint keep the anchor on the guide through a click's fastest turns: a free body
always follows. An anchor held back from the guide does not (a corner pressed into the floor,
a wall, a body too heavy for the bound), and the full bound then acts through whatever holds
it back as through a lever: a box's top corner pressed down and sideways into the floor tips
the box about its edge at 30 rad/s, flung. So the bound falls with the anchor's error C, from
F_max up to HELD_BACK_START to the follow force m (|g| + max_target_acceleration) from
HELD_BACK_FULL on: what moves the body along the guide's fastest motion, still enough to press
it down, slide it along the floor and lift it.

A body touching the floor gets the follow force at most, whatever its error: the contacts,
solved after the joint, hold it back within the substep, so the error stays small while the
full bound jams the box against the floor and spins it (a corner dragged across the far edge:
30-40 rad/s). An anchor held back and let go (lifted off the floor) closes on the guide as the
guide closes on a target, b |C| <= a sqrt(2 A |C|) for A = max_target_acceleration: rigid
mode's b = delta / h would close 4 cm at 16 m/s, a snap that flings the box.
"""

import math
from typing import Optional, Tuple

from .algebra import multiply_symmetric, multiply_transposed, Vector3
from .gyroscopic import free_rotation
from .settings import Settings
from .state import BodyState
from .step_plan import coefficients

# The most a substep's position correction may turn the body (rad). The impulse is solved for
# the linearized constraint, which holds while the body turns little in a substep; a far target
# on a long lever arm would otherwise ask for a turn of radians per substep, the linear step
# would miss, and the missed error would pump energy in. Only corrections of large errors meet
# the limit; they then close at this turn per substep instead of at delta per substep.
MAX_CORRECTION_TURN = 0.2
# Held back: an anchor farther than HELD_BACK_START (m) from where the joint pulls it is pulled
# with less than the full force bound, down to the follow force (``settings.follow_force``)
# from HELD_BACK_FULL on. A rigid joint keeps a free anchor on the guide to micrometres, a soft
# one within millimetres through a click; a centimetre is a contact, a wall, or a body too
# heavy for the bound.
HELD_BACK_START = 0.01
HELD_BACK_FULL = 0.05
ZERO: Vector3 = (0.0, 0.0, 0.0)


def velocities(px: float, py: float, pz: float, q, v: Vector3, w: Vector3, h: float,
               coefficients: Tuple, joint: Optional[Tuple[Vector3, Optional[Vector3]]],
               wrench: Tuple[Vector3, Vector3], friction_torque: float,
               touching: bool = False):
    """
    Return the velocities after a substep's velocity stage, the joint's impulse, the friction.

    :param coefficients: the settings' share of the substep, from ``coefficients``.
    :param joint: None for a free body, else the point the anchor is pulled to and the
        velocity it moves at (None: the seed's joint, which takes it as still).
    :param wrench: the external (force through the COM (N), torque (N m)), world frame.
    :param friction_torque: the angular friction's torque so far (N m), returned as it is
        where the substep has none to say (the backward half step of a free body).
    :param touching: whether the floor's contacts act on the body after this stage: it then
        turns by the final w, as a held body does, and the joint pulls with the follow force.
    :returns: v, w (world frame), the joint's impulse, the friction torque and, for a free
        body, the world-frame unit quaternion of its turn over the substep (else None: the
        body turns by w h).

    The hot path of the core: the algebra helpers (``rotation_matrix``, ``multiply``, ...)
    are written out inline here, in the same operation order, because a Python call and its
    tuples cost as much as the arithmetic they wrap.
    """
    (gx, gy, gz, linear_decay, angular_decay, a, b, max_impulse, follow_impulse, catch_up,
     max_turn_impulse, carry, kick, gyroscopic, inertia, joint_body, body_inertia,
     inverse_inertia, spin_axis) = coefficients
    # R(q), as algebra.rotation_matrix.
    x, y, z, qw = q
    xx, yy, zz = x * x, y * y, z * z
    xy, xz, yz = x * y, x * z, y * z
    wx, wy, wz = qw * x, qw * y, qw * z
    r00, r01, r02 = 1.0 - 2.0 * (yy + zz), 2.0 * (xy - wz), 2.0 * (xz + wy)
    r10, r11, r12 = 2.0 * (xy + wz), 1.0 - 2.0 * (xx + zz), 2.0 * (yz - wx)
    r20, r21, r22 = 2.0 * (xz - wy), 2.0 * (yz + wx), 1.0 - 2.0 * (xx + yy)
    (fx, fy, fz), torque = wrench
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
            inverse_inertia)
        w_body = (w_body[0] + h * ax, w_body[1] + h * ay, w_body[2] + h * az)
    if joint is None and not touching:
        # A free body turns as its gyroscopic step says, which keeps the world L = R I w_b:
        # the angular momentum changes by the torque's h tau alone (``free_rotation``).
        if h > 0.0:
            (wbx, wby, wbz), (tx, ty, tz, tw) = free_rotation(gyroscopic, inertia, w_body, h)
            friction_torque = 0.0
        else:
            # The backward half step of the start: the world L at t - h / 2 is L(t) - tau h / 2
            # whatever the body's turn, held in the body frame of t (which it stays in).
            (wbx, wby, wbz), (tx, ty, tz, tw) = w_body, (0.0, 0.0, 0.0, 1.0)
        # The turn in the world frame, R t_b, and w = R (t_b w_b t_b^-1) at the new orientation.
        tx, ty, tz = (r00 * tx + r01 * ty + r02 * tz, r10 * tx + r11 * ty + r12 * tz,
                      r20 * tx + r21 * ty + r22 * tz)
        wx = (r00 * wbx + r01 * wby + r02 * wbz) * angular_decay
        wy = (r10 * wbx + r11 * wby + r12 * wbz) * angular_decay
        wz = (r20 * wbx + r21 * wby + r22 * wbz) * angular_decay
        cx, cy, cz = ty * wz - tz * wy, tz * wx - tx * wz, tx * wy - ty * wx
        return ((vx, vy, vz),
                (wx + 2.0 * (tw * cx + ty * cz - tz * cy),
                 wy + 2.0 * (tw * cy + tz * cx - tx * cz),
                 wz + 2.0 * (tw * cz + tx * cy - ty * cx)),
                ZERO, friction_torque, (tx, ty, tz, tw))
    wbx, wby, wbz = gyroscopic(inertia, w_body, h)
    if h > 0.0:
        friction_torque = 0.0
    if joint is None:
        # w = R w_body, damped.
        return ((vx, vy, vz),
                ((r00 * wbx + r01 * wby + r02 * wbz) * angular_decay,
                 (r10 * wbx + r11 * wby + r12 * wbz) * angular_decay,
                 (r20 * wbx + r21 * wby + r22 * wbz) * angular_decay),
                ZERO, friction_torque, None)
    # The constraint is solved in the body frame, where K and the lever are constant:
    # with r = R r_b and I_w^-1 = R I_b^-1 R^T, K = R K_b R^T for
    # K_b = m^-1 I3 + [r_b]x I_b^-1 [r_b]x^T (eq. 1.10 in the body frame), so
    # P = R P_b with P_b = -K_b^-1 R^T (a J V + b C), and the angular velocity change
    # I_w^-1 (r x P) = R I_b^-1 [r_b]x P_b. K_b^-1 and I_b^-1 [r_b]x are computed once per
    # settings (``step_plan.coefficients``); rotations keep every norm below.
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
    error = math.sqrt(cx * cx + cy * cy + cz * cz)
    if target_velocity is not None and b * b * error > a * a * catch_up:
        # Held back, then let go: it closes at a sqrt(2 A |C|) at most (module docstring).
        scale = a * math.sqrt(catch_up / error) / b
        sx, sy, sz = sx * scale, sy * scale, sz * scale
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
    if follow_impulse < max_impulse:
        # On the floor, or held back: the bound falls to the follow force (module docstring).
        if touching:
            max_impulse = follow_impulse
        elif error > HELD_BACK_START:
            share = max(0.0, (HELD_BACK_FULL - error) / (HELD_BACK_FULL - HELD_BACK_START))
            max_impulse = follow_impulse + (max_impulse - follow_impulse) * share
    if norm > max_impulse:
        scale = max_impulse / norm
        ix *= scale
        iy *= scale
        iz *= scale
    wbx += m00 * ix + m01 * iy + m02 * iz
    wby += m10 * ix + m11 * iy + m12 * iz
    wbz += m20 * ix + m21 * iy + m22 * iz
    if max_turn_impulse > 0.0 and spin_axis is not None:
        # Angular friction, after the joint: the row w . n = 0 on the spin about the line n
        # from the COM to the anchor, its angular impulse within the bound. The body turns
        # about the anchor, whose velocity it keeps, as the joint carries the reaction
        # (``step_plan.spin_axis``); the spin then stops and the swing across n is untouched,
        # as the two rows solved together would leave them. A joint at its force bound does
        # not carry it, and the friction then turns the free body.
        nx, ny, nz, pinned_mass, (ux, uy, uz), (fx, fy, fz), free_mass, free_turn = spin_axis
        spin = nx * wbx + ny * wby + nz * wbz
        stop = max(-max_turn_impulse, min(max_turn_impulse, -pinned_mass * spin))
        jx, jy, jz = ix + stop * fx, iy + stop * fy, iz + stop * fz
        if jx * jx + jy * jy + jz * jz <= max_impulse * max_impulse:
            ix, iy, iz = jx, jy, jz
        else:
            stop = max(-max_turn_impulse, min(max_turn_impulse, -free_mass * spin))
            ux, uy, uz = free_turn
        wbx, wby, wbz = wbx + stop * ux, wby + stop * uy, wbz + stop * uz
        friction_torque = abs(stop) / h
    elif max_turn_impulse > 0.0:
        # An anchor at the COM, which has no line: the whole spin is stopped, I w within the
        # bound; the impulse scales w, as I w and w differ by the positive definite I.
        ixx, ixy, ixz, iyy, iyz, izz = body_inertia
        lx = ixx * wbx + ixy * wby + ixz * wbz
        ly = ixy * wbx + iyy * wby + iyz * wbz
        lz = ixz * wbx + iyz * wby + izz * wbz
        spin = math.sqrt(lx * lx + ly * ly + lz * lz)
        kept = max(0.0, 1.0 - max_turn_impulse / spin) if spin > 0.0 else 1.0
        friction_torque = spin * (1.0 - kept) / h
        wbx, wby, wbz = wbx * kept, wby * kept, wbz * kept
    # Back to the world frame: P = R P_b, w = R w_b.
    ix, iy, iz = (r00 * ix + r01 * iy + r02 * iz, r10 * ix + r11 * iy + r12 * iz,
                  r20 * ix + r21 * iy + r22 * iz)
    return ((vx + ix * inverse_mass, vy + iy * inverse_mass, vz + iz * inverse_mass),
            (r00 * wbx + r01 * wby + r02 * wbz, r10 * wbx + r11 * wby + r12 * wbz,
             r20 * wbx + r21 * wby + r22 * wbz),
            (ix, iy, iz), friction_torque, None)


def stagger(settings: Settings, state: BodyState, target: Optional[Vector3],
            wrench: Tuple[Vector3, Vector3], friction_torque: float,
            h: float) -> Tuple[BodyState, float]:
    """
    Return ``state`` with its velocities moved from time t back to t - h / 2, and the torque.

    Symplectic Euler is the leapfrog scheme with velocities at half steps: x(t + h) =
    x(t) + h v(t + h / 2). A state given with v(t), such as a body released at rest, starts
    it half a step out of phase, an O(h) error for the whole motion (0.164 mm RMS for the
    corner pendulum released 20 deg from hanging, 5 s at 1 kHz); starting from v(t - h / 2)
    makes it O(h^2) (0.021 mm; both printed by ``python -m bench.physics_figures``). The
    velocity stage is run backwards over h / 2 for that: gravity, damping, the gyroscopic
    term (the midpoint rule is time-symmetric, so the energy is kept; a free body's world L
    is L(t) - tau h / 2 whatever it turns, so its term is left out) and the constraint's
    reaction, with soft mode's spring; rigid mode's Baumgarte correction is numerical and
    is left out. The published velocities are then the half-step ones. With one substep per
    step, the linear velocity is exactly the finite difference of the published positions, and
    a held body's angular velocity that of the orientations; a free body turns by the Cayley
    rotation of the mean of its angular velocities before and after (``free_rotation``), and
    its published angular velocity is the one of its angular momentum, L = I_w w.

    :param target: where the joint pulls (the guide or the target), None for a free body.
    :param friction_torque: the angular friction's torque so far (N m).
    """
    (px, py, pz), q, v, w = state
    joint = None if target is None else (target, None)
    v, w, _, friction_torque, _ = velocities(
        px, py, pz, q, v, w, -0.5 * h, coefficients(settings, -0.5 * h, start=True),
        joint, wrench, friction_torque)
    return BodyState((px, py, pz), q, v, w), friction_torque
