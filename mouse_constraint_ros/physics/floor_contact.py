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
Box-plane contact: sequential impulses with accumulated clamping, warm started, split impulses.

``solve`` runs after the velocity stage of a substep (gravity, wrench, the mouse constraint),
so the floor has the last word on the velocity: a joint pulling the body into the floor is
held by it. Per contact point r (from the COM, world frame), normal n = z and the tangents x and
y of the world frame, the velocity of the point is u = v + w x r and an impulse P along a
direction d changes it by K P, K = 1 / m + (r x d) . I_w^-1 (r x d).

- Normal: the accumulated impulse stays >= 0. A speculative contact (the corner s > 0 above the
  plane) asks only u_n >= -s / h, so the corner reaches the plane within the substep but does
  not pass it; a touching one (s <= 0) asks u_n >= 0; a contact approaching faster than the
  restitution threshold that reaches the plane in the substep asks u_n >= -e u_n0 (u_n0 its
  velocity before the solve).
- Friction: both tangential impulses together stay within the cone |P_t| <= mu P_n.
- Warm start: each contact starts from the impulses its corner had in the previous substep.
- Position: penetration deeper than ``slop`` is removed by split impulses, pseudo-velocities
  solved like the normal rows (rate ``POSITION_RATE`` per substep) that move the body in this
  substep's position update and are then dropped, so the correction adds no kinetic energy.

The arithmetic is written out on floats, as in ``kernel``: a contact costs some thirty
operations per sweep, and Python calls and tuples would cost more than that.
"""

import math
from typing import List, Tuple

from .algebra import congruence, Vector3
from .floor import CORNER_SIGNS

# Fraction of the penetration beyond the slop that the split impulses remove per substep.
POSITION_RATE = 0.2
# Sweeps stop once no impulse changed a contact's velocity by more than this (m/s).
CONVERGED_SPEED = 1e-9

# A contact, as ``solve`` keeps it: corner index, r (x, y, z), separation s, I_w^-1 (r x d) for
# d = z, x, y (three each), K along z, 1 / K along z, x, y, the normal goal, the accumulated
# impulses along z, x, y (index 19 to 21; the next substep warm starts from them) and the
# velocity the contact bounces to (None: it does not bounce).
Rows = List[list]


def touching(coefficients: Tuple, pz: float, q) -> bool:
    """
    Return whether the box's lowest corner is within the margin of the plane.

    The reach below the COM is ``Floor.depth``'s, written out on the coefficients: it runs every
    substep (``test_resting_contacts_carry_the_weight`` and the rest tests see both agree).
    """
    height, hx, hy, hz, _, _, _, margin = coefficients[:8]
    x, y, z, w = q
    reach = (abs(2.0 * (x * z - w * y)) * hx + abs(2.0 * (y * z + w * x)) * hy
             + abs(1.0 - 2.0 * (x * x + y * y)) * hz)
    return pz - reach <= height + margin


def solve(coefficients: Tuple, position: Vector3, q, v: Vector3, w: Vector3, h: float, *,
          inverse_mass: float, inertia, inverse_inertia, gravity: Vector3, warm: Rows):
    """
    Return the velocities after the floor's contacts, those that move the body, and the contacts.

    :param coefficients: ``floor.coefficients`` of the settings.
    :param position: the COM at the substep's start (m).
    :param q: the orientation there.
    :param v: the linear velocity after the velocity stage (m/s).
    :param w: the angular velocity after it (rad/s, world frame).
    :param h: the substep (s).
    :param inverse_mass: 1 / m.
    :param inertia: the body-frame I_b as a symmetric 6-tuple (kg m^2).
    :param inverse_inertia: its inverse I_b^-1.
    :param gravity: the gravitational acceleration (m/s^2), for the energy a bounce may have.
    :param warm: the previous substep's contacts (``Rows``), whose impulses the contacts of
        the same corners start from.
    :returns: (v, w) after the contacts; (v, w) plus the split impulses' pseudo-velocities,
        for the position update; and the contacts (``Rows``, see ``contact_points``).
    """
    (height, hx, hy, hz, friction, restitution, iterations, margin, slop,
     threshold) = coefficients
    pz = position[2]
    # R(q), as algebra.rotation_matrix and kernel.velocities write it out.
    x, y, z, qw = q
    xx, yy, zz = x * x, y * y, z * z
    xy, xz, yz = x * y, x * z, y * z
    wx_, wy_, wz_ = qw * x, qw * y, qw * z
    rotation = (1.0 - 2.0 * (yy + zz), 2.0 * (xy - wz_), 2.0 * (xz + wy_),
                2.0 * (xy + wz_), 1.0 - 2.0 * (xx + zz), 2.0 * (yz - wx_),
                2.0 * (xz - wy_), 2.0 * (yz + wx_), 1.0 - 2.0 * (xx + yy))
    r00, r01, r02, r10, r11, r12, r20, r21, r22 = rotation
    i00, i01, i02, i11, i12, i22 = congruence(rotation, inverse_inertia)
    im = inverse_mass
    vx, vy, vz = v
    wx, wy, wz = w
    # The speeds of approach are taken before any warm start.
    vz0, wx0, wy0 = vz, wx, wy
    previous = [None] * 8
    for row in warm:
        previous[row[0]] = row
    rows = []
    bounces = False
    # The corners' world offsets are sums of the box's half axes R (hx, 0, 0), ...
    ux, uy, uz = r00 * hx, r10 * hx, r20 * hx
    vx_, vy_, vz_ = r01 * hy, r11 * hy, r21 * hy
    tx_, ty_, tz_ = r02 * hz, r12 * hz, r22 * hz
    base = pz - height
    for index, (sx, sy, sz) in enumerate(CORNER_SIGNS):
        rz = sx * uz + sy * vz_ + sz * tz_
        s = base + rz
        if s > margin:
            continue
        rx = sx * ux + sy * vx_ + sz * tx_
        ry = sx * uy + sy * vy_ + sz * ty_
        # I_w^-1 (r x d) and K for d = z, x, y.
        nx, ny, nz = i00 * ry - i01 * rx, i01 * ry - i11 * rx, i02 * ry - i12 * rx
        tx, ty, tz = i01 * rz - i02 * ry, i11 * rz - i12 * ry, i12 * rz - i22 * ry
        bx, by, bz = i02 * rx - i00 * rz, i12 * rx - i01 * rz, i22 * rx - i02 * rz
        kn = im + ry * nx - rx * ny
        kt = im + rz * ty - ry * tz
        kb = im + rx * bz - rz * bx
        approach = vz0 + wx0 * ry - wy0 * rx
        goal = -s / h if s > 0.0 else 0.0
        if restitution > 0.0 and approach < -threshold and approach * h <= -s:
            bounces = True
            bounce = -restitution * approach
        else:
            bounce = None
        last = previous[index]
        if last is None:
            pn = pt = pb = 0.0
        else:
            pn, pt, pb = last[19], last[20], last[21]
            vx += im * pt
            vy += im * pb
            vz += im * pn
            wx += pn * nx + pt * tx + pb * bx
            wy += pn * ny + pt * ty + pb * by
            wz += pn * nz + pt * tz + pb * bz
        rows.append([index, rx, ry, rz, s, nx, ny, nz, tx, ty, tz, bx, by, bz,
                     kn, 1.0 / kn, 1.0 / kt, 1.0 / kb, goal, pn, pt, pb, bounce])
    for _ in range(iterations):
        largest = 0.0
        for row in rows:
            (_, rx, ry, rz, _, nx, ny, nz, tx, ty, tz, bx, by, bz, kn, mn, mt, mb, goal,
             pn, pt, pb, _) = row
            # Normal: u_n >= goal with an accumulated impulse >= 0.
            un = vz + wx * ry - wy * rx
            total = pn + (goal - un) * mn
            if total < 0.0:
                total = 0.0
            d = total - pn
            if d != 0.0:
                vz += im * d
                wx += d * nx
                wy += d * ny
                wz += d * nz
                change = abs(d) * kn
                if change > largest:
                    largest = change
                pn = total
            # Friction: both tangential impulses within the cone |P_t| <= mu P_n.
            ut = vx + wy * rz - wz * ry
            ub = vy + wz * rx - wx * rz
            at = pt - ut * mt
            ab = pb - ub * mb
            bound = friction * pn
            size = math.sqrt(at * at + ab * ab)
            if size > bound:
                scale = bound / size
                at *= scale
                ab *= scale
            dt, db = at - pt, ab - pb
            if dt != 0.0 or db != 0.0:
                vx += im * dt
                vy += im * db
                wx += dt * tx + db * bx
                wy += dt * ty + db * by
                wz += dt * tz + db * bz
                change = abs(dt) / mt + abs(db) / mb
                if change > largest:
                    largest = change
                pt, pb = at, ab
            row[19], row[20], row[21] = pn, pt, pb
        if largest <= CONVERGED_SPEED:
            break
    if bounces:
        vx, vy, vz, wx, wy, wz = _bounce(
            rows, (v, w), (vx, vy, vz, wx, wy, wz), rotation=rotation,
            inverse_mass=inverse_mass, inertia=inertia, gravity=gravity, h=h,
            iterations=iterations)
    # Split impulses: pseudo-velocities that remove POSITION_RATE of the penetration beyond
    # the slop in this substep's position update, and change no velocity.
    mvx = mvy = mvz = mwx = mwy = mwz = 0.0
    deep = [row for row in rows if row[4] < -slop]
    if deep:
        pushes = [0.0] * len(deep)
        for _ in range(iterations):
            largest = 0.0
            for k, row in enumerate(deep):
                rx, ry, s, nx, ny, nz, mn, kn = row[1], row[2], row[4], row[5], row[6], \
                    row[7], row[15], row[14]
                goal = POSITION_RATE * (-s - slop) / h
                un = mvz + mwx * ry - mwy * rx
                total = pushes[k] + (goal - un) * mn
                if total < 0.0:
                    total = 0.0
                d = total - pushes[k]
                if d != 0.0:
                    mvz += im * d
                    mwx += d * nx
                    mwy += d * ny
                    mwz += d * nz
                    pushes[k] = total
                    change = abs(d) * kn
                    if change > largest:
                        largest = change
            if largest <= CONVERGED_SPEED:
                break
    return ((vx, vy, vz), (wx, wy, wz),
            ((vx + mvx, vy + mvy, vz + mvz), (wx + mwx, wy + mwy, wz + mwz)), rows)


def contact_points(position: Vector3, rows: Rows) -> Tuple[Tuple[int, Vector3, float], ...]:
    """Return (corner index, world point (m), normal impulse (N s)) of ``solve``'s contacts."""
    px, py, pz = position
    return tuple((row[0], (px + row[1], py + row[2], pz + row[3]), row[19]) for row in rows)


def _bounce(rows: Rows, before: Tuple[Vector3, Vector3], after: Tuple[float, ...], *,
            rotation, inverse_mass: float, inertia, gravity: Vector3, h: float,
            iterations: int) -> Tuple[float, ...]:
    """
    Return the velocities (vx, vy, vz, wx, wy, wz) after the bouncing contacts' restitution.

    The contacts that bounce and pushed in the solve (a positive normal impulse) are driven to
    u_n >= -e u_n0 by normal impulses alone, after friction, as Box2D v3 applies restitution.
    Newton's restitution with friction and several contacts can gain energy (Kane's paradox),
    and so can the discrete step: a corner reversed after gravity's kick h g of the substep
    leaves h |g| faster than it came and climbs h v in the position update, 2 m |g| h v of energy
    per bounce. The result is therefore pulled back along the restitution's impulse, as far as
    needed, to the energy (kinetic, and potential after the position update) the body would have
    had without the floor, or after the solve without restitution if that is more: the contacts
    never add energy.
    """
    vx, vy, vz, wx, wy, wz = after
    im = inverse_mass
    bouncing = [row for row in rows if row[22] is not None and row[19] > 0.0]
    if not bouncing:
        return after
    start = [row[19] for row in bouncing]
    for _ in range(iterations):
        largest = 0.0
        for row in bouncing:
            rx, ry, nx, ny, nz, kn, mn, pn, goal = row[1], row[2], row[5], row[6], row[7], \
                row[14], row[15], row[19], row[22]
            un = vz + wx * ry - wy * rx
            total = pn + (goal - un) * mn
            if total < 0.0:
                total = 0.0
            d = total - pn
            if d != 0.0:
                vz += im * d
                wx += d * nx
                wy += d * ny
                wz += d * nz
                row[19] = total
                change = abs(d) * kn
                if change > largest:
                    largest = change
        if largest <= CONVERGED_SPEED:
            break
    # The change, and the largest share alpha of it that keeps the energy at most the cap.
    ax, ay, az, bx, by, bz = after
    dvx, dvy, dvz, dwx, dwy, dwz = vx - ax, vy - ay, vz - az, wx - bx, wy - by, wz - bz
    mass = 1.0 / im
    i00, i01, i02, i11, i12, i22 = congruence(rotation, inertia)
    # Twice the energy after this substep's position update, but for a constant: the kinetic
    # energy and the potential energy -m g . (x + h v) it moves to.
    gx, gy, gz = (2.0 * h * c for c in gravity)

    def twice_energy(ux, uy, uz, ox, oy, oz):
        return (mass * (ux * (ux - gx) + uy * (uy - gy) + uz * (uz - gz))
                + ox * (i00 * ox + i01 * oy + i02 * oz) + oy * (i01 * ox + i11 * oy + i12 * oz)
                + oz * (i02 * ox + i12 * oy + i22 * oz))

    (ux, uy, uz), (ox, oy, oz) = before
    cap = max(twice_energy(ux, uy, uz, ox, oy, oz), twice_energy(*after))
    if twice_energy(vx, vy, vz, wx, wy, wz) <= cap:
        return vx, vy, vz, wx, wy, wz
    quadratic = (mass * (dvx * dvx + dvy * dvy + dvz * dvz)
                 + dwx * (i00 * dwx + i01 * dwy + i02 * dwz)
                 + dwy * (i01 * dwx + i11 * dwy + i12 * dwz)
                 + dwz * (i02 * dwx + i12 * dwy + i22 * dwz))
    linear = (mass * (dvx * (2.0 * ax - gx) + dvy * (2.0 * ay - gy) + dvz * (2.0 * az - gz))
              + 2.0 * (dwx * (i00 * bx + i01 * by + i02 * bz)
                       + dwy * (i01 * bx + i11 * by + i12 * bz)
                       + dwz * (i02 * bx + i12 * by + i22 * bz)))
    constant = twice_energy(*after) - cap
    if quadratic > 0.0:
        alpha = (-linear + math.sqrt(max(0.0, linear * linear - 4.0 * quadratic * constant))) \
            / (2.0 * quadratic)
        alpha = min(max(alpha, 0.0), 1.0)
    else:
        alpha = 0.0
    for row, impulse in zip(bouncing, start):
        row[19] = impulse + alpha * (row[19] - impulse)
    return (ax + alpha * dvx, ay + alpha * dvy, az + alpha * dvz,
            bx + alpha * dwx, by + alpha * dwy, bz + alpha * dwz)
