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
The browser tier on a mesh body: a real mouse in Debian's chromium on the mug, a URDF link.

As in test_view_browser, the node and ``mouse_view`` run in-process while Playwright drives
headless chromium (SwiftShader). The node's body is the mug (``test_support.meshes``), its mesh
written to the test's folder and named by absolute path in ``robot_description``. The test checks
that the view's scene holds the mesh (a scene node of the file's vertices) and that the page is
turned to the mug's middle, presses on the mug's outer wall where it faces the camera, and checks
that the anchor the node took lies on the mesh's surface (within 2 mm, in the link frame, by
trimesh's closest point); then drags and checks that the target is the pointer's ray met with the
camera-facing plane through the grabbed point and that the body moved with it; then releases.
"""

from pathlib import Path

import numpy as np
import pytest
from rclpy.parameter import Parameter
import trimesh

# mouse_view serves its page with viser (requirements/view.txt; no rosdep key: package.xml).
pytest.importorskip('viser', reason='mouse_view needs viser: pip install -r requirements/view.txt')
from mouse_constraint_ros.node.mouse_constraint_node import MouseConstraintNode
from mouse_constraint_ros.pointer.geometry import local_point, world_point
from mouse_constraint_ros.view.command import page_address
from mouse_constraint_ros.view.node import MouseViewNode
from mouse_constraint_ros.view.scene import ViewScene
from mouse_constraint_ros.view.server import start
from test_support import browser_page
from test_support.browser_page import (camera_known, CameraReports, clear_of_the_panel,
                                       drag_and_follow, held, let_go, newest_client,
                                       press_until_grabbed, spinning, wait_for)
from test_support.meshes import geometry, MUG_HEIGHT, MUG_RADIUS, urdf, write
from test_support.meshes import mug as mug_mesh

pytestmark = pytest.mark.browser

# The anchor before the grab: on the mug's axis, half way up (the link frame).
START_ANCHOR = (0.0, 0.0, 0.5 * MUG_HEIGHT)
# The mug at rest; inertia from its mesh at a density; 100 Hz and no markers or diagnostics, so
# that the node, which shares this process with Playwright, leaves the CPU to the browser.
AT_REST = {'gravity': [0.0, 0.0, 0.0], 'hold_initial_anchor': False, 'density': 1000.0,
           'anchor': list(START_ANCHOR), 'max_target_speed': 0.1, 'rate_hz': 100.0,
           'marker_rate_hz': 0.0, 'diagnostics_rate_hz': 0.0}
# How far from the mesh's surface the anchor may lie (m).
ON_THE_SURFACE = 0.002
# The drag, in pixels from the press: some 4 cm at the mug's framing.
DRAG = np.array([60.0, -40.0])
# How long presses are tried until the page has drawn the body (s): SwiftShader's first frame
# takes 10-20 s, several times that on a loaded machine.
GRAB_TIMEOUT = 180.0


@pytest.fixture
def chromium_page():
    """Yield a 1280x720 page of Debian's chromium, headless; closed afterwards."""
    with browser_page.chromium_page() as page:
        yield page


def test_a_real_mouse_grabs_the_mug_on_its_mesh_and_drags_it(ros, chromium_page, tmp_path):
    """Press on the mug: the anchor on its mesh; drag: the body follows; release: it is free."""
    path = write(mug_mesh(), tmp_path / 'mug.stl')
    mesh = trimesh.load(path, force='mesh')
    description = urdf([geometry('mesh', filename=str(path), element='visual'),
                        geometry('mesh', filename=str(path))])
    server = start('127.0.0.1', 0)
    try:
        node = ros.add(MouseConstraintNode(context=ros.context, parameter_overrides=[
            Parameter(name, value=value) for name, value in
            {**AT_REST, 'robot_description': description}.items()]))
        view = ros.add(MouseViewNode(scene_factory=lambda p: ViewScene(server, p),
                                     context=ros.context))
        reports = CameraReports(server)
        page = chromium_page
        with spinning(ros):
            page.goto(page_address('127.0.0.1', server.get_port()), timeout=60_000)
            wait_for(lambda: any(camera_known(c) for c in server.get_clients().values()),
                     60.0, 'the browser reported its camera')
            wait_for(lambda: len(view.scene.drawing.pieces) == 1, 60.0, 'the mug drawn')
            [piece] = view.scene.drawing.pieces
            assert len(piece.vertices) == len(mesh.vertices)
            assert np.array_equal(piece.faces, mesh.faces)
            _wait_framed(server, view)
            start_pose = view.latest_pose()
            camera, press = press_until_grabbed(
                page, lambda: _aim(reports, view), lambda: held(server, view, node),
                GRAB_TIMEOUT, missed=reports.turned,
                over=lambda: let_go(server, view, node))
            assert not np.allclose(node.get_parameter('anchor').value, START_ANCHOR)
            anchor = np.array(node.get_parameter('anchor').value)
            _, distance, _ = trimesh.proximity.closest_point(mesh, [anchor])
            print(f'the anchor lies {distance[0]:.3g} m from the mesh surface')
            assert distance[0] <= ON_THE_SURFACE, (anchor, distance[0])
            drag_and_follow(page, node, view, camera, press + DRAG, anchor=anchor, steps=8,
                            tolerance=0.0025)
            # The grabbed point went with the drag (some 4 cm): the body followed, however it
            # turned about that point on the way.
            moved = np.linalg.norm(np.subtract(world_point(view.latest_pose(), anchor),
                                               world_point(start_pose, anchor)))
            assert moved > 0.02, moved
            page.screenshot(path=str(Path(tmp_path) / 'mug.png'))
            page.mouse.up()
            wait_for(lambda: node.simulation.target is None, 10.0, 'the release freed the body')
    finally:
        server.stop()


def _wait_framed(server, view) -> None:
    """Wait until the page looks at the mug's middle (half its height up the link's z)."""
    def turned() -> bool:
        client = newest_client(server)
        if view.scene.shown is None or not camera_known(client):
            return False
        middle = world_point(view.scene.shown, (0.0, 0.0, 0.5 * MUG_HEIGHT))
        return np.allclose(client.camera.look_at, middle, atol=1e-3)
    wait_for(turned, 60.0, "the page turned to the mug's middle")


def _aim(reports: CameraReports, view):
    """
    Return the browser's camera and the pixel of the mug's outer wall that faces it, half way up.

    The camera is turned to the body again first, and taken once the page reports it: a press
    before the page has drawn the body orbits it.
    """
    camera = reports.framed(view)
    pose = view.latest_pose()
    toward = np.subtract(local_point(camera.position, pose), START_ANCHOR)[:2]
    toward /= np.linalg.norm(toward)
    local = (MUG_RADIUS * toward[0], MUG_RADIUS * toward[1], START_ANCHOR[2])
    press = camera.pixel(world_point(pose, local))
    assert clear_of_the_panel(press)
    return camera, press
