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
The energy the floor's contacts may leave the body with.

``twice_energy`` is the measure: kinetic energy, and the potential energy after the substep's
position update. ``bounce`` applies restitution after the sweeps of ``floor_contact.solve`` and
pulls it back, as far as needed, so that a bounce adds no energy.
"""

import math
from typing import List, Tuple

from .algebra import congruence, Vector3
from .contact_row import (BOUNCE, GOAL, LEVER_X, LEVER_Y, NORMAL_IMPULSE, NORMAL_MASS,
                          NORMAL_STIFFNESS, NORMAL_TURN_X, NORMAL_TURN_Y, NORMAL_TURN_Z)

# Sweeps stop once no impulse changed a contact's velocity by more than this (m/s).
CONVERGED_SPEED = 1e-9


def twice_energy(velocities: Tuple[float, ...], mass: float, world_inertia,
                 kick: Vector3) -> float:
    """
    Return twice the energy after the substep's position update, but for a constant.

    The kinetic energy of ``velocities`` (vx, vy, vz, wx, wy, wz) and the potential energy
    -m g . (x + h v) the position update moves the COM to; ``kick`` is 2 h g and
    ``world_inertia`` the world-frame I_w as a symmetric 6-tuple.
    """
    ux, uy, uz, ox, oy, oz = velocities
    gx, gy, gz = kick
    i00, i01, i02, i11, i12, i22 = world_inertia
    return (mass * (ux * (ux - gx) + uy * (uy - gy) + uz * (uz - gz))
            + ox * (i00 * ox + i01 * oy + i02 * oz) + oy * (i01 * ox + i11 * oy + i12 * oz)
            + oz * (i02 * ox + i12 * oy + i22 * oz))


def bounce(rows: List[list], before: Tuple[Vector3, Vector3], after: Tuple[float, ...], *,
           rotation, inverse_mass: float, inertia, gravity: Vector3, h: float,
           iterations: int) -> Tuple[float, ...]:
    """
    Return the velocities (vx, vy, vz, wx, wy, wz) after the bouncing contacts' restitution.

    The contacts that bounce and pushed in the solve (a positive normal impulse) are driven to
    u_n >= -e u_n0 by normal impulses alone, after friction, as Box2D v3 applies restitution;
    the other contacts keep their own goals (row 18) in the same pass, so that a corner's
    bounce, turning the box, does not drive another corner into the floor.
    Newton's restitution with friction and several contacts can gain energy (Kane's paradox),
    and so can the discrete step: a corner reversed after gravity's kick h g of the substep
    leaves h |g| faster than it came and climbs h v in the position update, 2 m |g| h v of energy
    per bounce. The result is therefore pulled back along the pass's impulses, as far as
    needed, to the energy (kinetic, and potential after the position update) the body would have
    had without the floor, or after the solve without restitution if that is more: the contacts
    never add energy.
    """
    vx, vy, vz, wx, wy, wz = after
    im = inverse_mass
    if not any(row[BOUNCE] is not None and row[NORMAL_IMPULSE] > 0.0 for row in rows):
        return after
    # Every contact takes part: a bouncing corner's push turns the box, and its other corners
    # in contact hold their own goal (u_n >= -s / h, or >= 0) against it.
    bouncing = [row[BOUNCE] is not None and row[NORMAL_IMPULSE] > 0.0 for row in rows]
    goals = [row[BOUNCE] if bounces else row[GOAL] for row, bounces in zip(rows, bouncing)]
    start = [row[NORMAL_IMPULSE] for row in rows]
    vx, vy, vz, wx, wy, wz = _normal_pass(rows, goals, after, inverse_mass, iterations)
    bounced = [row[NORMAL_IMPULSE] for row in rows]
    mass = 1.0 / im
    i00, i01, i02, i11, i12, i22 = congruence(rotation, inertia)
    world_inertia = (i00, i01, i02, i11, i12, i22)
    kick = tuple(2.0 * h * c for c in gravity)
    gx, gy, gz = kick

    def energy(*velocities):
        return twice_energy(velocities, mass, world_inertia, kick)

    cap = max(energy(*before[0], *before[1]), energy(*after))
    if energy(vx, vy, vz, wx, wy, wz) <= cap:
        return vx, vy, vz, wx, wy, wz
    # Pulled back toward the bouncing corners stopped on the floor (u_n = 0): the bounce is
    # scaled down as a whole, a lower restitution, and stays as symmetric as the impact was.
    # (The solve's own result would do too, but its speculative rows turn the box to land its
    # corners together, and a share of that turn, kept, grows bounce after bounce.)
    for row, impulse in zip(rows, start):
        row[NORMAL_IMPULSE] = impulse
    stopped = [0.0 if bounces else goal for goal, bounces in zip(goals, bouncing)]
    ax, ay, az, bx, by, bz = _normal_pass(rows, stopped, after, inverse_mass, iterations)
    base = [row[NORMAL_IMPULSE] for row in rows]
    dvx, dvy, dvz, dwx, dwy, dwz = vx - ax, vy - ay, vz - az, wx - bx, wy - by, wz - bz
    quadratic = (mass * (dvx * dvx + dvy * dvy + dvz * dvz)
                 + dwx * (i00 * dwx + i01 * dwy + i02 * dwz)
                 + dwy * (i01 * dwx + i11 * dwy + i12 * dwz)
                 + dwz * (i02 * dwx + i12 * dwy + i22 * dwz))
    linear = (mass * (dvx * (2.0 * ax - gx) + dvy * (2.0 * ay - gy) + dvz * (2.0 * az - gz))
              + 2.0 * (dwx * (i00 * bx + i01 * by + i02 * bz)
                       + dwy * (i01 * bx + i11 * by + i12 * bz)
                       + dwz * (i02 * bx + i12 * by + i22 * bz)))
    constant = energy(ax, ay, az, bx, by, bz) - cap
    if quadratic > 0.0 and constant <= 0.0:
        alpha = (-linear + math.sqrt(max(0.0, linear * linear - 4.0 * quadratic * constant))) \
            / (2.0 * quadratic)
        alpha = min(max(alpha, 0.0), 1.0)
    else:
        alpha = 0.0
    for row, low, high in zip(rows, base, bounced):
        row[NORMAL_IMPULSE] = low + alpha * (high - low)
    return (ax + alpha * dvx, ay + alpha * dvy, az + alpha * dvz,
            bx + alpha * dwx, by + alpha * dwy, bz + alpha * dwz)


def _normal_pass(rows: List[list], goals: List[float], velocities: Tuple[float, ...],
                 inverse_mass: float, iterations: int) -> Tuple[float, ...]:
    """Return the velocities after normal rows alone drive each contact to its goal."""
    vx, vy, vz, wx, wy, wz = velocities
    im = inverse_mass
    for _ in range(iterations):
        largest = 0.0
        for row, goal in zip(rows, goals):
            rx, ry = row[LEVER_X], row[LEVER_Y]
            nx, ny, nz = row[NORMAL_TURN_X], row[NORMAL_TURN_Y], row[NORMAL_TURN_Z]
            kn, mn, pn = row[NORMAL_STIFFNESS], row[NORMAL_MASS], row[NORMAL_IMPULSE]
            # The normal row of floor_contact._sweeps (its twin), written out in the loop.
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
                row[NORMAL_IMPULSE] = total
                change = abs(d) * kn
                if change > largest:
                    largest = change
        if largest <= CONVERGED_SPEED:
            break
    return vx, vy, vz, wx, wy, wz
