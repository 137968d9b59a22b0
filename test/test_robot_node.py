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

"""The whole robot through ROS: the node in lockstep, its joint_states, pose, grab and drag."""

import math

import numpy as np
import pytest

from mouse_constraint_ros.testing import SimulatedBody
from test_support.robots import double_pendulum, double_pendulum_tip

START = math.radians(60.0)


def test_a_double_pendulum_through_ros_follows_the_closed_equations_and_keeps_its_energy():
    # 1 kHz, one substep: each tick is one step of the robot's symplectic Euler.
    with SimulatedBody(robot_description=double_pendulum(), substeps=1,
                       initial_joint_positions=[START, START - START]) as body:
        assert body.node.simulation.tracked_link == 'tip'
        tips, stamps = [], []
        for _tick in range(2000):
            body.step()
            tips.append(body.pose.position[[0, 2]])
            stamps.append(body.joints.header.stamp.nanosec + body.joints.header.stamp.sec * 10**9)
            assert list(body.joints.name) == ['shoulder', 'elbow']
        # joint_states on every published tick, stamped as the tick.
        assert np.all(np.diff(stamps) == 1_000_000)
        reference = double_pendulum_tip(np.arange(1, 2001) * 1e-3, START)
        errors = np.linalg.norm(np.array(tips) - reference, axis=1)
        assert math.sqrt(np.mean(errors ** 2)) < 1e-3
        robot = body.node.simulation.robot
        start_energy = robot.energy()
        means = []
        for _second in range(8):
            total = 0.0
            for _tick in range(1000):
                body.step()
                total += robot.energy()
            means.append(total / 1000.0)
        swing = start_energy - (-9.80665 * (1.0 * -0.25 + 1.0 * -0.75))  # above hanging rest
        assert np.max(np.abs(np.array(means) - start_energy)) / swing < 1e-3


def test_a_grab_on_the_middle_link_takes_that_link_and_drags_the_robot():
    with SimulatedBody(robot_description=double_pendulum(), substeps=1) as body:
        body.step()
        # A point on the upper rod's surface (it spans z 0 .. -0.5, 4 cm thick).
        anchor = body.grab((0.02, 0.0, -0.2))
        simulation = body.node.simulation
        assert simulation.grabbed_link == 'upper'
        assert np.allclose(anchor, (0.02, 0.0, -0.2), atol=1e-9)
        # The point turned 1 rad about the shoulder (+y): in the robot's reach.
        turn = -1.0
        target = np.array((0.02 * math.cos(turn) - 0.2 * math.sin(turn), 0.0,
                           -0.02 * math.sin(turn) - 0.2 * math.cos(turn)))
        for _tick in range(1500):
            body.target(target)
            body.step()
        assert np.linalg.norm(simulation.anchor_position() - target) < 1e-3
        # The shoulder turned to bring its link's point there; the efforts are the mouse's.
        assert body.joints.position[0] == pytest.approx(turn, abs=1e-2)
        assert np.any(np.abs(body.joints.effort) > 0.1)


def test_a_grab_off_every_link_is_refused():
    from mouse_constraint_ros.testing.errors import InputRefused
    with SimulatedBody(robot_description=double_pendulum(), substeps=1) as body:
        body.step()
        with pytest.raises(InputRefused):
            body.grab((0.5, 0.0, 0.3))


def test_a_run_time_change_to_a_robot_or_of_it_is_refused_in_one_line():
    from rclpy.parameter import Parameter
    with SimulatedBody(robot_description=double_pendulum(), substeps=1) as body:
        other = double_pendulum(length=(0.4, 0.4))
        result = body.node.set_parameters([Parameter('robot_description', value=other)])[0]
        assert not result.successful and '\n' not in result.reason
        assert 'restart' in result.reason
        # What acts on the body acts on the robot at run time: gravity off, and it stays.
        result = body.node.set_parameters([Parameter('gravity', value=[0.0, 0.0, 0.0])])[0]
        assert result.successful
        body.step(100)
        assert np.allclose(body.joints.position, 0.0, atol=1e-12)


def test_a_real_arm_with_its_meshes_hangs_and_is_dragged_0_3_m_by_its_hand(monkeypatch):
    # The Panda of the public collection as shipped: its package:// meshes through the ament
    # index, its fingers a mimic pair. It falls onto its stops, is grabbed on its hand and
    # dragged 0.3 m up through ROS with the shipped joint (guided, bounded).
    from test_support.robots import collection_urdf, robot_collection
    monkeypatch.setenv('AMENT_PREFIX_PATH', str(robot_collection()))
    text = collection_urdf('panda_description/urdf/panda.urdf').read_text()
    with SimulatedBody(robot_description=text) as body:
        body.step(500)
        simulation = body.node.simulation
        model = simulation.robot.model
        placements = simulation.robot.link_placements()
        origin, rotation = placements['panda_hand']
        # A point 2 cm inside the hand's collision mesh, on its axis.
        point = origin + rotation @ np.array((0.0, 0.0, 0.02))
        anchor = np.array(body.grab(point))
        assert simulation.grabbed_link == 'panda_hand'
        assert np.allclose(anchor, (0.0, 0.0, 0.02), atol=1e-9)
        goal = point + (0.0, 0.0, 0.3)
        worst = 0.0
        for _tick in range(3000):
            body.target(goal)
            body.step()
            for joint, position in zip(model.joints, body.joints.position):
                worst = max(worst, joint.lower - position, position - joint.upper)
        assert np.linalg.norm(np.array(simulation.anchor_position()) - goal) < 1e-3
        assert worst <= simulation.robot.settings.limit_slop


class Transforms:
    """A TF broadcaster that keeps what it is sent: (child frame, translation, rotation)."""

    def __init__(self, _node) -> None:
        """Keep nothing yet."""
        self.sent = {}

    def sendTransform(self, transform) -> None:  # noqa: N802 (tf2_ros's name)
        """Keep the transform's pose by its child frame."""
        t, r = transform.transform.translation, transform.transform.rotation
        self.sent[transform.child_frame_id] = ((t.x, t.y, t.z), (r.x, r.y, r.z, r.w),
                                               transform.header.frame_id)


def test_tf_carries_every_link_and_reset_returns_the_joints():
    made = []

    def factory(node):
        made.append(Transforms(node))
        return made[-1]

    with SimulatedBody(robot_description=double_pendulum(), substeps=1,
                       transform_broadcaster=factory,
                       initial_joint_positions=[0.4, -0.2]) as body:
        body.step(200)
        poses = body.node.simulation.robot.link_poses()
        sent = made[0].sent
        assert set(sent) == {'base', 'upper', 'lower', 'tip'}
        for link, (position, orientation) in poses.items():
            assert np.allclose(sent[link][0], position, atol=1e-12)
            assert np.allclose(np.abs(np.dot(sent[link][1], orientation)), 1.0, atol=1e-12)
            assert sent[link][2] == 'world'
        assert not np.allclose(body.joints.position, (0.4, -0.2))
        body.reset()
        body.step()
        # One tick from the start at rest: a step's motion, no more.
        assert np.allclose(body.joints.position, (0.4, -0.2), atol=1e-4)


def test_joint_states_come_at_the_publish_rate_asked():
    with SimulatedBody(robot_description=double_pendulum(), substeps=1,
                       publish_rate_hz=100.0) as body:
        stamps = []
        for _tick in range(100):
            body.step()
            if body.joints is not None:
                stamp = body.joints.header.stamp
                stamps.append(stamp.sec * 10**9 + stamp.nanosec)
        # The ticks 10, 20 ... 100 of 100 publish, pose and joint_states alike.
        published = sorted(set(stamps))
        assert published == [tick * 1_000_000 for tick in range(10, 101, 10)]
        stamp = body.pose.message.header.stamp
        assert stamp.sec * 10**9 + stamp.nanosec == published[-1]


def test_a_cad_mesh_that_is_not_closed_is_grabbed_by_its_convex_hull(monkeypatch):
    # Kinova's arm of the public collection ships collision meshes with open edges.
    from mouse_constraint_ros.description.robot_links import robot_links
    from test_support.robots import collection_urdf, robot_collection
    monkeypatch.setenv('AMENT_PREFIX_PATH', str(robot_collection()))
    text = collection_urdf('kinova_description/robots/kinova.urdf').read_text()
    lines = []
    links = robot_links(text, warn=lines.append)
    assert any("link 'j2s6s200_link_1'" in line and 'convex hull' in line for line in lines)
    hull = links.pieces['j2s6s200_link_1'][0].mesh
    assert hull.is_watertight and hull.is_convex
    with SimulatedBody(robot_description=text, substeps=1) as body:
        body.step()
        origin, rotation = body.node.simulation.robot.link_placements()['j2s6s200_link_1']
        centre = origin + rotation @ hull.centroid
        body.grab(centre)
        assert body.node.simulation.grabbed_link == 'j2s6s200_link_1'


def test_a_reset_while_paused_publishes_the_joints_with_its_pose():
    with SimulatedBody(robot_description=double_pendulum(), substeps=1,
                       initial_joint_positions=[0.4, -0.2]) as body:
        body.step(50)
        assert not np.allclose(body.joints.position, (0.4, -0.2))
        body.node.ticker.set_paused(True)
        body.reset()
        assert np.allclose(body.joints.position, (0.4, -0.2), atol=1e-12)
        assert body.joints.header.stamp == body.pose.message.header.stamp
