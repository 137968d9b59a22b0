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
A polynomial of time about a point, in 3D: the target stream's fit, made and evaluated.

``cross_validated`` fits a weighted least-squares polynomial of the degree the points bear.
``polynomial`` makes p(t) = p0 + c_1 tau + ... + c_d tau^d (tau = t - t0, d <= 4) and
``evaluate`` returns its position and velocity at a time, ``around`` before t0 too. A line or a
parabola (the arrival-timed fit) is evaluated as written; a higher degree (the stamped fit) by
Horner's scheme on coefficients laid out per axis, written out: it runs in every substep of a
drag.
"""

import math
from typing import Optional, Tuple

import numpy as np

from .algebra import Vector3

ZERO: Vector3 = (0.0, 0.0, 0.0)

# (t0, p0, (c_1, ..., c_d), per-axis quartic or None): made by ``polynomial``.
Curve = Tuple[float, Vector3, Tuple[Vector3, ...], Optional[Tuple[Tuple[float, ...], ...]]]


def polynomial(t0: float, p0: Vector3, coefficients: Tuple[Vector3, ...]) -> Curve:
    """
    Return the polynomial p(t) = p0 + c_1 tau + ... + c_d tau^d, tau = t - t0, for ``evaluate``.

    Above degree 2 the coefficients are also laid out per axis, padded to a quartic, with the
    derivative's (c_1, c_2, c_3, c_4, 2 c_2, 3 c_3, 4 c_4): evaluated every substep, written out.
    """
    quartic = None
    if len(coefficients) > 2:
        padded = list(coefficients) + [ZERO] * (4 - len(coefficients))
        quartic = tuple((padded[0][i], padded[1][i], padded[2][i], padded[3][i],
                         2.0 * padded[1][i], 3.0 * padded[2][i], 4.0 * padded[3][i])
                        for i in range(3))
    return (t0, p0, coefficients, quartic)


def evaluate(curve: Curve, time: float) -> Tuple[Vector3, Vector3]:
    """Return the position and velocity of ``curve`` at ``time`` (a time before t0 is t0)."""
    t0, p, coefficients, quartic = curve
    tau = max(time - t0, 0.0)
    if quartic is None:
        # A line or a parabola: p + v tau + c_2 tau^2 and v + 2 c_2 tau.
        v = coefficients[0]
        c = coefficients[1] if len(coefficients) == 2 else ZERO
        square = tau * tau
        return ((p[0] + v[0] * tau + c[0] * square, p[1] + v[1] * tau + c[1] * square,
                 p[2] + v[2] * tau + c[2] * square),
                (v[0] + 2.0 * c[0] * tau, v[1] + 2.0 * c[1] * tau, v[2] + 2.0 * c[2] * tau))
    # Horner's scheme, per axis.
    (ax, bx, cx, dx, bx2, cx3, dx4), (ay, by, cy, dy, by2, cy3, dy4), \
        (az, bz, cz, dz, bz2, cz3, dz4) = quartic
    return ((p[0] + tau * (ax + tau * (bx + tau * (cx + tau * dx))),
             p[1] + tau * (ay + tau * (by + tau * (cy + tau * dy))),
             p[2] + tau * (az + tau * (bz + tau * (cz + tau * dz)))),
            (ax + tau * (bx2 + tau * (cx3 + tau * dx4)),
             ay + tau * (by2 + tau * (cy3 + tau * dy4)),
             az + tau * (bz2 + tau * (cz3 + tau * dz4))))


def around(curve: Curve, time: float) -> Tuple[Vector3, Vector3]:
    """Return ``evaluate(curve, time)``, before t0 too: the polynomial there, not p0."""
    t0, p, coefficients, _ = curve
    tau = time - t0
    if tau >= 0.0:
        return evaluate(curve, time)
    position, velocity, power = list(p), [0.0, 0.0, 0.0], 1.0
    for k, c in enumerate(coefficients, start=1):
        for i in range(3):
            velocity[i] += k * c[i] * power
        power *= tau
        for i in range(3):
            position[i] += c[i] * power
    return (position[0], position[1], position[2]), (velocity[0], velocity[1], velocity[2])


def cross_validated(times: np.ndarray, values: np.ndarray, weights: np.ndarray,
                    most: int) -> np.ndarray:
    """
    Return the weighted least-squares polynomial of the degree, at most ``most``, the data bear.

    The degree d minimizes generalized cross-validation, n RSS_d / (n - d - 1)^2 (Craven and
    Wahba): a curve's points (a circle's, exact) fall on a quartic and take it; a still
    pointer's jitter is no curve and takes degree 0, so that it is not extrapolated and its
    wander is not amplified. Two points give their line. Rows are the coefficients of
    tau^0 .. tau^d per axis.
    """
    count = len(times)
    if count == 2:
        # Two points are a line: nothing to cross-validate.
        return np.linalg.solve(np.vander(times, 2, increasing=True), values)
    top = min(most, count - 2)
    weighted = values * weights[:, None]
    # One QR of the highest degree's design serves every lower one: the columns of Q^T y past
    # a degree's d + 1 are its residual.
    q, r = np.linalg.qr(np.vander(times, top + 1, increasing=True) * weights[:, None])
    projected = q.T @ weighted
    left = float(np.sum(weighted * weighted))
    best, best_score = 0, math.inf
    for degree in range(top + 1):
        left -= float(np.sum(projected[degree] * projected[degree]))
        score = count * max(left, 0.0) / (count - degree - 1) ** 2
        # A tie (exact data, zero residuals) goes to the lower degree.
        if score < best_score * (1.0 - 1e-9):
            best, best_score = degree, score
    size = best + 1
    return np.linalg.solve(r[:size, :size], projected[:size])
