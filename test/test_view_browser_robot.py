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
The browser tier on a whole robot: a real mouse in Debian's chromium on the double pendulum.

As in test_view_browser, the node and ``mouse_view`` run in-process while Playwright drives
headless chromium (SwiftShader). The node serves the double pendulum (``test_support.robots``),
bent and at rest. The test waits until the page is turned to the robot, presses on the upper
rod (not the tracked link, the tip) where it faces the camera, and checks that the node took
the grab on that link, its anchor on the rod; then drags the pointer to where the grabbed point
would be turned further about the shoulder and checks that the target is the pointer's ray met
with the camera-facing plane through the grabbed point, that the shoulder turned, and that the
page draws every link where the node has it; then releases.
"""

from pathlib import Path

import numpy as np
import pytest
from rclpy.parameter import Parameter

# mouse_view serves its page with viser (requirements/view.txt; no rosdep key: package.xml).
pytest.importorskip('viser', reason='mouse_view needs viser: pip install -r requirements/view.txt')
from mouse_constraint_ros.node.mouse_constraint_node import MouseConstraintNode
from mouse_constraint_ros.pointer.geometry import camera_plane_point, framing, world_point
from mouse_constraint_ros.view.command import page_address
from mouse_constraint_ros.view.node import MouseViewNode
from mouse_constraint_ros.view.scene import ViewScene
from mouse_constraint_ros.view.server import start
from test_support import browser_page
from test_support.browser_page import (camera_known, CameraReports, clear_of_the_panel, held,
                                       let_go, newest_client, press_until_grabbed, spinning,
                                       wait_for)
from test_support.robots import double_pendulum

pytestmark = pytest.mark.browser

# The pendulum bent and at rest (no gravity; damped, so that it settles after the drag); 100 Hz
# and no markers or diagnostics, so that the node, which shares this process with Playwright,
# leaves the CPU to the browser.
START = [0.6, -0.9]
AT_REST = {'gravity': [0.0, 0.0, 0.0], 'hold_initial_anchor': False,
           'initial_joint_positions': START, 'angular_damping': 2.0, 'rate_hz': 100.0,
           'marker_rate_hz': 0.0, 'diagnostics_rate_hz': 0.0,
           'robot_description': double_pendulum()}
# The pressed point: the middle of the upper rod's face toward the camera (-y), link frame.
ON_UPPER = (0.0, -0.02, -0.25)
# How far further about the shoulder the drag turns the pressed point (rad).
TURN = 0.35
# How long presses are tried until the page has drawn the robot (s): SwiftShader's first frame
# takes 10-20 s, several times that on a loaded machine.
GRAB_TIMEOUT = 180.0


@pytest.fixture
def chromium_page():
    """Yield a 1280x720 page of Debian's chromium, headless; closed afterwards."""
    with browser_page.chromium_page() as page:
        yield page


def test_a_real_mouse_grabs_the_upper_rod_and_drags_the_robot(ros, chromium_page, tmp_path):
    """Press on the upper rod: that link is grabbed there; drag: the robot turns after it."""
    server = start('127.0.0.1', 0)
    try:
        node = ros.add(MouseConstraintNode(context=ros.context, parameter_overrides=[
            Parameter(name, value=value) for name, value in AT_REST.items()]))
        view = ros.add(MouseViewNode(scene_factory=lambda p: ViewScene(server, p),
                                     context=ros.context))
        reports = CameraReports(server)
        page = chromium_page
        with spinning(ros):
            page.goto(page_address('127.0.0.1', server.get_port()), timeout=60_000)
            wait_for(lambda: any(camera_known(c) for c in server.get_clients().values()),
                     60.0, 'the browser reported its camera')
            wait_for(lambda: _framed(server, view), 60.0, 'the page turned to the robot')
            assert node.simulation.grabbed_link == 'tip'  # the tracked link, until a grab
            camera, press = press_until_grabbed(page, lambda: _aim(reports, view),
                                                lambda: _held(server, view, node), GRAB_TIMEOUT,
                                                missed=reports.turned,
                                                over=lambda: let_go(server, view, node))
            anchor = np.array(node.get_parameter('anchor').value)
            rod = view.robot.shape.geometries['upper']
            assert rod.distance(anchor) <= node.get_parameter('grab_margin').value, anchor
            # The drag's plane faces the camera through the grabbed point: through the target.
            through = np.array(node.simulation.target)
            shoulder = node.simulation.robot.joint_positions()[0]
            # Where the anchor would be, turned further about the shoulder (+y).
            x, y, z = world_point(view.scene.shown_links['upper'], anchor)
            turned = (x * np.cos(TURN) + z * np.sin(TURN), y, -x * np.sin(TURN) + z * np.cos(TURN))
            pixel = camera.pixel(turned)
            assert clear_of_the_panel(pixel)
            page.mouse.move(*pixel, steps=8)
            expected = camera_plane_point(camera.position, camera.ray(pixel), through=through,
                                          normal=camera.forward)
            wait_for(lambda: np.linalg.norm(np.subtract(node.simulation.target, expected))
                     < 0.005, 20.0, "the target reached the pointer's plane point")
            wait_for(lambda: node.simulation.robot.joint_positions()[0] > shoulder + 0.5 * TURN,
                     30.0, f'the shoulder turned after the drag (from {shoulder:.3f} rad)')
            wait_for(lambda: _drawn_as_the_node_has_them(view, node, 2e-3), 30.0,
                     'every link drawn where the node has it')
            page.screenshot(path=str(Path(tmp_path) / 'robot.png'))
            page.mouse.up()
            wait_for(lambda: node.simulation.target is None, 10.0, 'the release freed the robot')
    finally:
        server.stop()


def _held(server, view, node) -> bool:
    """Return whether the page's drag holds the upper rod (``browser_page.held``)."""
    return held(server, view, node) and node.simulation.grabbed_link == 'upper'


def _framed(server, view) -> bool:
    """Return whether the page looks at the middle of the robot as drawn, from its framing."""
    client = newest_client(server)
    robot = view.scene.robot
    if robot is None or view.scene.shown_links is None or not camera_known(client):
        return False
    expected = framing(robot.center, robot.extents, float(client.camera.fov))
    return (np.allclose(client.camera.look_at, expected.look_at, atol=1e-3)
            and np.allclose(client.camera.position, expected.position, atol=1e-3))


def _aim(reports: CameraReports, view):
    """
    Return the browser's camera and the pixel of the upper rod's face that looks at it.

    The camera is turned to the robot again first, and taken once the page reports it: a press
    before the page has drawn the robot orbits it.
    """
    camera = reports.framed(view)
    press = camera.pixel(world_point(view.scene.shown_links['upper'], ON_UPPER))
    assert clear_of_the_panel(press), press
    return camera, press


def _drawn_as_the_node_has_them(view, node, tolerance: float) -> bool:
    """Return whether every link's scene node is at the link's pose in the node's robot."""
    expected = node.simulation.robot.link_poses()
    for link, frame in view.scene.robot.frames.items():
        position, (x, y, z, w) = expected[link]
        if not np.allclose(frame.position, position, atol=tolerance):
            return False
        if abs(np.dot(frame.wxyz, (w, x, y, z))) < 1.0 - tolerance:
            return False
    return True
