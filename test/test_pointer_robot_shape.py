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
A whole robot as a client has it (``pointer.robot_shape``): its links placed, met and grabbed.

Every link's pose from the joint positions of ``joint_states`` is the node's own (the robot's
simulation at the same state), a floating base is placed from the tracked link's pose, a ray
meets the link nearest its origin, and a grab lands on the link the node lands it on.
"""

import math
import subprocess
import sys
import textwrap

import numpy as np
import pytest

from mouse_constraint_ros.physics import BodyState, RigidBody, Settings
from mouse_constraint_ros.physics.robot_body import RobotBody
from mouse_constraint_ros.pointer.geometry import Pose, world_point
from mouse_constraint_ros.pointer.node_readouts import ViewParameters
from mouse_constraint_ros.pointer.robot_shape import nearest_link, ray_robot_hit, RobotShape
from test_support.robots import double_pendulum


# The double pendulum with a base of its own mass: free, it is a robot of three bodies.
MASSIVE_BASE = ('<link name="base"><inertial><mass value="2.0"/><inertia ixx="0.01" iyy="0.01" '
                'izz="0.01" ixy="0" ixz="0" iyz="0"/></inertial><collision><geometry>'
                '<box size="0.1 0.1 0.1"/></geometry></collision></link>')


def _shape(description: str = '', **parameters) -> RobotShape:
    shape = RobotShape()
    assert shape.update(ViewParameters(robot_description=description or double_pendulum(),
                                       **parameters))
    assert shape.error is None
    return shape


def _swinging(description: str = '', base: str = 'fixed',
              base_pose=(0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 1.0)) -> RobotBody:
    """Return the double pendulum of the node's parameters, swung 0.3 s from (1.0, -0.5) rad."""
    shape = _shape(description, base=base, base_pose=base_pose)
    body = RobotBody(shape.robot.model, Settings(RigidBody.solid_box(2.0, (0.1, 0.1, 0.1))),
                     tracked_link='tip',
                     link_distance=shape.links.distance,
                     base_state=BodyState(base_pose[:3], base_pose[3:]),
                     joint_positions=(1.0, -0.5))
    for _ in range(300):
        body.step(0.001)
    return body


def _same_poses(got, expected) -> None:
    assert set(got) == set(expected)
    for link, (position, orientation) in expected.items():
        assert np.allclose(got[link].position, position, atol=1e-9), link
        # q and -q are the same turn.
        assert abs(np.dot(got[link].orientation, orientation)) == pytest.approx(1.0, abs=1e-9)


def test_the_links_are_placed_from_the_joint_positions_as_the_node_places_them():
    """On a fixed base away from the origin: every link's pose is the simulation's own."""
    base_pose = (0.3, -0.2, 1.0, 0.0, 0.0, math.sin(0.2), math.cos(0.2))
    body = _swinging(base_pose=base_pose)
    robot = body.robot
    shape = _shape(base_pose=base_pose)
    names = [joint.name for joint in robot.model.joints]
    # joint_states may list the joints in any order.
    poses = shape.link_poses(names[::-1], robot.joint_positions()[::-1])
    _same_poses(poses, robot.link_poses())
    assert not np.allclose(poses['lower'].position, shape.link_poses(names, (0.0, 0.0))['lower']
                           .position)


def test_a_floating_base_is_placed_so_that_the_tracked_link_is_at_its_pose():
    """joint_states has no base: the tracked link's published pose places the whole robot."""
    description = double_pendulum().replace('<link name="base"/>', MASSIVE_BASE)
    turn = np.array((0.3, -0.5, 0.8)) / np.linalg.norm((0.3, -0.5, 0.8)) * math.sin(0.4)
    body = _swinging(description, base='floating',
                     base_pose=(0.1, 0.2, 2.0, *turn, math.cos(0.4)))
    robot = body.robot
    assert np.linalg.norm(robot.state.q[:3] - (0.1, 0.2, 2.0)) > 0.01  # the base fell
    tip = body.state
    shape = _shape(description, base='floating')
    names = [joint.name for joint in robot.model.joints]
    poses = shape.link_poses(names, robot.joint_positions(),
                             tracked=Pose(tip.position, tip.orientation))
    _same_poses(poses, robot.link_poses())


def test_joint_states_missing_a_joint_or_not_finite_place_nothing():
    """A message that does not give every joint a finite position places no link."""
    shape = _shape()
    assert shape.link_poses(['shoulder'], [0.1]) is None
    assert shape.link_poses(['shoulder', 'elbow'], [0.1, math.nan]) is None
    assert RobotShape().link_poses(['shoulder', 'elbow'], [0.1, 0.2]) is None


def test_a_ray_meets_the_link_nearest_its_origin():
    """Along x through both rods (upper at z -0.2 in front of lower at x 0.3): the nearer."""
    shape = _shape()
    poses = shape.link_poses(['shoulder', 'elbow'], [0.0, 0.0])
    assert set(shape.geometries) == {'upper', 'lower'}  # base and tip have no pieces
    link, hit = ray_robot_hit((0.0, -1.0, -0.2), (0.0, 1.0, 0.0), poses=poses,
                              geometries=shape.geometries)
    assert link == 'upper' and hit == pytest.approx((0.0, -0.02, -0.2), abs=1e-12)
    # Bent 90 degrees at the elbow: the lower rod lies along -x (a turn about +y takes -z to -x)
    # at z = -0.5; a ray down from above at x = -0.3 meets it, not the upper rod.
    bent = shape.link_poses(['shoulder', 'elbow'], [0.0, math.pi / 2])
    link, hit = ray_robot_hit((-0.3, 0.0, 1.0), (0.0, 0.0, -1.0), poses=bent,
                              geometries=shape.geometries)
    assert link == 'lower' and hit == pytest.approx((-0.3, 0.0, -0.48), abs=1e-12)
    # Along the arm's axis from below: the lower rod's end first, then the upper behind it.
    link, _ = ray_robot_hit((0.0, 0.0, -2.0), (0.0, 0.0, 1.0), poses=poses,
                            geometries=shape.geometries)
    assert link == 'lower'
    assert ray_robot_hit((1.0, -1.0, 0.0), (0.0, 1.0, 0.0), poses=poses,
                         geometries=shape.geometries) is None


def test_a_grab_lands_on_the_link_the_node_lands_it_on():
    """Points about the swung pendulum: the same link and distance as ``RobotBody.land``."""
    body = _swinging()
    shape = _shape()
    names = [joint.name for joint in body.robot.model.joints]
    poses = shape.link_poses(names, body.robot.joint_positions())
    rng = np.random.default_rng(7)
    for point in rng.uniform((-1.0, -0.1, -1.0), (1.0, 0.1, 0.2), (200, 3)):
        link, _, distance = body.land(point)
        assert nearest_link(point, poses=poses, geometries=shape.geometries) == pytest.approx(
            (link, distance), abs=1e-9)
    # A point of the upper rod's face, in its frame, lands on it at distance 0.
    point = world_point(poses['upper'], (0.02, 0.0, -0.3))
    assert nearest_link(point, poses=poses, geometries=shape.geometries) == pytest.approx(
        ('upper', 0.0), abs=1e-12)


def test_a_body_or_a_link_is_no_robot_and_a_changed_robot_is_loaded_again():
    """The box and a single link: no robot; a new base loads a new model; the same: not."""
    shape = RobotShape()
    assert shape.update(ViewParameters()) and shape.robot is None
    assert not shape.update(ViewParameters())
    assert shape.update(ViewParameters(robot_description=double_pendulum(), body_link='upper'))
    assert shape.robot is None and shape.error is None
    assert shape.update(ViewParameters(robot_description=double_pendulum()))
    first = shape.robot
    assert first is not None and shape.tracked_link == 'tip'
    assert not shape.update(ViewParameters(robot_description=double_pendulum(), anchor=(0, 0, 0)))
    free = double_pendulum().replace('<link name="base"/>', MASSIVE_BASE)
    assert shape.update(ViewParameters(robot_description=free))
    second = shape.robot
    assert second is not first
    assert shape.update(ViewParameters(robot_description=free, base='floating'))
    assert shape.robot is not second and shape.robot.model.floating


def test_a_robot_the_view_cannot_load_is_no_robot_and_says_why():
    """A tracked link the robot does not have: no robot, one line naming it."""
    shape = RobotShape()
    assert shape.update(ViewParameters(robot_description=double_pendulum(),
                                       tracked_link='hand'))
    assert shape.robot is None and "'hand'" in shape.error and '\n' not in shape.error


def test_a_visual_mesh_this_machine_lacks_leaves_the_robot_drawn_by_its_collision_pieces(
        tmp_path):
    """The upper rod's visual names a file that is not there: its box is drawn, and said so."""
    visual = (f'<visual><geometry><mesh filename="{tmp_path / "absent.stl"}"/></geometry>'
              '</visual>')
    description = double_pendulum().replace('</collision></link>', '</collision>' + visual
                                            + '</link>', 1)
    shape = RobotShape()
    assert shape.update(ViewParameters(robot_description=description))
    assert shape.robot is not None and set(shape.geometries) == {'upper', 'lower'}
    assert 'collision pieces' in shape.error and 'absent.stl' in shape.error
    assert shape.links.drawn('upper') == shape.links.pieces['upper']


@pytest.mark.system
def test_a_view_of_a_box_or_a_link_never_imports_pinocchio():
    """The view's modules and a box's or a single link's shape load no Pinocchio."""
    probe = subprocess.run([sys.executable, '-c', textwrap.dedent("""
        import sys
        import mouse_constraint_ros.view.node
        from mouse_constraint_ros.pointer.node_readouts import ViewParameters
        from mouse_constraint_ros.pointer.robot_shape import RobotShape
        from test_support.robots import double_pendulum
        shape = RobotShape()
        shape.update(ViewParameters())
        shape.update(ViewParameters(robot_description=double_pendulum(), body_link='upper'))
        print('pinocchio' in sys.modules)
        """)], capture_output=True, text=True, timeout=120)
    assert probe.returncode == 0 and probe.stdout.strip() == 'False', probe.stdout + probe.stderr
