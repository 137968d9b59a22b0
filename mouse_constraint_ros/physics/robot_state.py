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
What moves of a robot: its configuration q and velocity v, and how they start.

q and v are Pinocchio's: a floating base leads with its position, its unit quaternion
(x, y, z, w) and its twist in its own frame; a continuous joint's q is (cos, sin) of its angle.
``RobotSettings`` holds what the robot's step is configured with, beside the model.
"""

from dataclasses import dataclass
import math
from typing import NamedTuple, Optional, Sequence

import numpy as np
import pinocchio

from .mouse_joint import MouseConstraint
from .robot_model import RobotModel
from .settings import STANDARD_GRAVITY
from .state import BodyState
from .validation import finite_vector, scalar, shown


class RobotState(NamedTuple):
    """The configuration q (Pinocchio's, nq) and the velocity v (nv)."""

    q: np.ndarray
    v: np.ndarray


# The most sweeps the rows of one substep get (the mouse, the limits, friction, speed limits).
MAX_ROW_ITERATIONS = 1000


@dataclass(frozen=True)
class RobotSettings:
    """
    Everything the robot's step depends on apart from the model, the state and the target.

    :param constraint: how the anchor follows the target (its ``anchor`` is unused: the robot's
        anchor is a link and a point, ``RobotSimulation.grab``).
    :param gravity: m/s^2 in the world frame.
    :param linear_damping: rate c (1/s) at which a prismatic joint's and the floating base's
        linear velocity decay, exp(-c t).
    :param angular_damping: the same for revolute and continuous joints and the base's rotation.
    :param substeps: equal substeps per step.
    :param iterations: sweeps over the rows per substep when more than the mouse's is active.
    :param limit_slop: how far past a position limit the correction leaves alone (rad or m).
    :param limit_baumgarte: the fraction of the penetration past the slop corrected per substep.
    """

    constraint: MouseConstraint = MouseConstraint()
    gravity: Sequence[float] = STANDARD_GRAVITY
    linear_damping: float = 0.0
    angular_damping: float = 0.0
    substeps: int = 1
    iterations: int = 10
    limit_slop: float = 0.005
    limit_baumgarte: float = 0.2

    def __post_init__(self) -> None:
        """Validate every field; raise ValueError naming the first invalid one."""
        if not isinstance(self.constraint, MouseConstraint):
            raise ValueError(f'constraint must be a MouseConstraint, got {shown(self.constraint)}')
        object.__setattr__(self, 'gravity', finite_vector('gravity', self.gravity))
        for name in ('linear_damping', 'angular_damping', 'limit_slop'):
            object.__setattr__(self, name, scalar(name, getattr(self, name), at_least=0.0))
        object.__setattr__(self, 'limit_baumgarte', scalar(
            'limit_baumgarte', self.limit_baumgarte, above=0.0, at_most=1.0))
        for name, most in (('substeps', math.inf), ('iterations', MAX_ROW_ITERATIONS)):
            value = getattr(self, name)
            if isinstance(value, bool) or not isinstance(value, int) or not 1 <= value <= most:
                raise ValueError(f'{name} must be an integer >= 1, got {shown(value)}')


def initial_state(model: RobotModel, *, joint_positions: Optional[Sequence[float]] = None,
                  base_state: BodyState = BodyState()) -> RobotState:
    """
    Return the robot at rest: each joint at its position (default: 0, or its nearest limit).

    :param model: the robot.
    :param joint_positions: each moving joint's position (rad or m), in ``model.joints`` order.
    :param base_state: a floating base's pose and velocity (its link frame, world frame).
    """
    q = pinocchio.neutral(model.model)
    v = np.zeros(model.nv)
    if joint_positions is not None and len(joint_positions) != len(model.joints):
        raise ValueError(f'joint positions must be {len(model.joints)} numbers, got '
                         f'{len(joint_positions)}')
    for index, joint in enumerate(model.joints):
        position = 0.0 if joint_positions is None else float(joint_positions[index])
        if not math.isfinite(position):
            raise ValueError(f'joint {joint.name!r}: position must be finite, got {position}')
        if joint.kind == 'continuous':
            q[joint.q_index:joint.q_index + 2] = math.cos(position), math.sin(position)
        else:
            q[joint.q_index] = min(max(position, joint.lower), joint.upper)
    if model.floating:
        base = base_state.validated()
        q[0:3] = base.position
        q[3:7] = base.orientation
        rotation = pinocchio.Quaternion(base.orientation[3], *base.orientation[:3])
        world_to_base = rotation.toRotationMatrix().T
        v[0:3] = world_to_base @ np.array(base.linear_velocity)
        v[3:6] = world_to_base @ np.array(base.angular_velocity)
    return RobotState(q, v)
