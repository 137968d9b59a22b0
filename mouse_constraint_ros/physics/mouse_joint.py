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
The mouse constraint of Irlan Robson's note "The Mouse Constraint (and its Jacobian)", corrected.

A body-fixed anchor, at ``r = R r_local`` from the center of mass, is pulled to the mouse target:

- eq. 1.1: C = x + r - x_mouse;
- eq. 1.2: dC/dt = J V = v + w x r, so J = [I3, -[r]x] (eq. 1.3 as printed has the angular
  block's sign flipped: it computes v + r x w, which is not the derivative of C);
- eq. 1.10: K = J M^-1 J^T = m^-1 I3 + [r]x I_w^-1 [r]x^T (right as printed: the sign of the
  angular block cancels in the product);
- eq. 1.5, rigid mode: lambda = K^-1 (-J V - (delta / h) C). The note prints ``+ delta / dt C``,
  which makes the next error (1 + delta) C instead of (1 - delta) C.

Both modes are one formula here, the net impulse of a substep,

    P = -K^-1 (a J V + b C),    |P| <= h F_max,

with gains (a, b) = (1, delta / h) in rigid mode and the soft-step gains of ``soft_gains`` in
soft mode. It equals Box2D v3's warm-started mouse-joint solve with one iteration: warm starting
applies the previous impulse P0, the solve adds -a K^-1 (J V + K P0 + (b / a) C) - (1 - a) P0
with impulse scale 1 - a, and the sum is the P above whatever P0 was.
"""

from dataclasses import dataclass
import math
from typing import Tuple

from .algebra import Symmetric3, Vector3
from .limits import MAX_DISTANCE
from .validation import finite_vector, norm, scalar, shown


# Upper bounds on the soft-mode settings: far beyond any use (a 1 MHz spring is rigid at any
# step this runs at), and low enough that the gains stay finite.
MAX_FREQUENCY_HZ = 1e6
MAX_DAMPING_RATIO = 1e6


@dataclass(frozen=True)
class MouseConstraint:
    """
    How the anchor is held: where it is on the body and how stiffly it follows the target.

    :param anchor: the anchor in the body frame, from the COM (m), at most MAX_DISTANCE away
        (and near enough for the body's effective mass, see ``simulation.check_lever``).
    :param baumgarte: rigid mode's Baumgarte factor delta in (0, 1] (seed eq. 1.5).
    :param frequency_hz: soft mode's natural frequency f (Hz); 0 selects rigid mode.
    :param damping_ratio: soft mode's damping ratio zeta (1 = critical).
    :param max_force: bound on the constraint force's norm (N); +inf for unlimited.
    :param max_force_per_weight: a second bound on it, in body weights: k m |g| (N), with the
        standard gravity's norm when gravity is zero, so that a weightless body is not held by
        a dead joint; +inf for none. It scales with the mass, as Box2D's and Bounce's samples
        scale theirs, so a light and a heavy body are dragged alike.
    :param angular_friction: c >= 0 of the angular friction that acts while a target is held:
        an angular impulse that stops the body's spin about the line from the anchor to the
        COM (the whole spin for an anchor at the COM), bounded by the torque
        c m |g| sqrt(I_mean / m) (N m), I_mean the mean principal moment (Box2D v3.2's samples
        bound their velocity torque so with c = 0.25); 0 for none. The swing about the anchor,
        a turn across that line, is left alone (``kernel``).
    :param gravity_feed_forward: soft mode: the joint carries the weight's pull on the anchor
        outright, so the spring does not sag by g / omega^2 (rigid mode carries it anyway).
    """

    anchor: Vector3 = (0.0, 0.0, 0.0)
    baumgarte: float = 0.2
    frequency_hz: float = 0.0
    damping_ratio: float = 1.0
    max_force: float = math.inf
    max_force_per_weight: float = math.inf
    angular_friction: float = 0.0
    gravity_feed_forward: bool = False

    def __post_init__(self) -> None:
        """Validate every field; raise ValueError naming the first invalid one."""
        anchor = finite_vector('anchor', self.anchor)
        if norm(anchor) > MAX_DISTANCE:
            raise ValueError(
                f'anchor must be at most {MAX_DISTANCE:g} m from the COM, got {shown(anchor)} '
                f'({norm(anchor):g} m): positions are not resolved beyond')
        object.__setattr__(self, 'anchor', anchor)
        object.__setattr__(self, 'baumgarte',
                           scalar('baumgarte', self.baumgarte, above=0.0, at_most=1.0))
        object.__setattr__(self, 'frequency_hz', scalar(
            'frequency_hz', self.frequency_hz, at_least=0.0, at_most=MAX_FREQUENCY_HZ))
        object.__setattr__(self, 'damping_ratio', scalar(
            'damping_ratio', self.damping_ratio, at_least=0.0, at_most=MAX_DAMPING_RATIO))
        object.__setattr__(self, 'max_force',
                           scalar('max_force', self.max_force, above=0.0, allow_inf=True))
        object.__setattr__(self, 'max_force_per_weight', scalar(
            'max_force_per_weight', self.max_force_per_weight, above=0.0, allow_inf=True))
        object.__setattr__(self, 'angular_friction', scalar(
            'angular_friction', self.angular_friction, at_least=0.0))
        if not isinstance(self.gravity_feed_forward, bool):
            raise ValueError('gravity_feed_forward must be true or false, got '
                             f'{shown(self.gravity_feed_forward)}')

    @property
    def rigid(self) -> bool:
        """Return True in the seed's rigid mode (Baumgarte), False for a soft spring."""
        return self.frequency_hz == 0.0

    def gains(self, h: float) -> Tuple[float, float]:
        """Return the impulse's gains a and b for a substep of ``h`` seconds (module docstring)."""
        if self.rigid:
            return 1.0, self.baumgarte / h
        return soft_gains(self.frequency_hz, self.damping_ratio, h)


def soft_gains(frequency_hz: float, damping_ratio: float, h: float) -> Tuple[float, float]:
    """
    Return the gains (a, b) of a spring of frequency f and damping ratio zeta, discretized exactly.

    Catto's soft step (Box2D's b2MakeSoft) uses a = a2 a3 (mass scale) and b = a (omega / a1)
    (mass scale times bias rate), with omega = 2 pi f, a1 = 2 zeta + h omega, a2 = h omega a1,
    a3 = 1 / (1 + a2). For the anchor error e of a point mass that step is the linear map
    e' = e + h v', v' = (1 - a) v - b e, whose determinant is 1 - a and trace 2 - a - h b. It is
    implicit Euler on the spring, and so adds damping: at f = 5 Hz, h = 1 ms, zeta = 0.1 decays
    like zeta = 0.116. Here a and b are chosen instead so that the map's eigenvalues are exactly
    exp(s h) for the roots s of s^2 + 2 zeta omega s + omega^2: determinant exp(-2 zeta omega h)
    and trace exp(s1 h) + exp(s2 h). The error then rings at f and decays with zeta at any h, the
    gains agree with b2MakeSoft's to first order in h omega, and the step is as stable
    (|eigenvalues| <= 1).
    """
    omega = 2.0 * math.pi * frequency_hz
    decay_rate = damping_ratio * omega
    discriminant = damping_ratio * damping_ratio - 1.0
    if discriminant < 0.0:
        trace = 2.0 * math.exp(-decay_rate * h) * math.cos(omega * math.sqrt(-discriminant) * h)
    else:
        # Both real roots are <= 0: sum their exponentials rather than use cosh, which overflows.
        spread = omega * math.sqrt(discriminant)
        trace = math.exp((spread - decay_rate) * h) + math.exp(-(spread + decay_rate) * h)
    determinant = math.exp(-2.0 * decay_rate * h)
    return 1.0 - determinant, (1.0 + determinant - trace) / h


def coupling_gains(stiffness: float, damping: float, mass: float) -> Tuple[float, float]:
    """
    Return (frequency_hz, damping_ratio) of the soft mode that is a spring k and damper c.

    The soft mode's impulse is P = -K^-1 (a J V + b C): scaled by the effective mass K^-1,
    which is m at the COM (eq. 1.10 with r = 0). Its anchor error then moves as a mass m on a
    spring k = m omega^2 and damper c = 2 m zeta omega, discretized so that the error's map
    has exactly the eigenvalues exp(s h) of m s^2 + c s + k (``soft_gains``): omega =
    sqrt(k / m), zeta = c / (2 sqrt(k m)). Off the COM the effective mass is smaller across
    the lever arm (eq. 1.10), and so are the spring and damper there.

    :param stiffness: k > 0 (N/m).
    :param damping: c >= 0 (N s/m).
    :param mass: the body's mass m > 0 (kg).
    """
    omega = math.sqrt(stiffness / mass)
    critical = 2.0 * math.sqrt(stiffness * mass)
    # k m below the smallest double: any damper is then infinitely many critical ones.
    ratio = damping / critical if critical > 0.0 else (math.inf if damping > 0.0 else 0.0)
    return omega / (2.0 * math.pi), ratio


def effective_mass(inverse_mass: float, inverse_inertia: Symmetric3, r: Vector3) -> Symmetric3:
    """
    Return K = m^-1 I3 + [r]x I_w^-1 [r]x^T (eq. 1.10) as a symmetric 6-tuple.

    :param inverse_mass: m^-1.
    :param inverse_inertia: the world-frame I_w^-1 as (xx, xy, xz, yy, yz, zz).
    :param r: the anchor's offset from the COM in the world frame.
    """
    rx, ry, rz = r
    a00, a01, a02, a11, a12, a22 = inverse_inertia
    # B = [r]x I_w^-1, then K_angular = B [r]x^T.
    b00 = ry * a02 - rz * a01
    b01 = ry * a12 - rz * a11
    b02 = ry * a22 - rz * a12
    b10 = rz * a00 - rx * a02
    b11 = rz * a01 - rx * a12
    b12 = rz * a02 - rx * a22
    b20 = rx * a01 - ry * a00
    b21 = rx * a11 - ry * a01
    return (
        inverse_mass + ry * b02 - rz * b01,
        rz * b00 - rx * b02,
        rx * b01 - ry * b00,
        inverse_mass + rz * b10 - rx * b12,
        rx * b11 - ry * b10,
        inverse_mass + rx * b21 - ry * b20,
    )
