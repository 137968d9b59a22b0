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
``mouse_view`` in-process against a node that serves a whole robot: the double pendulum.

As in test_view_node, the view runs with its real scene on a viser server (no browser) and its
own click and drag callbacks are called as viser calls them. The page draws every link that has
pieces as a scene node of its own, each at the pose the node's robot has it (placed from
``joint_states``), and follows the robot as it moves; a click's ray and a press on a link that
is not the tracked one grab that link, and a drag moves the robot.
"""

import asyncio
from types import SimpleNamespace

import numpy as np
import pytest
from rclpy.parameter import Parameter

# mouse_view serves its page with viser (requirements/view.txt; no rosdep key: package.xml).
viser = pytest.importorskip('viser',
                            reason='mouse_view needs viser: pip install -r requirements/view.txt')
from mouse_constraint_ros.node.mouse_constraint_node import MouseConstraintNode
from mouse_constraint_ros.pointer.geometry import world_point
from mouse_constraint_ros.pointer.gestures import HOLD_MODIFIER
from mouse_constraint_ros.pointer.node_readouts import ViewParameters
from mouse_constraint_ros.view.node import MouseViewNode
from mouse_constraint_ros.view.scene import ViewScene
from mouse_constraint_ros.view.server import start
from test_support.robots import double_pendulum

# The pendulum bent and at rest (no gravity): the tracked link is the tip, below the lower rod.
START = [0.6, -0.9]
AT_REST = {'gravity': [0.0, 0.0, 0.0], 'hold_initial_anchor': False,
           'initial_joint_positions': START}
CAMERA = SimpleNamespace(position=np.array([0.0, -3.0, -0.3]),
                         look_at=np.array([0.0, 0.0, -0.3]))
# A point of the upper rod's face toward the camera (-y), in its link frame.
ON_UPPER = (0.0, -0.02, -0.3)


@pytest.fixture
def server():
    """Yield a viser server on a free port, stopped afterwards."""
    server = start('127.0.0.1', 0)
    yield server
    server.stop()


def _started(ros, server, **parameters):
    node = ros.add(MouseConstraintNode(context=ros.context, parameter_overrides=[
        Parameter(name, value=value) for name, value in
        {**AT_REST, 'robot_description': double_pendulum(), **parameters}.items()]))
    view = ros.add(MouseViewNode(scene_factory=lambda p: ViewScene(server, p),
                                 context=ros.context))
    clients = view.node_services.clients.values()
    assert ros.spin_until(lambda: view.scene.shown_links is not None
                          and view.follower.parameters_known
                          and view.grab_publisher.get_subscription_count() > 0
                          and all(c.service_is_ready() for c in clients))
    ros.spin_for(0.2)
    return node, view


def _drawn_as_the_node_has_them(view, node, tolerance: float) -> bool:
    """Return whether every link's scene node is at the link's pose in the node's robot."""
    expected = node.simulation.robot.link_poses()
    for link, frame in view.scene.robot.frames.items():
        position, (x, y, z, w) = expected[link]
        if not np.allclose(frame.position, position, atol=tolerance):
            return False
        if abs(np.dot(frame.wxyz, (w, x, y, z))) < 1.0 - tolerance:  # q and -q: one turn
            return False
    return True


def test_every_link_is_a_scene_node_of_its_own_placed_by_joint_states(ros, server):
    """Two rods, two link frames with their box; at the node's link poses; the body hidden."""
    node, view = _started(ros, server)
    scene = view.scene
    robot = scene.robot
    assert robot is not None and not scene.body.visible
    # The base and the tip have no pieces: nothing to draw.
    assert set(robot.frames) == {'upper', 'lower'}
    for link, frame in robot.frames.items():
        assert isinstance(frame, viser.FrameHandle)
        [box] = robot.pieces[link]
        assert isinstance(box, viser.BoxHandle) and box.name.startswith(frame.name + '/')
        assert tuple(box.dimensions) == pytest.approx((0.04, 0.04, 0.5))
        assert tuple(box.position) == pytest.approx((0.0, 0.0, -0.25))
    assert ros.spin_until(lambda: _drawn_as_the_node_has_them(view, node, 1e-9))
    # Bent: the lower rod is turned by both joints, not where the tracked link's pose alone
    # would put it.
    lower = node.simulation.robot.link_poses()['lower']
    assert np.linalg.norm(np.subtract(lower[0], (0.0, 0.0, -0.5))) > 0.1
    assert tuple(robot.frames['lower'].position) != pytest.approx(view.latest_pose().position)


def test_a_click_on_the_upper_rod_grabs_it_there(ros, server):
    """The ray meets the upper rod first: the node holds that link at that point."""
    node, view = _started(ros, server)
    assert node.simulation.grabbed_link == 'tip'  # the tracked link, until a grab
    pressed = world_point(view.scene.shown_links['upper'], ON_UPPER)
    origin = np.add(pressed, (0.0, -2.0, 0.0))
    asyncio.run(view._on_click(SimpleNamespace(ray_origin=tuple(origin),
                                               ray_direction=(0.0, 1.0, 0.0),
                                               modifier=HOLD_MODIFIER)))
    assert ros.spin_until(lambda: node.simulation.target is not None)
    assert node.simulation.grabbed_link == 'upper'
    assert node.get_parameter('anchor').value == pytest.approx(ON_UPPER, abs=1e-9)
    # The view heard the grab: its anchor sphere is on the upper rod's point.
    assert ros.spin_until(lambda: view.robot.anchor_link == 'upper' and np.allclose(
        view.scene.anchor.position, pressed, atol=1e-6))


def test_a_press_on_the_upper_rod_grabs_it_and_a_drag_swings_the_robot(ros, server):
    """A drag's start on the upper link's scene node: that point; its moves: the robot follows."""
    node, view = _started(ros, server)
    pressed = world_point(view.scene.shown_links['upper'], ON_UPPER)
    _drag(view, 'start', pressed, target=view.scene.robot.frames['upper'])
    assert ros.spin_until(lambda: node.simulation.target is not None)
    assert node.simulation.grabbed_link == 'upper'
    assert node.get_parameter('anchor').value == pytest.approx(ON_UPPER, abs=1e-6)
    start = node.simulation.robot.link_poses()
    # The pressed point turned 0.4 rad further about the shoulder (+y): within the rod's reach,
    # on the plane through it that faces the camera (y = -0.02).
    turn = 0.4
    pointer = np.array((pressed[0] * np.cos(turn) + pressed[2] * np.sin(turn), pressed[1],
                        -pressed[0] * np.sin(turn) + pressed[2] * np.cos(turn)))
    _drag(view, 'update', pressed, end=pointer)
    assert ros.spin_until(lambda: np.allclose(node.simulation.target, pointer, atol=1e-9))
    assert ros.spin_until(lambda: np.linalg.norm(
        node.simulation.anchor_position() - pointer) < 1e-3, timeout=20.0)
    assert node.simulation.robot.joint_positions()[0] == pytest.approx(START[0] + turn, abs=1e-2)
    moved = node.simulation.robot.link_poses()
    assert np.linalg.norm(np.subtract(moved['lower'][0], start['lower'][0])) > 0.1
    # The page follows the robot: every link where the node has it, within a tick's motion.
    assert ros.spin_until(lambda: _drawn_as_the_node_has_them(view, node, 1e-3))


def _drag(view, phase: str, pressed, *, end=(0.0, 0.0, 0.0), target=None) -> None:
    event = SimpleNamespace(phase=phase, client_id=1, client=SimpleNamespace(camera=CAMERA),
                            start_position=tuple(pressed), end_position=tuple(end),
                            modifier=None, target=target)
    asyncio.run(view._on_drag(event))


def test_a_node_that_comes_back_with_a_body_is_drawn_as_the_body_and_back(ros, server):
    """Parameters of a box after the robot's: the robot's nodes gone, the box shown; and back."""
    node, view = _started(ros, server)
    robot_parameters = view.parameters
    frames = list(view.scene.robot.frames.values())
    view._parameters_changed(ViewParameters())
    assert view.scene.robot is None and not view.robot.active
    assert view.scene.body.visible and isinstance(view.scene.body, viser.BoxHandle)
    assert all(name not in server.scene._handle_from_node_name
               for name in (frame.name for frame in frames))
    view._parameters_changed(robot_parameters)
    assert view.scene.robot is not None and not view.scene.body.visible
    # Drawn again at the next joint_states.
    assert ros.spin_until(lambda: _drawn_as_the_node_has_them(view, node, 1e-9)
                          and view.scene.shown_links is not None)
