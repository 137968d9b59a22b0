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
Body-plane contact: sequential impulses with accumulated clamping, warm started, split impulses.

``solve`` runs after the velocity stage of a substep (gravity, wrench, the mouse constraint),
so the floor has the last word on the velocity: a joint pulling the body into the floor is
held by it. Per contact point r (from the COM, world frame;
``collision.CollisionShape.contacts``), normal n = z and the tangents x and y of the world
frame, the velocity of the point is u = v + w x r and an impulse P along a
direction d changes it by K P, K = 1 / m + (r x d) . I_w^-1 (r x d).

- Normal: the accumulated impulse stays >= 0. A speculative contact (the point s > 0 above the
  plane) asks only u_n >= -s / h, so the point reaches the plane within the substep but does
  not pass it; a touching one (s <= 0) asks u_n >= 0; a contact approaching faster than the
  restitution threshold that reaches the plane in the substep asks u_n >= -e u_n0 (u_n0 its
  velocity before the solve), in a pass after the sweeps (``floor_energy.bounce``).
- Friction: both tangential impulses together stay within the cone |P_t| <= mu P_n.
- Sweeps: a contact's friction, then its normal row (``_sweeps``), so that each sweep ends
  with non-penetration met. Where the rows couple strongly the sweeps alone settle slowly: a
  many-vertex hull's few contacts close together, and any body whose inertia is far from
  m r^2 (a row's effective mass is then that of turning the body, not of lifting it). After a
  sweep that has not converged, two to four contacts' normal rows are solved together,
  exactly (``normal_block``); sweeps that end unconverged leave the pushing contacts to be
  held at once, friction and all, where they can be (``floor_sticking``).
- Warm start: each contact starts from the impulses its point had in the previous substep;
  if the sweeps end unconverged with more energy than the substep started with
  (``floor_energy.twice_energy``), the contacts are solved again from zero impulses.
- Position: penetration deeper than ``slop`` is removed by split impulses, pseudo-velocities
  solved like the normal rows (rate ``POSITION_RATE`` per substep) that move the body in this
  substep's position update and are then dropped, so the correction adds no kinetic energy.

The phases, named as Box2D's contact solver names its own: prepare (``_prepare``: the
contacts within reach, their effective masses and goals, ``contact_row``'s slots), warm start
(``_warm_start``), solve (``_sweeps``, with ``normal_block`` and ``floor_sticking``, and the
cold solve where a warm start gained energy), restitution (``floor_energy.bounce``), position
(``_split_impulses``) and store (the contacts ``solve`` returns keep their impulses).

The arithmetic is written out on floats, as in ``kernel``: a contact costs some thirty
operations per sweep, and Python calls and tuples would cost more than that.
"""

import math
import sys
from typing import List, Optional, Tuple

from . import floor_energy, floor_sticking, normal_block
from .algebra import congruence, rotation_matrix, Vector3
from .contact_row import (BITANGENT_IMPULSE, BITANGENT_MASS, BITANGENT_TURN_X, BITANGENT_TURN_Y,
                          BITANGENT_TURN_Z, IMPULSES, LEVER_X, LEVER_Y, LEVER_Z, NORMAL_IMPULSE,
                          NORMAL_MASS, NORMAL_STIFFNESS, NORMAL_TURN_X, NORMAL_TURN_Y,
                          NORMAL_TURN_Z, POINT, SEPARATION, TANGENT_IMPULSE, TANGENT_MASS,
                          TANGENT_TURN_X, TANGENT_TURN_Y, TANGENT_TURN_Z)
from .floor_energy import CONVERGED_SPEED, twice_energy

# Fraction of the penetration beyond the slop that the split impulses remove per substep.
POSITION_RATE = 0.2
# m r^2 / I beyond which a box's normal rows are solved as a block (``_strongly_coupled``): a
# URDF written in grams gives thousands; a box's own inertia, 3 to 15.
COUPLED_RATIO = 100.0

# The share of a contact's normal impulse within which its impulses' changes in a sweep are
# their rounding (16 units in the last place; a resting body's chatter is within 2 or 3).
IMPULSE_ROUNDING = 16.0 * sys.float_info.epsilon

# The contacts as ``solve`` keeps them: a list of ``contact_row.SLOTS`` floats each, read and
# written by their slots' names (``contact_row``).
Rows = List[list]


def touching(coefficients: Tuple, pz: float, q) -> bool:
    """
    Return whether the body's lowest point is within the margin of the plane.

    A body whose bounding ball stays above the margin is not touching, without a look at its
    pieces; otherwise the reach below the COM is ``Floor.depth``'s (``CollisionShape.reach``).
    """
    height, shape, margin = coefficients[0], coefficients[1], coefficients[5]
    base = pz - height
    if base - shape.bound > margin:
        return False
    x, y, z, w = q
    rotation = (0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 2.0 * (x * z - w * y), 2.0 * (y * z + w * x),
                1.0 - 2.0 * (x * x + y * y))
    if shape.cylinders:
        rotation = rotation_matrix(q)
    return base - shape.reach(rotation) <= margin


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
    :param gravity: the gravitational acceleration (m/s^2), for the energy the contacts may
        leave (a bounce's, a warm start's).
    :param warm: the previous substep's contacts (``Rows``), whose impulses the contacts of
        the same points start from.
    :returns: (v, w) after the contacts; (v, w) plus the split impulses' pseudo-velocities,
        for the position update; and the contacts (``Rows``, see ``contact_points``), the
        points of ``collision.CollisionShape.contacts``.
    """
    (height, shape, friction, restitution, iterations, margin, slop,
     threshold) = coefficients
    # R(q), as algebra.rotation_matrix and kernel.velocities write it out.
    x, y, z, qw = q
    xx, yy, zz = x * x, y * y, z * z
    xy, xz, yz = x * y, x * z, y * z
    wx_, wy_, wz_ = qw * x, qw * y, qw * z
    rotation = (1.0 - 2.0 * (yy + zz), 2.0 * (xy - wz_), 2.0 * (xz + wy_),
                2.0 * (xy + wz_), 1.0 - 2.0 * (xx + zz), 2.0 * (yz - wx_),
                2.0 * (xz - wy_), 2.0 * (yz + wx_), 1.0 - 2.0 * (xx + yy))
    world_inverse = congruence(rotation, inverse_inertia)
    im = inverse_mass
    # 1. prepare: the contacts within reach, their effective masses, goals and bounces.
    rows, bounces = _prepare(shape, rotation, world_inverse, position[2] - height, margin, slop,
                             h, im, (*v, *w), restitution, threshold)
    # 2. warm start: each contact from the impulses its point had in the last substep.
    velocities, warmed = _warm_start(rows, warm, (*v, *w), im)
    # 3. solve: the sweeps, a block solve of the normal rows, the sticking contacts at once.
    i00, i01, _, i11, _, _ = world_inverse
    block = (im, i00, i01, i11) if 1 < len(rows) <= normal_block.MOST_CONTACTS and (
        shape.hull is not None or _strongly_coupled(shape.bound, im, inverse_inertia)) else None
    velocities, converged = _sweeps(rows, velocities, im, friction, iterations, block)
    if not converged:
        # Sweeps that did not settle: the pushing contacts held at once, if they can be.
        held = floor_sticking.stick(rows, velocities, im, congruence(rotation, inertia),
                                    friction, CONVERGED_SPEED)
        if held is not None:
            velocities, converged = held, True
    if warmed and not converged and _gained_energy(velocities, (v, w), rotation, inertia, im,
                                                   gravity, h):
        # A warm start that the sweeps could not undo may leave an old impulse pushing a
        # contact that now separates, which adds energy. Then the contacts are solved cold.
        for row in rows:
            row[IMPULSES] = (0.0, 0.0, 0.0)
        velocities, _ = _sweeps(rows, (*v, *w), im, friction, iterations, block)
    # 4. restitution: the contacts that bounce, driven to their bounce velocity.
    if bounces:
        velocities = floor_energy.bounce(
            rows, (v, w), velocities, rotation=rotation, inverse_mass=inverse_mass,
            inertia=inertia, gravity=gravity, h=h, iterations=iterations)
    vx, vy, vz, wx, wy, wz = velocities
    # 5. position: the split impulses' pseudo-velocities; 6. store: the contacts returned keep
    # their impulses, the next substep's warm start.
    mvx, mvy, mvz, mwx, mwy, mwz = _split_impulses(rows, slop, h, im, iterations)
    return ((vx, vy, vz), (wx, wy, wz),
            ((vx + mvx, vy + mvy, vz + mvz), (wx + mwx, wy + mwy, wz + mwz)), rows)


def _strongly_coupled(bound: float, im: float, inverse_inertia) -> bool:
    """
    Return whether the body's inertia is so far below m r^2 that sweeps alone cannot lift it.

    A contact row's effective mass is then that of turning the body, a fraction I / (m r^2) of
    its mass, and the normal rows are solved as a block after a sweep that did not converge.
    For a body whose inertia suits its size (a box's m r^2 / I is some 3 to 15) the sweeps
    settle within their iterations, and the block's factorizations would cost a body dragged
    across the floor ten times the sweeps.

    :param bound: the shape's bounding radius r (m).
    :param inverse_inertia: I_b^-1 as a symmetric 6-tuple: its diagonal bounds 1 / I.
    """
    largest = max(inverse_inertia[0], inverse_inertia[3], inverse_inertia[5])
    return bound * bound * largest > COUPLED_RATIO * im


def _prepare(shape, rotation: Tuple[float, ...], world_inverse: Tuple[float, ...],
             base: float, margin: float, slop: float, h: float, im: float,
             velocities: Tuple[float, ...], restitution: float,
             threshold: float) -> Tuple[Rows, bool]:
    """
    Return the contacts within reach of the plane (``contact_row``), and if any bounces.

    Their impulses start at zero (``_warm_start`` gives them the last substep's).

    :param base: the COM's height above the plane (m).
    :param velocities: (v, w) after the velocity stage: the speeds of approach.
    """
    i00, i01, i02, i11, i12, i22 = world_inverse
    vx, vy, vz, wx, wy, wz = velocities
    rows = []
    bounces = False
    # What the substep can bring down to the plane: the slop, and twice the fastest a point
    # within the shape's bound moves down in a substep (the warm start and the sweeps change
    # the velocity: twice leaves room).
    band = slop + 2.0 * h * (abs(vz) + math.sqrt(wx * wx + wy * wy + wz * wz) * shape.bound)
    for index, rx, ry, rz, s in shape.contacts(rotation, base, margin, band):
        # I_w^-1 (r x d) and K for d = z, x, y.
        nx, ny, nz = i00 * ry - i01 * rx, i01 * ry - i11 * rx, i02 * ry - i12 * rx
        tx, ty, tz = i01 * rz - i02 * ry, i11 * rz - i12 * ry, i12 * rz - i22 * ry
        bx, by, bz = i02 * rx - i00 * rz, i12 * rx - i01 * rz, i22 * rx - i02 * rz
        kn = im + ry * nx - rx * ny
        kt = im + rz * ty - ry * tz
        kb = im + rx * bz - rz * bx
        approach = vz + wx * ry - wy * rx
        goal = -s / h if s > 0.0 else 0.0
        if restitution > 0.0 and approach < -threshold and approach * h <= -s:
            bounces = True
            bounce = -restitution * approach
        else:
            bounce = None
        # The slots in ``contact_row`` order.
        rows.append([index, rx, ry, rz, s, nx, ny, nz, tx, ty, tz, bx, by, bz,
                     kn, 1.0 / kn, 1.0 / kt, 1.0 / kb, goal, 0.0, 0.0, 0.0, bounce])
    return rows, bounces


def _warm_start(rows: Rows, warm: Rows, velocities: Tuple[float, ...],
                im: float) -> Tuple[Tuple[float, ...], bool]:
    """
    Return the velocities with each contact's last impulses applied, and if any was.

    A contact takes the impulses of the last substep's contact of the same point.
    """
    vx, vy, vz, wx, wy, wz = velocities
    previous = {row[POINT]: row for row in warm}
    warmed = False
    for row in rows:
        last = previous.get(row[POINT])
        if last is None:
            continue
        pn = row[NORMAL_IMPULSE] = last[NORMAL_IMPULSE]
        pt = row[TANGENT_IMPULSE] = last[TANGENT_IMPULSE]
        pb = row[BITANGENT_IMPULSE] = last[BITANGENT_IMPULSE]
        warmed = True
        vx += im * pt
        vy += im * pb
        vz += im * pn
        wx += pn * row[NORMAL_TURN_X] + pt * row[TANGENT_TURN_X] + pb * row[BITANGENT_TURN_X]
        wy += pn * row[NORMAL_TURN_Y] + pt * row[TANGENT_TURN_Y] + pb * row[BITANGENT_TURN_Y]
        wz += pn * row[NORMAL_TURN_Z] + pt * row[TANGENT_TURN_Z] + pb * row[BITANGENT_TURN_Z]
    return (vx, vy, vz, wx, wy, wz), warmed


def _gained_energy(velocities: Tuple[float, ...], before: Tuple[Vector3, Vector3],
                   rotation: Tuple[float, ...], inertia, im: float, gravity: Vector3,
                   h: float) -> bool:
    """Return whether the contacts left the body more energy than it came with."""
    world_inertia = congruence(rotation, inertia)
    kick = tuple(2.0 * h * c for c in gravity)
    mass = 1.0 / im
    allowed = twice_energy((*before[0], *before[1]), mass, world_inertia, kick) + mass * h * h * (
        gravity[0] * gravity[0] + gravity[1] * gravity[1] + gravity[2] * gravity[2])
    return twice_energy(velocities, mass, world_inertia, kick) > allowed


def _split_impulses(rows: Rows, slop: float, h: float, im: float,
                    iterations: int) -> Tuple[float, ...]:
    """
    Return the split impulses' pseudo-velocities (v, w): the penetration's correction.

    They remove ``POSITION_RATE`` of each contact's penetration beyond the slop in this
    substep's position update, and are then dropped: the correction changes no velocity. The
    loop is ``_sweeps``' normal row on the pseudo-velocities, written out as it is there (the
    hot loop's cost).
    """
    mvx = mvy = mvz = mwx = mwy = mwz = 0.0
    deep = [row for row in rows if row[SEPARATION] < -slop]
    if not deep:
        return mvx, mvy, mvz, mwx, mwy, mwz
    pushes = [0.0] * len(deep)
    for _ in range(iterations):
        largest = 0.0
        for k, row in enumerate(deep):
            rx, ry, s = row[LEVER_X], row[LEVER_Y], row[SEPARATION]
            nx, ny, nz = row[NORMAL_TURN_X], row[NORMAL_TURN_Y], row[NORMAL_TURN_Z]
            mn, kn = row[NORMAL_MASS], row[NORMAL_STIFFNESS]
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
    return mvx, mvy, mvz, mwx, mwy, mwz


def _sweeps(rows: Rows, velocities: Tuple[float, ...], im: float, friction: float,
            iterations: int, block: Optional[Tuple[float, float, float, float]] = None
            ) -> Tuple[Tuple[float, ...], bool]:
    """
    Return the velocities after the sequential-impulse sweeps over ``rows``, and if converged.

    Converged: the last sweep changed no contact's velocity by more than ``CONVERGED_SPEED``,
    or by more than the rounding of the contacts' impulses moves it (``_rounding``).
    With ``block``, a sweep that has not converged is followed by ``normal_block``'s exact
    solve of the normal rows, which the next sweep then confirms or refines.
    Each sweep solves a contact's friction, then its normal row, so that the sweep ends with
    the contact's non-penetration met, whatever friction did to it; normal first, friction's
    change of the normal velocity (a corner's lever arm couples them) can undo the normal
    impulse, and the sweeps then alternate between two states instead of converging.
    """
    # The impulses' slots as locals: the loop below stores them for every contact and sweep.
    normal, tangent, bitangent = NORMAL_IMPULSE, TANGENT_IMPULSE, BITANGENT_IMPULSE
    vx, vy, vz, wx, wy, wz = velocities
    memo = []
    for _ in range(iterations):
        largest = 0.0
        for row in rows:
            (_, rx, ry, rz, _, nx, ny, nz, tx, ty, tz, bx, by, bz, kn, mn, mt, mb, goal,
             pn, pt, pb, _) = row
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
            # Normal: u_n >= goal with an accumulated impulse >= 0. Written out here and in
            # floor_energy.bounce (its twin, the hot loop's cost); test_floor_contact's energy
            # and rebound tests hold both to the same row.
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
            row[normal], row[tangent], row[bitangent] = pn, pt, pb
        if largest <= CONVERGED_SPEED or largest <= _rounding(rows):
            return (vx, vy, vz, wx, wy, wz), True
        if block is not None:
            impulses = normal_block.impulses(rows, vz, wx, wy, block, CONVERGED_SPEED, memo)
            if impulses is None:
                block = None
                continue
            for row, total in zip(rows, impulses):
                d = total - row[NORMAL_IMPULSE]
                if d != 0.0:
                    vz += im * d
                    wx += d * row[NORMAL_TURN_X]
                    wy += d * row[NORMAL_TURN_Y]
                    wz += d * row[NORMAL_TURN_Z]
                    row[NORMAL_IMPULSE] = total
    return (vx, vy, vz, wx, wy, wz), False


def _rounding(rows: Rows) -> float:
    """
    Return the most a contact's velocity changes in a sweep by the rounding of the impulses (m/s).

    An accumulated impulse P is rounded to some 1e-16 of itself at each update, and a change of
    the impulses by that moves a contact's velocity by that times its stiffness: for a body whose
    impulses are large and whose contacts are stiff (1e12 kg on a small inertia, m r^2 / I some
    1e12) more than ``CONVERGED_SPEED``, and the sweeps would never settle on the rounding's
    chatter. A contact's friction impulses stay within mu P_n, so its normal impulse P_n bounds
    their rounding too. For any body whose m r^2 / I is below some 1e8 this is below
    ``CONVERGED_SPEED``, and the sweeps stop where they always did.
    """
    largest = 0.0
    for row in rows:
        stiffness = max(row[NORMAL_STIFFNESS], 1.0 / row[TANGENT_MASS] + 1.0 / row[BITANGENT_MASS])
        largest = max(largest, row[NORMAL_IMPULSE] * stiffness)
    return IMPULSE_ROUNDING * largest


def contact_points(position: Vector3, rows: Rows) -> Tuple[Tuple[int, Vector3, float], ...]:
    """Return (contact index, world point (m), normal impulse (N s)) of ``solve``'s contacts."""
    px, py, pz = position
    return tuple((row[POINT], (px + row[LEVER_X], py + row[LEVER_Y], pz + row[LEVER_Z]),
                  row[NORMAL_IMPULSE]) for row in rows)
