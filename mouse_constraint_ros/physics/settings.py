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
The simulation's settings, replaced as a whole, and the force and torque bounds they give.

``Settings`` validates every field when it is made, so a running simulation never holds an
invalid one; ``force_bound`` and ``friction_torque_bound`` are the joint's bounds in newtons and
newton metres, read by the step kernel and by the monitors that show them.
"""

from dataclasses import dataclass
import math

from .algebra import Vector3
from .body import RigidBody
from .floor import Floor
from .limits import MAX_ACCELERATION, MAX_CONDITION
from .mouse_joint import MouseConstraint
from .target_motion import TargetMotion
from .validation import finite_vector, norm, scalar, shown

STANDARD_GRAVITY: Vector3 = (0.0, 0.0, -9.80665)


@dataclass(frozen=True)
class Settings:
    """
    Everything the step depends on apart from the state and the target; replaced as a whole.

    :param body: mass and inertia.
    :param constraint: anchor and how stiffly it follows the target.
    :param gravity: gravitational acceleration in the world frame (m/s^2), of norm at most
        MAX_ACCELERATION (see ``limits``).
    :param linear_damping: rate c (1/s): v decays as exp(-c t) whatever the step size. Any
        rate >= 0 is valid: the factor exp(-c h) lies in [0, 1] and c h cannot overflow.
    :param angular_damping: the same for the angular velocity.

    The body and the constraint's anchor must suit each other: see ``check_lever``.
    :param substeps: equal substeps per ``step`` call (>= 1).
    :param target_motion: how the target handed to the joint moves (``target_motion``): the
        default hands the target over as given, with zero velocity (the seed's joint).
    :param floor: the floor the box rests on and its contact settings (``floor``); the default
        has none.
    """

    body: RigidBody
    constraint: MouseConstraint = MouseConstraint()
    gravity: Vector3 = STANDARD_GRAVITY
    linear_damping: float = 0.0
    angular_damping: float = 0.0
    substeps: int = 1
    target_motion: TargetMotion = TargetMotion()
    floor: Floor = Floor()

    def __post_init__(self) -> None:
        """Validate every field; raise ValueError naming the first invalid one."""
        if not isinstance(self.body, RigidBody):
            raise ValueError(f'body must be a RigidBody, got {shown(self.body)}')
        if not isinstance(self.constraint, MouseConstraint):
            raise ValueError(f'constraint must be a MouseConstraint, got {shown(self.constraint)}')
        check_lever(self.body, self.constraint.anchor)
        gravity = finite_vector('gravity', self.gravity)
        if norm(gravity) > MAX_ACCELERATION:
            raise ValueError(
                f'gravity must be at most {MAX_ACCELERATION:g} m/s^2 (about the surface '
                f'gravity of a neutron star), got {shown(gravity)} of norm {norm(gravity):g}: '
                'beyond, the velocities it gives leave what the step keeps finite')
        object.__setattr__(self, 'gravity', gravity)
        object.__setattr__(self, 'linear_damping',
                           scalar('linear_damping', self.linear_damping, at_least=0.0))
        object.__setattr__(self, 'angular_damping',
                           scalar('angular_damping', self.angular_damping, at_least=0.0))
        if isinstance(self.substeps, bool) or not isinstance(self.substeps, int) \
                or self.substeps < 1:
            raise ValueError(f'substeps must be an integer >= 1, got {shown(self.substeps)}')
        if not isinstance(self.target_motion, TargetMotion):
            raise ValueError(
                f'target_motion must be a TargetMotion, got {shown(self.target_motion)}')
        if not isinstance(self.floor, Floor):
            raise ValueError(f'floor must be a Floor, got {shown(self.floor)}')


def check_lever(body: RigidBody, anchor: Vector3, *, body_name: str = 'body of mass') -> None:
    """
    Raise ValueError naming ``anchor`` if the effective mass K is too ill-conditioned to solve.

    K = m^-1 I3 + [r]x I_w^-1 [r]x^T has the eigenvalue 1 / m along r and at most
    1 / m + |r|^2 / I_min across it, in any orientation: its condition number is at most
    1 + m |r|^2 / I_min, which must not exceed MAX_CONDITION (see ``limits``). A point farther out
    would be held by a K that rounding makes singular, and its Cholesky factor would fail.

    :param body: the body.
    :param anchor: the anchor in the body frame (m).
    :param body_name: what the message calls the body, before its mass (naming the parameters
        its mass and inertia came from).
    """
    moments = body.principal_moments
    lever = norm(anchor)
    condition = 1.0 + body.mass * (lever / moments[0]) * lever
    if condition > MAX_CONDITION:
        reach = math.sqrt((MAX_CONDITION - 1.0) * moments[0] / body.mass)
        raise ValueError(
            f'anchor {shown(anchor)} is {lever:g} m from the COM, too far for the {body_name} '
            f'{body.mass:g} kg (smallest principal moment {moments[0]:g} kg m^2): the '
            f'effective mass K would have condition number {condition:g} > {MAX_CONDITION:g} '
            f'(1 + m |anchor|^2 / I_min), too ill-conditioned to solve; at most {reach:g} m')


def weight_scale(settings: Settings) -> float:
    """Return m |g| (N), with the standard gravity's norm when gravity is zero."""
    gravity = norm(settings.gravity) or norm(STANDARD_GRAVITY)
    return settings.body.mass * gravity


def force_bound(settings: Settings) -> float:
    """Return the bound on the constraint force (N): max_force and max_force_per_weight m g."""
    constraint = settings.constraint
    if math.isinf(constraint.max_force_per_weight):
        return constraint.max_force
    return min(constraint.max_force, constraint.max_force_per_weight * weight_scale(settings))


def follow_force(settings: Settings) -> float:
    """
    Return the force (N) that moves the body along the guide's fastest motion: m (|g| + a).

    a is ``max_target_acceleration``; without a guide (or an unbounded one) there is none to
    follow, and the force is unbounded. A held-back anchor is pulled with no more than this
    (``kernel.velocities``).
    """
    acceleration = settings.target_motion.max_acceleration
    if math.isinf(acceleration) or not settings.target_motion.guided:
        return math.inf
    return settings.body.mass * (math.hypot(*settings.gravity) + acceleration)


def friction_torque_bound(settings: Settings) -> float:
    """Return the angular friction's torque bound c m |g| sqrt(I_mean / m) (N m)."""
    friction = settings.constraint.angular_friction
    if friction == 0.0:
        return 0.0
    body = settings.body
    gyration = math.sqrt(sum(body.principal_moments) / 3.0 / body.mass)
    return friction * weight_scale(settings) * gyration
