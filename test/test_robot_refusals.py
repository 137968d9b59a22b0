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

"""What the robot mode refuses of a URDF, each in one line naming the joint or link."""

import pytest

from mouse_constraint_ros.description.robot_description import load_robot
from mouse_constraint_ros.description.robot_structure import MAX_JOINTS, robot_structure
from test_support.robots import double_pendulum, rod_link

LIMIT = '<limit lower="-1" upper="1" effort="10" velocity="10"/>'


def chain(count: int) -> str:
    """Return a URDF of ``count`` revolute joints in a row."""
    links = ''.join(rod_link(f'l{i}', 1.0, 0.1) for i in range(count))
    joints = ''.join(
        f'<joint name="j{i}" type="revolute"><parent link="{"base" if i == 0 else f"l{i - 1}"}"/>'
        f'<child link="l{i}"/><axis xyz="0 1 0"/>{LIMIT}</joint>' for i in range(count))
    return f'<robot name="c"><link name="base"/>{links}{joints}</robot>'


REFUSED = {
    'a kinematic loop': (
        double_pendulum().replace(
            '</robot>', '<joint name="loop" type="fixed"><parent link="base"/>'
            '<child link="lower"/></joint></robot>'), "link 'lower' is the child of joints"),
    'a cycle with no root': (
        '<robot name="r">' + rod_link('a', 1.0, 0.1) + rod_link('b', 1.0, 0.1)
        + '<joint name="ab" type="continuous"><parent link="a"/><child link="b"/></joint>'
        + '<joint name="ba" type="continuous"><parent link="b"/><child link="a"/></joint>'
        + '</robot>', 'one root link, got 0'),
    'a moving massless link': (
        double_pendulum().replace(rod_link('lower', 1.0, 0.5), '<link name="lower"/>'),
        "joint 'elbow' moves links of zero mass"),
    'lower above upper': (
        double_pendulum(kind='revolute', limit='<limit lower="1" upper="-1" effort="1" '
                        'velocity="1"/>'), "joint 'shoulder': <limit lower=\"1\" upper=\"-1\">"),
    'an axis of zero length': (
        double_pendulum().replace('<axis xyz="0 1 0"/>', '<axis xyz="0 0 0"/>', 1),
        "joint 'shoulder': <axis xyz=\"0 0 0\"> has zero length"),
    'a floating joint inside': (
        double_pendulum().replace('name="elbow" type="continuous"',
                                  'name="elbow" type="floating"'),
        "joint 'elbow' is of type 'floating'"),
    'a planar joint inside': (
        double_pendulum().replace('name="elbow" type="continuous"',
                                  'name="elbow" type="planar"'),
        "joint 'elbow' is of type 'planar'"),
    'a mimic of a missing joint': (
        double_pendulum().replace('<axis xyz="0 1 0"/></joint><joint name="tip_joint"',
                                  '<axis xyz="0 1 0"/><mimic joint="nope"/></joint>'
                                  '<joint name="tip_joint"'),
        "joint 'elbow' mimics 'nope'"),
    'too many joints': (chain(MAX_JOINTS + 1), f'more than {MAX_JOINTS}'),
    'an unexpanded xacro limit': (
        double_pendulum(kind='revolute', limit='<limit lower="${-pi}" upper="1" effort="1" '
                        'velocity="1"/>'), 'expand the xacro file first'),
    'a joint naming a missing link': (
        double_pendulum().replace('<child link="lower"/>', '<child link="nowhere"/>'),
        "joint 'elbow' names link 'nowhere'"),
}


@pytest.mark.parametrize('case', sorted(REFUSED))
def test_a_urdf_the_robot_mode_does_not_serve_is_refused_in_one_line(case):
    text, words = REFUSED[case]
    with pytest.raises(ValueError) as refusal:
        load_robot(text)
    message = str(refusal.value)
    assert words in message
    assert '\n' not in message


def test_the_largest_robot_served_loads():
    robot = load_robot(chain(MAX_JOINTS))
    assert robot.model.nv == MAX_JOINTS


def test_a_root_named_world_fixes_the_base_where_its_joint_puts_it():
    text = double_pendulum().replace(
        '<link name="base"/>', '<link name="world"/><link name="base"/><joint name="mount" '
        'type="fixed"><parent link="world"/><child link="base"/><origin xyz="1 2 3"/></joint>')
    robot = load_robot(text, base_position=(9.0, 9.0, 9.0))
    assert robot.structure.fixed_to_world
    from mouse_constraint_ros.physics.robot_simulation import RobotSimulation
    from mouse_constraint_ros.physics.robot_state import initial_state, RobotSettings
    simulation = RobotSimulation(robot.model, RobotSettings(), initial_state(robot.model))
    assert simulation.link_state('base').position == (1.0, 2.0, 3.0)
    with pytest.raises(ValueError, match="root link 'world'"):
        load_robot(text, base='floating')


def test_the_tool_is_the_last_link_of_the_longest_chain():
    assert robot_structure(double_pendulum()).tool == 'tip'
    assert robot_structure(chain(4)).tool == 'l3'
