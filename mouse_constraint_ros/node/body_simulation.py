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
Which simulation a configuration makes: the single body's or the whole robot's.

The node's parts use either through one interface (``physics.robot_body``). A running node keeps
its kind and its robot: a parameter change that would swap a body for a robot, a robot for a
body, or one robot (its description, base or base pose) for another is refused, in one line.
"""

from typing import Optional

from .parameters import NodeConfig
from ..physics import MouseSimulation


def simulation_for(config: NodeConfig):
    """Return the simulation of ``config``: a ``MouseSimulation``, or a ``RobotBody``."""
    if config.robot is None:
        return MouseSimulation(config.settings, config.initial_state)
    from ..physics.robot_body import RobotBody  # Pinocchio's: only a robot loads it
    robot = config.robot
    return RobotBody(robot.robot.model, config.settings, tracked_link=robot.tracked_link,
                     link_distance=robot.links.distance, base_state=robot.base_state,
                     joint_positions=robot.joint_positions)


def robot_change_refusal(running: NodeConfig, changed: NodeConfig) -> Optional[str]:
    """Return why the change from ``running`` to ``changed`` cannot apply at run time, or None."""
    if running.robot is None and changed.robot is None:
        return None
    if running.robot is None or changed.robot is None:
        return ('a change between a single body and a whole robot takes a restart of the node '
                '(robot_description with several links and no body_link is a robot)')
    if running.robot.robot is not changed.robot.robot:
        return ("a robot's description, base or base_pose changes with a restart of the node")
    if running.robot.tracked_link != changed.robot.tracked_link:
        return 'tracked_link changes with a restart of the node'
    return None
