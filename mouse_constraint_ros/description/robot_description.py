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
A whole robot from its URDF: the checked tree, then Pinocchio's model of it.

The tree is checked first (``robot_structure``), so that a URDF the robot mode does not serve
is refused in one line naming the joint or link, before Pinocchio reads it. Pinocchio is
imported here, when the first robot loads: the box and single-link routes never import it.
"""

from typing import NamedTuple

from .robot_structure import FIXED_BASE, FLOATING_BASE, robot_structure, RobotStructure
from .xml_declaration import as_xml_1_0
from ..physics.algebra import Quaternion, Vector3


class Robot(NamedTuple):
    """The robot of a URDF: its tree and its model (``physics.robot_model.RobotModel``)."""

    structure: RobotStructure
    model: object


def load_robot(text: str, *, base: str = FIXED_BASE, base_position: Vector3 = (0.0, 0.0, 0.0),
               base_orientation: Quaternion = (0.0, 0.0, 0.0, 1.0)) -> Robot:
    """
    Return the robot of the URDF ``text``; raise ValueError in one line if it is not served.

    :param text: the URDF (XML).
    :param base: ``fixed`` (at the base pose) or ``floating``. A root link named ``world``
        fixes the robot where its joint to the world puts it, whatever the base pose.
    :param base_position: the fixed base's position (m).
    :param base_orientation: the fixed base's orientation (x, y, z, w).
    """
    text = as_xml_1_0(text)  # pybullet's URDFs declare version 0.0
    structure = robot_structure(text)
    if structure.fixed_to_world:
        if base == FLOATING_BASE:
            raise ValueError("base is floating, but the URDF's root link 'world' fixes the "
                             'robot to the world: remove that link, or use base: fixed')
        base_position, base_orientation = (0.0, 0.0, 0.0), (0.0, 0.0, 0.0, 1.0)
    if base == FLOATING_BASE and structure.root_mass <= 0.0:
        raise ValueError(f'base is floating, but the root link {structure.root!r} and the links '
                         'fixed to it have no mass: a free base needs <inertial> mass')
    from ..physics.robot_model import robot_model
    model = robot_model(
        text, base=base, base_position=base_position, base_orientation=base_orientation,
        joint_kinds=[(joint.name, joint.kind) for joint in structure.joints],
        mimics=[(joint.name,) + joint.mimic for joint in structure.joints if joint.mimic])
    return Robot(structure, model)
