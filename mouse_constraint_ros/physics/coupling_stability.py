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
The haptic loop's stability: a device coupled to the body, predicted from the step's own map.

The loop (docs/haptics.md): a haptic device, a point mass m_d with damping b_d held by a hand
(a spring k_h and damper c_h to a reference), sends its position as the target; the node steps
the body (anchor at the COM, gravity off, no guide, no feed-forward: one linear axis) and sends
back the felt force F[k] = -sum P / T, which the device holds over the next tick (zero-order
hold) while it moves. Its position reaches the node ``delay`` ticks later than in lockstep,
where the position the device reached at the end of tick k is the target of tick k + 1.

Each part is the exact discrete map of what runs:

- the body: per substep h = T / n, the soft step of ``kernel.velocities`` with the gains (a, b)
  of ``mouse_joint.soft_gains`` for k and c (``coupling_gains``): v' = (1 - a) v - b (x - u),
  x' = x + h v'; over a tick (x, v)[k] = A (x, v)[k - 1] + B u[k], A = S^n, B = sum S^j c, and
  F[k] = -(m / T) (v[k] - v[k - 1]), since the impulses sum to m (v[k] - v[k - 1]);
- the device: m_d x'' = F - b_d x' - k_h x - c_h x' (+ the hand's reference) over a tick of
  constant F, integrated exactly (the matrix exponential): w[k + 1] = Phi w[k] + Gamma F[k].

In z, F = -(m / T) (z - 1) N_v(z) / D_b(z) u with D_b = det(zI - A), N_v = e_v^T adj(zI - A) B;
x_d = N_d(z) / D_d(z) F with D_d = det(zI - Phi), N_d = e_x^T adj(zI - Phi) Gamma; and u =
z^-delay x_d. The loop's characteristic polynomial is

    p(z) = z^delay D_b(z) D_d(z) + (m / T) (z - 1) N_v(z) N_d(z),

of degree delay + 4 (the body's two states, the device's two, the delay line); the loop is
stable while every root lies inside the unit circle. ``largest_stable_stiffness`` finds the
stiffness at which the first root leaves it.

Passivity (Colgate and Schenkel's condition for a sampled virtual environment H(z) rendered by a
device of damping b: b > T / (2 (1 - cos wT)) Re{(1 - e^-jwT) H(e^jwT)} for 0 < wT <= pi):
for a virtual wall K + B (1 - z^-1) / T it is Colgate and Brown's b > K T / 2 + |B|; delayed by
d samples, H(z) z^-d, the case of Hulin, Albu-Schaeffer and Hirzinger, its low-frequency limit is
b > K T (d + 1/2) - B (``passivity_damping``). What the device renders here is the body behind
the coupling, H(z) = z^-d (m / T) (z - 1) N_v(z) / D_b(z) (``coupling_passivity_damping``): the
coupling's damper acts on the anchor's own velocity (no feed-forward: the target's velocity is
not used), so a well-damped coupling is a spring alone to the device, B = 0, and needs
b > K T (2 d + 1) / 2 (the Dirichlet kernel peaks at w = 0); a lightly damped one needs more at
the body's resonance on the spring. ``passive_stiffness`` is the largest k that a device of
damping b renders passively.
"""

from dataclasses import dataclass
import math
from typing import Tuple

import numpy as np

from .mouse_joint import coupling_gains, soft_gains

# Largest |root| the loop may have to count as stable (rounding of the roots aside).
STABLE_RADIUS = 1.0


@dataclass(frozen=True)
class Device:
    """
    A haptic device's handle on one axis, held by a hand.

    :param mass: m_d (kg), the handle's apparent mass.
    :param damping: b_d (N s/m), its physical damping.
    :param hand_stiffness: k_h (N/m) of the hand holding it, to the hand's reference.
    :param hand_damping: c_h (N s/m) of the hand.
    """

    mass: float
    damping: float
    hand_stiffness: float = 0.0
    hand_damping: float = 0.0

    def matrices(self, period: float) -> Tuple[np.ndarray, np.ndarray]:
        """
        Return (Phi, Gamma): w[k + 1] = Phi w[k] + Gamma f for a force f held over ``period``.

        w = (x, v); f is the felt force plus the hand's pull toward its reference,
        k_h r + c_h r'. Exact: the exponential of the augmented matrix [[M, g], [0, 0]] T.
        """
        m = self.mass
        system = np.array([[0.0, 1.0, 0.0],
                           [-self.hand_stiffness / m,
                            -(self.damping + self.hand_damping) / m, 1.0 / m],
                           [0.0, 0.0, 0.0]])
        exponential = _expm(system * period)
        return exponential[:2, :2], exponential[:2, 2]


def _expm(matrix: np.ndarray) -> np.ndarray:
    """Return exp(matrix) by scaling and squaring a Taylor series (small matrices)."""
    norm = np.abs(matrix).sum(axis=1).max()
    squarings = max(0, int(math.ceil(math.log2(norm))) + 1) if norm > 0.5 else 0
    scaled = matrix / 2.0 ** squarings
    result = term = np.eye(len(matrix))
    for order in range(1, 25):
        term = term @ scaled / order
        result = result + term
    for _ in range(squarings):
        result = result @ result
    return result


def body_matrices(*, stiffness: float, damping: float, mass: float, period: float,
                  substeps: int) -> Tuple[np.ndarray, np.ndarray]:
    """
    Return (A, B) of the body's tick: (x, v)[k] = A (x, v)[k - 1] + B u[k], u the target.

    The soft step of ``kernel.velocities`` at the COM, for the gains of ``coupling_gains``.
    """
    frequency, ratio = coupling_gains(stiffness, damping, mass)
    h = period / substeps
    a, b = soft_gains(frequency, ratio, h)
    step = np.array([[1.0 - h * b, h * (1.0 - a)], [-b, 1.0 - a]])
    drive = np.array([h * b, b])
    tick, gathered = np.eye(2), np.zeros(2)
    for _ in range(substeps):
        gathered = step @ gathered + drive
        tick = step @ tick
    return tick, gathered


def characteristic_polynomial(*, stiffness: float, damping: float, mass: float,
                              device: Device, period: float, substeps: int,
                              delay: int = 0) -> np.ndarray:
    """Return p(z)'s coefficients, highest power first (module docstring)."""
    a, b = body_matrices(stiffness=stiffness, damping=damping, mass=mass, period=period,
                         substeps=substeps)
    phi, gamma = device.matrices(period)
    body_poles = np.poly(a)
    # e_v^T adj(zI - A) B and e_x^T adj(zI - Phi) Gamma, adj of a 2 x 2 written out.
    body_zeros = np.array([b[1], a[1, 0] * b[0] - a[0, 0] * b[1]])
    device_poles = np.poly(phi)
    device_zeros = np.array([gamma[0], phi[0, 1] * gamma[1] - phi[1, 1] * gamma[0]])
    loop = np.polymul(np.polymul(body_poles, device_poles), np.eye(1, delay + 1)[0])
    feedback = (mass / period) * np.polymul(np.polymul([1.0, -1.0], body_zeros), device_zeros)
    return np.polyadd(loop, feedback)


def spectral_radius(**loop) -> float:
    """Return the largest |root| of the loop's polynomial (``characteristic_polynomial``)."""
    return float(np.abs(np.roots(characteristic_polynomial(**loop))).max())


def largest_stable_stiffness(*, low: float = 1.0, high: float = 1e6, tolerance: float = 1e-6,
                             **loop) -> float:
    """
    Return the stiffness (N/m) at which the loop's first root leaves the unit circle.

    Scanned upward from ``low`` in steps of 5 %, then bisected to ``tolerance`` (relative);
    ``high`` if the loop is stable up to it.

    :param loop: the other arguments of ``characteristic_polynomial``.
    """
    def stable(stiffness: float) -> bool:
        return spectral_radius(stiffness=stiffness, **loop) < STABLE_RADIUS

    return _largest(stable, low, high, tolerance)


def _largest(holds, low: float, high: float, tolerance: float) -> float:
    """Return the stiffness up to which ``holds`` does: 5 % steps up from ``low``, bisected."""
    if not holds(low):
        raise ValueError(f'the loop fails already at {low!r} N/m')
    stiffness = low
    while stiffness < high:
        upper = min(stiffness * 1.05, high)
        if not holds(upper):
            break
        stiffness = upper
    else:
        return high
    while upper - stiffness > tolerance * stiffness:
        middle = 0.5 * (stiffness + upper)
        stiffness, upper = (middle, upper) if holds(middle) else (stiffness, middle)
    return stiffness


def colgate_brown_damping(stiffness: float, damping: float, period: float) -> float:
    """Return the device damping a virtual wall K, B needs to be passive: K T / 2 + |B| (N s/m)."""
    return 0.5 * stiffness * period + abs(damping)


def passivity_damping(stiffness: float, damping: float, period: float, delay: int = 0,
                      samples: int = 4096) -> float:
    """
    Return the device damping (N s/m) that keeps a delayed virtual wall K, B passive.

    Colgate and Schenkel's condition for H(z) = z^-delay (K + B (1 - z^-1) / T), its largest
    value over ``samples`` frequencies up to Nyquist (module docstring).
    """
    theta = np.linspace(math.pi / samples, math.pi, samples)
    back = np.exp(-1j * theta)
    wall = back ** delay * (stiffness + damping * (1.0 - back) / period)
    need = period / (2.0 * (1.0 - np.cos(theta))) * np.real((1.0 - back) * wall)
    return float(need.max())


def coupling_passivity_damping(*, stiffness: float, damping: float, mass: float,
                               period: float, substeps: int, delay: int = 0,
                               samples: int = 4096) -> float:
    """
    Return the device damping (N s/m) that keeps the body behind the coupling passive.

    Colgate and Schenkel's condition for H(z) = z^-delay (m / T) (z - 1) N_v(z) / D_b(z), the
    body in the soft step as ``characteristic_polynomial`` has it, over ``samples``
    frequencies up to Nyquist.
    """
    a, b = body_matrices(stiffness=stiffness, damping=damping, mass=mass, period=period,
                         substeps=substeps)
    theta = np.linspace(math.pi / samples, math.pi, samples)
    z = np.exp(1j * theta)
    body_zeros = np.array([b[1], a[1, 0] * b[0] - a[0, 0] * b[1]])
    rendered = (mass / period) * (z - 1.0) * np.polyval(body_zeros, z) / np.polyval(
        np.poly(a), z) * z ** -delay
    need = period / (2.0 * (1.0 - np.cos(theta))) * np.real((1.0 - 1.0 / z) * rendered)
    return float(need.max())


def passive_stiffness(*, device_damping: float, damping: float, mass: float, period: float,
                      substeps: int, delay: int = 0, low: float = 1.0, high: float = 1e6,
                      tolerance: float = 1e-6) -> float:
    """
    Return the largest coupling stiffness (N/m) a device of ``device_damping`` renders passively.

    Scanned and bisected as ``largest_stable_stiffness`` on ``coupling_passivity_damping``;
    about 2 b / ((2 d + 1) T) for a well-damped coupling.
    """
    def passive(stiffness: float) -> bool:
        return coupling_passivity_damping(stiffness=stiffness, damping=damping, mass=mass,
                                          period=period, substeps=substeps,
                                          delay=delay) < device_damping

    return _largest(passive, low, high, tolerance)


def static_stiffness(*, stiffness: float, damping: float, mass: float, period: float,
                     substeps: int) -> float:
    """
    Return the stiffness (N/m) a constant force meets: m b / ((1 - a) h), about k.

    At rest under a force f, its kick f h / m each substep is what the step's velocity term
    leaves of it, (1 - a) f h / m, balanced by the position term: b (x - u) = (1 - a) f h / m.
    """
    frequency, ratio = coupling_gains(stiffness, damping, mass)
    h = period / substeps
    a, b = soft_gains(frequency, ratio, h)
    return mass * b / ((1.0 - a) * h)
