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
The gyroscopic term of free rotation, w x (I w), integrated implicitly in the body frame.

Explicit integration of Euler's equations gains energy for a body spinning near its intermediate
axis; the implicit midpoint rule here keeps both invariants of free rotation (kinetic energy and
|L|) to rounding, and never gains energy where |w| h is too large for it to converge.
"""

import math

from typing import Tuple

from .algebra import Quaternion, Symmetric3, Vector3

# Newton iterations of the implicit midpoint gyroscopic step: at most this many, and none once
# the update is below 1e-13 of the midpoint velocity (its square is compared).
_GYROSCOPIC_ITERATIONS = 6
_CONVERGED = 1e-26
# The largest |w| h a piece of ``free_rotation`` takes, where the chord iteration converges
# within its iterations, and the most pieces a step is cut into.
PIECE_TURN = 0.1
MAX_PIECES = 1000


# Twin: gyroscopic_step_diagonal below, the same arithmetic without the off-diagonal products;
# test_physics_fast_paths.py's test_the_diagonal_gyroscopic_step_* keep the two equal to the bit.
def gyroscopic_step(inertia: Symmetric3, w: Vector3, h: float) -> Vector3:
    """
    Advance Euler's torque-free equation I dw/dt + w x (I w) = 0 by ``h``, body frame, implicitly.

    The implicit midpoint rule, I (w1 - w0) + h m x (I m) = 0 with m = (w0 + w1) / 2. Written for
    m it is I (m - w0) + (h / 2) m x (I m) = 0, backward Euler over h / 2, so its first Newton
    iteration from m = w0, with the Jacobian J = I + (h / 2) ([w0]x I - [I w0]x), is Bullet's and
    Bounce's one-step backward Euler at h / 2; further iterations reuse J^-1 (a chord method,
    converging by a factor of about (h |w|)^2 each) until the update is below 1e-13 of m. Then
    w1 = 2 m - w0.

    Solved this way the midpoint rule conserves both invariants of free rotation, the kinetic
    energy w.I w / 2 and |I w|, since both are quadratic in w. One backward-Euler step at h, as
    Bullet and Bounce take it, loses energy instead: a box spinning at 6 rad/s near its
    intermediate axis sheds 1.3 % in 10 s at h = 1 ms, and 49 % at 50 rad/s. Where the iteration
    cannot converge or finds a spurious root (|w| h of order 1 and beyond), w1 is scaled back to
    the energy of w0, so the step never gains energy, and where it overflows w0 is kept.
    """
    wx, wy, wz = w
    if wx == 0.0 and wy == 0.0 and wz == 0.0:
        return w
    ixx, ixy, ixz, iyy, iyz, izz = inertia
    k = 0.5 * h
    lx = ixx * wx + ixy * wy + ixz * wz
    ly = ixy * wx + iyy * wy + iyz * wz
    lz = ixz * wx + iyz * wy + izz * wz
    # J = I + k ([w0]x I - [I w0]x), row by row, and its inverse by Cramer's rule.
    j00 = ixx + k * (wy * ixz - wz * ixy)
    j01 = ixy + k * (wy * iyz - wz * iyy + lz)
    j02 = ixz + k * (wy * izz - wz * iyz - ly)
    j10 = ixy + k * (wz * ixx - wx * ixz - lz)
    j11 = iyy + k * (wz * ixy - wx * iyz)
    j12 = iyz + k * (wz * ixz - wx * izz + lx)
    j20 = ixz + k * (wx * ixy - wy * ixx + ly)
    j21 = iyz + k * (wx * iyy - wy * ixy - lx)
    j22 = izz + k * (wx * iyz - wy * ixz)
    c00 = j11 * j22 - j12 * j21
    c01 = j12 * j20 - j10 * j22
    c02 = j10 * j21 - j11 * j20
    det = j00 * c00 + j01 * c01 + j02 * c02
    if det == 0.0:
        # J is singular (about the intermediate axis at |w| h of order 1, to the last bit):
        # no unique step, keep w0 as where it overflows.
        return w
    inv_det = 1.0 / det
    n00, n01, n02 = c00 * inv_det, (j02 * j21 - j01 * j22) * inv_det, \
        (j01 * j12 - j02 * j11) * inv_det
    n10, n11, n12 = c01 * inv_det, (j00 * j22 - j02 * j20) * inv_det, \
        (j02 * j10 - j00 * j12) * inv_det
    n20, n21, n22 = c02 * inv_det, (j01 * j20 - j00 * j21) * inv_det, \
        (j00 * j11 - j01 * j10) * inv_det
    # The residual g(m) = I (m - w0) + k m x (I m) is k w0 x L0 at m = w0.
    gx = k * (wy * lz - wz * ly)
    gy = k * (wz * lx - wx * lz)
    gz = k * (wx * ly - wy * lx)
    mx, my, mz = wx, wy, wz
    for _ in range(_GYROSCOPIC_ITERATIONS):
        dx = n00 * gx + n01 * gy + n02 * gz
        dy = n10 * gx + n11 * gy + n12 * gz
        dz = n20 * gx + n21 * gy + n22 * gz
        mx -= dx
        my -= dy
        mz -= dz
        if dx * dx + dy * dy + dz * dz <= _CONVERGED * (mx * mx + my * my + mz * mz):
            break
        ex, ey, ez = mx - wx, my - wy, mz - wz
        ax = ixx * mx + ixy * my + ixz * mz
        ay = ixy * mx + iyy * my + iyz * mz
        az = ixz * mx + iyz * my + izz * mz
        gx = ixx * ex + ixy * ey + ixz * ez + k * (my * az - mz * ay)
        gy = ixy * ex + iyy * ey + iyz * ez + k * (mz * ax - mx * az)
        gz = ixz * ex + iyz * ey + izz * ez + k * (mx * ay - my * ax)
    # Where |w| h is of order 1 or more the iteration may stop short or at a spurious root: the
    # step must still not gain energy (nor overflow, or it keeps w0).
    vx, vy, vz = 2.0 * mx - wx, 2.0 * my - wy, 2.0 * mz - wz
    energy0 = wx * lx + wy * ly + wz * lz
    energy1 = (vx * (ixx * vx + ixy * vy + ixz * vz) + vy * (ixy * vx + iyy * vy + iyz * vz)
               + vz * (ixz * vx + iyz * vy + izz * vz))
    if not math.isfinite(energy1):
        return w
    if energy1 > energy0:
        scale = math.sqrt(energy0 / energy1)
        return (vx * scale, vy * scale, vz * scale)
    return (vx, vy, vz)


# Twin: gyroscopic_step above, written again for speed; test_physics_fast_paths.py's
# test_the_diagonal_gyroscopic_step_* keep the two equal to the bit.
def gyroscopic_step_diagonal(moments: Vector3, w: Vector3, h: float) -> Vector3:
    """
    Return ``gyroscopic_step`` for the diagonal inertia diag(``moments``), at half its cost.

    The same arithmetic in the same order with every product of an off-diagonal element (an
    exact zero, whose product with a finite number adds nothing) left out: the result is the
    general step's to the bit, up to the sign of a zero. Bodies whose frame is their principal
    frame, boxes, cylinders and most URDF links, have such an inertia.
    """
    wx, wy, wz = w
    if wx == 0.0 and wy == 0.0 and wz == 0.0:
        return w
    ixx, iyy, izz = moments
    k = 0.5 * h
    lx, ly, lz = ixx * wx, iyy * wy, izz * wz
    j00, j11, j22 = ixx, iyy, izz
    j01 = k * (lz - wz * iyy)
    j02 = k * (wy * izz - ly)
    j10 = k * (wz * ixx - lz)
    j12 = k * (lx - wx * izz)
    j20 = k * (ly - wy * ixx)
    j21 = k * (wx * iyy - lx)
    c00 = j11 * j22 - j12 * j21
    c01 = j12 * j20 - j10 * j22
    c02 = j10 * j21 - j11 * j20
    det = j00 * c00 + j01 * c01 + j02 * c02
    if det == 0.0:
        return w
    inv_det = 1.0 / det
    n00, n01, n02 = c00 * inv_det, (j02 * j21 - j01 * j22) * inv_det, \
        (j01 * j12 - j02 * j11) * inv_det
    n10, n11, n12 = c01 * inv_det, (j00 * j22 - j02 * j20) * inv_det, \
        (j02 * j10 - j00 * j12) * inv_det
    n20, n21, n22 = c02 * inv_det, (j01 * j20 - j00 * j21) * inv_det, \
        (j00 * j11 - j01 * j10) * inv_det
    gx = k * (wy * lz - wz * ly)
    gy = k * (wz * lx - wx * lz)
    gz = k * (wx * ly - wy * lx)
    mx, my, mz = wx, wy, wz
    for _ in range(_GYROSCOPIC_ITERATIONS):
        dx = n00 * gx + n01 * gy + n02 * gz
        dy = n10 * gx + n11 * gy + n12 * gz
        dz = n20 * gx + n21 * gy + n22 * gz
        mx -= dx
        my -= dy
        mz -= dz
        if dx * dx + dy * dy + dz * dz <= _CONVERGED * (mx * mx + my * my + mz * mz):
            break
        ax, ay, az = ixx * mx, iyy * my, izz * mz
        gx = ixx * (mx - wx) + k * (my * az - mz * ay)
        gy = iyy * (my - wy) + k * (mz * ax - mx * az)
        gz = izz * (mz - wz) + k * (mx * ay - my * ax)
    vx, vy, vz = 2.0 * mx - wx, 2.0 * my - wy, 2.0 * mz - wz
    energy0 = wx * lx + wy * ly + wz * lz
    energy1 = vx * (ixx * vx) + vy * (iyy * vy) + vz * (izz * vz)
    if not math.isfinite(energy1):
        return w
    if energy1 > energy0:
        scale = math.sqrt(energy0 / energy1)
        return (vx * scale, vy * scale, vz * scale)
    return (vx, vy, vz)


def free_rotation(step, inertia, w: Vector3, h: float) -> Tuple[Vector3, Quaternion]:
    """
    Return the body-frame w after torque-free rotation over ``h`` and the body's turn meanwhile.

    ``step`` is ``gyroscopic_step`` or ``gyroscopic_step_diagonal`` for ``inertia``. The midpoint
    rule maps the angular momentum L0 = I w0 to L1 = cay(-h [m]) L0 with m = (w0 + w1) / 2, a
    rotation by the Cayley transform (I (w1 - w0) = -h m x (L0 + L1) / 2 is that map written
    out). Turning the body by its inverse, cay(h [m]), the quaternion (h m / 2, 1) normalized,
    keeps the world-frame L = R L_b exactly, not only |L| and the energy: rotated by w1 h instead,
    as a held body is (its joint acts on the velocity w1), the world L drifts by O(h |w|) a step
    and a free body under a torque tau ends far from L = tau t. Where |w| h exceeds
    ``PIECE_TURN``, the step is taken in equal pieces, each one converged, so the midpoint rule
    holds in each and L is kept at any speed (at most ``MAX_PIECES`` pieces; beyond, the last
    piece's energy guard keeps the energy from growing).

    :param step: the gyroscopic step for ``inertia``.
    :param inertia: its inertia argument (moments or the symmetric 6-tuple).
    :param w: the body-frame angular velocity w0 (rad/s).
    :param h: the time (s).
    :returns: w1 and the unit quaternion (x, y, z, w) of the turn, in the body frame.
    """
    wx, wy, wz = w
    reach = math.sqrt(wx * wx + wy * wy + wz * wz) * abs(h)
    if reach <= PIECE_TURN:
        # One piece, written out (the common case, every substep of a free body).
        w1 = step(inertia, w, h)
        k = 0.25 * h
        ax, ay, az = k * (wx + w1[0]), k * (wy + w1[1]), k * (wz + w1[2])
        scale = 1.0 / math.sqrt(ax * ax + ay * ay + az * az + 1.0)
        return w1, (ax * scale, ay * scale, az * scale, scale)
    pieces = min(MAX_PIECES, math.ceil(reach / PIECE_TURN))
    k = h / pieces
    half = 0.5 * k
    tx, ty, tz, tw = 0.0, 0.0, 0.0, 1.0
    for _ in range(pieces):
        w1 = step(inertia, w, k)
        # The Cayley turn (k m / 2, 1), composed on the right: body frame.
        ax = half * 0.5 * (w[0] + w1[0])
        ay = half * 0.5 * (w[1] + w1[1])
        az = half * 0.5 * (w[2] + w1[2])
        tx, ty, tz, tw = (tw * ax + tx + ty * az - tz * ay, tw * ay + ty + tz * ax - tx * az,
                          tw * az + tz + tx * ay - ty * ax, tw - tx * ax - ty * ay - tz * az)
        # Normalized piece by piece: a product of unnormalized pieces would overflow.
        scale = 1.0 / math.sqrt(tx * tx + ty * ty + tz * tz + tw * tw)
        tx, ty, tz, tw = tx * scale, ty * scale, tz * scale, tw * scale
        w = w1
    return w, (tx, ty, tz, tw)
