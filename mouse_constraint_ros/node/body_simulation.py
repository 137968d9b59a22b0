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

from typing import Any, Mapping, Optional

from .parameters import NodeConfig
from .robot_parameters import is_robot, robot_key
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


def robot_change_refusal(running: NodeConfig, values: Mapping[str, Any]) -> Optional[str]:
    """
    Return why parameter ``values`` cannot apply to the node running ``running``, or None.

    Checked before any URDF is read: a robot's description, base, base pose and tracked link,
    and the switch between a body and a robot, change with a restart.
    """
    wanted = is_robot(values)
    if running.robot is None:
        if wanted:
            return ('a change from a single body to a whole robot (robot_description of several '
                    'links, no body_link) takes a restart of the node')
        return None
    if not wanted:
        return ('a change from a whole robot to a single body takes a restart of the node '
                '(set body_link, or a robot_description of one link, at start)')
    if robot_key(values) != running.robot.key:
        return ("a robot's robot_description, base, base_pose and tracked_link change with a "
                'restart of the node')
    return None
