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
Quaternions and 3x3 matrices on plain float tuples.

Quaternions are in ROS order (x, y, z, w) as REP 103 asks. Matrices are row-major 9-tuples and
symmetric matrices are 6-tuples in URDF order (xx, xy, xz, yy, yz, zz). Plain floats, because
numpy's per-call overhead on 3-vectors costs more than the arithmetic: a substep of the solver
would take ~80 us with numpy and takes a few microseconds like this (see ``bench/``).
"""

import math
from typing import Tuple

Vector3 = Tuple[float, float, float]
Quaternion = Tuple[float, float, float, float]
Matrix3 = Tuple[float, float, float, float, float, float, float, float, float]
Symmetric3 = Tuple[float, float, float, float, float, float]

IDENTITY_QUATERNION: Quaternion = (0.0, 0.0, 0.0, 1.0)


def rotation_matrix(q: Quaternion) -> Matrix3:
    """Return the rotation matrix of the unit quaternion ``q`` (x, y, z, w), row-major."""
    x, y, z, w = q
    xx, yy, zz = x * x, y * y, z * z
    xy, xz, yz = x * y, x * z, y * z
    wx, wy, wz = w * x, w * y, w * z
    return (
        1.0 - 2.0 * (yy + zz), 2.0 * (xy - wz), 2.0 * (xz + wy),
        2.0 * (xy + wz), 1.0 - 2.0 * (xx + zz), 2.0 * (yz - wx),
        2.0 * (xz - wy), 2.0 * (yz + wx), 1.0 - 2.0 * (xx + yy),
    )


def multiply(a: Vector3, m: Matrix3) -> Vector3:
    """Return ``M a`` for a row-major matrix ``m``."""
    x, y, z = a
    return (
        m[0] * x + m[1] * y + m[2] * z,
        m[3] * x + m[4] * y + m[5] * z,
        m[6] * x + m[7] * y + m[8] * z,
    )


def multiply_transposed(a: Vector3, m: Matrix3) -> Vector3:
    """Return ``M^T a`` for a row-major matrix ``m``."""
    x, y, z = a
    return (
        m[0] * x + m[3] * y + m[6] * z,
        m[1] * x + m[4] * y + m[7] * z,
        m[2] * x + m[5] * y + m[8] * z,
    )


def multiply_symmetric(a: Vector3, s: Symmetric3) -> Vector3:
    """Return ``S a`` for a symmetric matrix ``s`` given as (xx, xy, xz, yy, yz, zz)."""
    x, y, z = a
    sxx, sxy, sxz, syy, syz, szz = s
    return (
        sxx * x + sxy * y + sxz * z,
        sxy * x + syy * y + syz * z,
        sxz * x + syz * y + szz * z,
    )


def congruence(m: Matrix3, s: Symmetric3) -> Symmetric3:
    """Return ``M S M^T`` for a symmetric ``s``, e.g. the world inverse inertia R I_b^-1 R^T."""
    sxx, sxy, sxz, syy, syz, szz = s
    # Rows of M S.
    a0 = m[0] * sxx + m[1] * sxy + m[2] * sxz
    a1 = m[0] * sxy + m[1] * syy + m[2] * syz
    a2 = m[0] * sxz + m[1] * syz + m[2] * szz
    b0 = m[3] * sxx + m[4] * sxy + m[5] * sxz
    b1 = m[3] * sxy + m[4] * syy + m[5] * syz
    b2 = m[3] * sxz + m[4] * syz + m[5] * szz
    c0 = m[6] * sxx + m[7] * sxy + m[8] * sxz
    c1 = m[6] * sxy + m[7] * syy + m[8] * syz
    c2 = m[6] * sxz + m[7] * syz + m[8] * szz
    return (
        a0 * m[0] + a1 * m[1] + a2 * m[2],
        a0 * m[3] + a1 * m[4] + a2 * m[5],
        a0 * m[6] + a1 * m[7] + a2 * m[8],
        b0 * m[3] + b1 * m[4] + b2 * m[5],
        b0 * m[6] + b1 * m[7] + b2 * m[8],
        c0 * m[6] + c1 * m[7] + c2 * m[8],
    )


def cross(a: Vector3, b: Vector3) -> Vector3:
    """Return the cross product ``a x b``."""
    ax, ay, az = a
    bx, by, bz = b
    return (ay * bz - az * by, az * bx - ax * bz, ax * by - ay * bx)


# Twin: written out in MouseSimulation.step's substep loop (a call per substep costs); the
# test test_the_step_turns_the_body_as_integrate_orientation_does_to_the_bit keeps them equal.
def integrate_orientation(q: Quaternion, w: Vector3, h: float) -> Quaternion:
    """
    Rotate ``q`` by the world-frame angular velocity ``w`` held for ``h`` seconds.

    The increment is the exact rotation exp(w h / 2), applied on the left because ``w`` is in the
    world frame; the result is renormalized so that rounding never accumulates in the norm.
    """
    wx, wy, wz = w
    speed = math.sqrt(wx * wx + wy * wy + wz * wz)
    half_angle = 0.5 * speed * h
    if half_angle < 1e-4:
        # sin(a)/speed by its series: exact to rounding here, and finite at speed = 0.
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
    return (nx * inv_norm, ny * inv_norm, nz * inv_norm, nw * inv_norm)


def cholesky(k: Symmetric3) -> Symmetric3:
    """Return the Cholesky factor L of an SPD K = L L^T as (l00, l10, l20, l11, l21, l22)."""
    k00, k01, k02, k11, k12, k22 = k
    l00 = math.sqrt(k00)
    l10 = k01 / l00
    l20 = k02 / l00
    l11 = math.sqrt(k11 - l10 * l10)
    l21 = (k12 - l20 * l10) / l11
    return (l00, l10, l20, l11, l21, math.sqrt(k22 - l20 * l20 - l21 * l21))


def solve_cholesky(factor: Symmetric3, b: Vector3) -> Vector3:
    """Return x with L L^T x = b for a factor from ``cholesky``."""
    l00, l10, l20, l11, l21, l22 = factor
    y0 = b[0] / l00
    y1 = (b[1] - l10 * y0) / l11
    y2 = (b[2] - l20 * y0 - l21 * y1) / l22
    x2 = y2 / l22
    x1 = (y1 - l21 * x2) / l11
    return ((y0 - l10 * x1 - l20 * x2) / l00, x1, x2)
