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
The whole robot behind the single body's interface: what the node's tick, inputs and outputs use.

The node's parts (the tick, the target and wrench inputs, the simulator controls, the monitors
and the state publishers) ask a simulation for the same things of a robot as of one body:
``step``, ``state``, ``target``, ``settings``, the constraint's force and the last step's
impulse. ``RobotBody`` answers them for a ``RobotSimulation``: the state is the tracked link's
frame (its pose, the velocity of its origin and its angular velocity, world frame), the anchor
is a point of the grabbed link, and the single-body ``Settings`` the node builds give the
gravity, damping, substeps and the constraint's gains. What only a robot has (joint positions,
velocities and torques, every link's pose, a grab landing on any link) is read from
``robot``.
"""

from typing import Callable, Optional, Sequence, Tuple

import numpy as np

from .algebra import Vector3
from .robot_model import RobotModel
from .robot_simulation import RobotSimulation
from .robot_state import initial_state, RobotSettings
from .settings import Settings
from .state import BodyState
from .validation import finite_vector

ZERO: Vector3 = (0.0, 0.0, 0.0)
# A link's distance to a point (m), given the point in the link's frame; inf without pieces.
LinkDistance = Callable[[str, np.ndarray], float]


def robot_settings(settings: Settings) -> RobotSettings:
    """Return the robot's step settings of the node's single-body ``settings``."""
    return RobotSettings(constraint=settings.constraint, gravity=settings.gravity,
                         linear_damping=settings.linear_damping,
                         angular_damping=settings.angular_damping, substeps=settings.substeps)


class RobotBody:
    """
    A robot stepped as the node steps its body.

    :param model: the robot.
    :param settings: the node's settings (``robot_settings`` takes the robot's part).
    :param tracked_link: the link whose frame is ``state`` (pose, twist, TF's body frame).
    :param link_distance: a link's distance to a point in its frame, for grabs.
    :param base_state: a floating base's starting pose (its root link frame).
    :param joint_positions: the joints' starting positions; None: zero (or the nearest limit).
    """

    def __init__(self, model: RobotModel, settings: Settings, *, tracked_link: str,
                 link_distance: LinkDistance, base_state: BodyState = BodyState(),
                 joint_positions: Optional[Sequence[float]] = None) -> None:
        """Start the robot at rest at its initial joint positions."""
        self.robot = RobotSimulation(model, robot_settings(settings), initial_state(
            model, joint_positions=joint_positions, base_state=base_state))
        self._settings = settings
        self._tracked = tracked_link
        self._link_distance = link_distance
        self._grabbed = tracked_link

    # --- what the node configures ------------------------------------------------------------
    @property
    def settings(self) -> Settings:
        """Return the node's settings in force."""
        return self._settings

    def configure(self, settings: Settings, initial_state: BodyState) -> None:
        """Take new settings (the anchor moves on the grabbed link); the robot's start stays."""
        self._settings = settings
        self.robot.settings = robot_settings(settings)
        if self.robot.anchor is not None or settings.constraint.anchor != ZERO:
            self.robot.grab(self._grabbed, settings.constraint.anchor)

    @property
    def tracked_link(self) -> str:
        """Return the link whose frame ``state`` is."""
        return self._tracked

    # --- the grab ---------------------------------------------------------------------------
    def land(self, point: Sequence[float]) -> Tuple[str, Vector3, float]:
        """
        Return the link nearest ``point`` (world), the point in its frame, and the distance.

        The node takes the grab when the distance is within ``grab_margin``; ``hold`` then makes
        the point the anchor.
        """
        point = np.array(finite_vector('grab', point))
        best = ('', ZERO, float('inf'))
        for link, (origin, rotation) in self.robot.link_placements().items():
            local = rotation.T @ (point - origin)
            distance = self._link_distance(link, local)
            if distance < best[2]:
                best = (link, tuple(float(x) for x in local), distance)
        return best

    def hold(self, link: str) -> None:
        """Make ``link`` the one the anchor (the ``anchor`` setting, its frame) is on."""
        self._grabbed = link
        self.robot.grab(link, self._settings.constraint.anchor)

    @property
    def grabbed_link(self) -> str:
        """Return the link the anchor is on."""
        return self._grabbed

    # --- the single body's interface ---------------------------------------------------------
    @property
    def state(self) -> BodyState:
        """Return the tracked link's frame state, world frame."""
        return self.robot.link_state(self._tracked)

    @property
    def time(self) -> float:
        """Return the simulated seconds so far."""
        return self.robot.time

    @property
    def target(self) -> Optional[Vector3]:
        """Return the target, or None for a free robot."""
        return self.robot.target

    @target.setter
    def target(self, target: Optional[Vector3]) -> None:
        self.set_target(target)

    def set_target(self, target: Optional[Vector3], *, time: Optional[float] = None,
                   stamped: bool = False) -> None:
        """Set the target the anchor is pulled to (the robot pulls at it as it is, untimed)."""
        if target is not None and self.robot.anchor is None:
            self.robot.grab(self._grabbed, self._settings.constraint.anchor)
        self.robot.target = target

    def shift_target_times(self, seconds: float) -> None:
        """Do nothing: the robot's targets are untimed."""

    @property
    def joint_target(self) -> Optional[Vector3]:
        """Return where the joint pulls the anchor: the target."""
        return self.robot.target

    @property
    def wrench(self) -> Tuple[Vector3, Vector3]:
        """Return the external force and torque on the tracked link, world frame."""
        return self.robot.wrench

    @wrench.setter
    def wrench(self, wrench: Tuple[Vector3, Vector3]) -> None:
        force, torque = wrench
        self.robot.set_wrench(force, torque, self._tracked)

    @property
    def constraint_force(self) -> Vector3:
        """Return the mouse constraint's force of the last substep (N), world frame."""
        return self.robot.constraint_force

    @property
    def tick_impulse(self) -> Tuple[Vector3, float]:
        """Return the mouse's impulse summed over the last step (N s) and its dt (s)."""
        return self.robot.tick_impulse

    @property
    def contacts(self) -> tuple:
        """Return no contacts: the robot has no floor."""
        return ()

    contact_count = 0

    def anchor_position(self) -> Vector3:
        """Return the anchor's world position (the tracked link's origin when none is held)."""
        position = self.robot.anchor_position()
        if position is None:
            return self.state.position
        return tuple(float(x) for x in position)

    def anchor_error(self) -> Optional[Vector3]:
        """Return anchor - target, or None without a target."""
        target = self.robot.target
        if target is None:
            return None
        return tuple(a - t for a, t in zip(self.anchor_position(), target))

    def step(self, dt: float) -> BodyState:
        """Advance ``dt``; return the tracked link's state."""
        self.robot.advance(dt)
        return self.state

    def reset(self) -> None:
        """Return to the initial state and drop the target."""
        self.robot.reset()
