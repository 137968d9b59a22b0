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
The browser tier: a real mouse in Debian's chromium (headless, Playwright) on the rendered body.

The node and ``mouse_view`` run in-process (their executor spins on a thread while Playwright
drives the browser); chromium draws the page with SwiftShader, its first frame in 10-20 s. The
pointer is aimed at the body through the camera the browser reports (a pinhole with its vertical
field of view), away from the panel. The test checks that the loaded page is turned to the body
at a readable size, presses on the body and checks the node's
``anchor`` parameter becomes a point on the body, drags and checks the target is the pointer's
ray met with the camera-facing plane through the grabbed point and that the anchor follows it,
then releases and checks the body is free; grabs again and lets go with shift pressed 30 ms
before, and checks the body stays held once the view is done with the drag. It checks the
panel's hint and that the hold toggle's label reads dark. It saves a screenshot of the drag,
once the body is on its way back: to ``MOUSE_VIEW_SCREENSHOT`` when set (``docs/view.md`` names
the command), else to the test's temporary folder; and checks what it shows: the body's colour on
a point of the grabbed face, the neutral background off the body.
"""

import itertools
import os
from pathlib import Path
import time

import numpy as np
from PIL import Image
import pytest
from rclpy.parameter import Parameter
from scipy.spatial.transform import Rotation

# mouse_view serves its page with viser (requirements/view.txt; no rosdep key: package.xml).
pytest.importorskip('viser', reason='mouse_view needs viser: pip install -r requirements/view.txt')
from mouse_constraint_ros.inputs.grab import box_distance
from mouse_constraint_ros.monitoring.markers import BODY_COLOR
from mouse_constraint_ros.node.mouse_constraint_node import MouseConstraintNode
from mouse_constraint_ros.pointer.geometry import FRAME_FRACTION, world_point
from mouse_constraint_ros.view.command import page_address
from mouse_constraint_ros.view.node import MouseViewNode
from mouse_constraint_ros.view.scene import FLOOR_COLOR, ViewScene
from mouse_constraint_ros.view.server import start
from test_support import browser_page
from test_support.browser_page import (camera_known, CameraReports, clear_of_the_panel,
                                       drag_and_follow, held, let_go, newest_client,
                                       PinholeCamera, press_until_grabbed, spinning, VIEWPORT,
                                       wait_for)

pytestmark = pytest.mark.browser

BOX = (0.4, 0.2, 0.1)
# The body at rest where it starts; a slow guide, so that the picture catches it on its way; 100 Hz
# and no markers or diagnostics, so that the node, which shares this process with Playwright,
# leaves the CPU to the browser's software rendering.
AT_REST = {'gravity': [0.0, 0.0, 0.0], 'hold_initial_anchor': False, 'box_size': list(BOX),
           'floor': True,
           'max_target_speed': 0.1, 'rate_hz': 100.0, 'marker_rate_hz': 0.0,
           'diagnostics_rate_hz': 0.0}
DEFAULT_ANCHOR = (0.2, 0.1, 0.05)
# The drag, in pixels from the press.
DRAG = np.array([120.0, -80.0])
# How long presses are tried until the page has drawn the body (s): SwiftShader's first frame
# takes 10-20 s, several times that on a loaded machine.
GRAB_TIMEOUT = 180.0
# The hint's first words.
HINT_START = 'Press on the body'
# How far the anchor has gone back from the drag's end when the picture is taken (m).
ON_ITS_WAY = 0.05
# How far (CSS px) a checked pixel keeps from the drawn target, line and trail: more than the
# spheres' radius there (a twentieth of the box's longest edge, some 10 px).
CLEARANCE = 20.0
# The points of a face the body's pixel is chosen from: on the line through its middle along
# its longer edge, in fractions of that edge from the middle.
FACE_LINE = (-0.3, -0.15, 0.15, 0.3)
# A body pixel's hue leans from the background's toward BODY_COLOR's by at least this share of
# BODY_COLOR's own lean (a lit face washes the colour out to some half of it; grey and white: 0).
BODY_LEAN = 0.25


@pytest.fixture
def chromium_page():
    """Yield a 1280x720 page of Debian's chromium, headless; closed afterwards."""
    with browser_page.chromium_page() as page:
        yield page


def test_a_real_mouse_grabs_drags_and_releases_the_body(ros, chromium_page, tmp_path):
    """Press on the body: it is grabbed there; drag: the anchor follows; release: it is free."""
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
            _assert_framed(server, view)
            _check_the_panel(page)
            camera, press = _grab(page, server, view, node, reports)
            anchor = np.array(node.get_parameter('anchor').value)
            assert not np.allclose(anchor, DEFAULT_ANCHOR)
            assert box_distance(anchor, BOX) <= node.get_parameter('grab_margin').value
            grabbed = world_point(view.latest_pose(), anchor)
            end = press + DRAG
            drag_and_follow(page, node, view, camera, end, anchor=anchor, steps=12,
                            tolerance=0.01)
            # The picture while the body is on its way back: target, line and trail in sight.
            dragged = world_point(view.latest_pose(), anchor)
            page.mouse.move(*(end - 1.5 * DRAG), steps=4)
            wait_for(lambda: np.linalg.norm(np.subtract(
                world_point(view.latest_pose(), anchor), dragged)) > ON_ITS_WAY, 30.0,
                'the body on its way back')
            shot = Path(os.environ.get('MOUSE_VIEW_SCREENSHOT', tmp_path / 'view.png'))
            before = view.latest_pose()
            page.screenshot(path=str(shot))
            after = view.latest_pose()
            _check_the_picture(shot, camera, (before, after), anchor,
                               [grabbed, dragged, world_point(before, anchor),
                                world_point(after, anchor), node.simulation.target])
            page.mouse.up()
            wait_for(lambda: node.simulation.target is None, 10.0, 'the release freed the body')
            assert not page.get_by_text(HINT_START).is_visible()
            _shift_at_the_release_holds(page, server, view, node, reports)
    finally:
        server.stop()


def _shift_at_the_release_holds(page, server, view, node, reports: CameraReports) -> None:
    """
    README: hold shift to keep the body held where you let go; shift goes down 30 ms before.

    The browser ends the drag's segment when shift goes down and holds back the next one; the
    page confirms it at once and the view takes it as the same drag, held at the release. The
    view is done with the drag when it has taken its end, no next segment is awaited and nothing
    waits or is called: a release would have reached the node by then.
    """
    _, press = _grab(page, server, view, node, reports)
    page.mouse.move(*(press + 0.5 * DRAG), steps=6)
    page.keyboard.down('Shift')
    time.sleep(0.03)  # not a wait: shift down 30 ms before the release, the gesture tested
    page.mouse.up()
    page.keyboard.up('Shift')
    client = newest_client(server).client_id
    wait_for(lambda: not view.gestures.dragging(client) and not view.gestures.ending(client)
             and view.outbox.waiting == 0 and view.calls.pending == 0, 30.0,
             'the view done with the drag')
    assert node.simulation.target is not None, 'shift down at the release let the body go'


def _check_the_panel(page) -> None:
    """Check the hint says to press on the body and the hold toggle's label reads dark."""
    wait_for(lambda: page.get_by_text(HINT_START).is_visible(), 30.0, 'the hint shown')
    color = page.evaluate("""() => {
        const label = [...document.querySelectorAll('label')].find(
            (e) => e.textContent.includes('Hold on release'));
        return getComputedStyle(label).color;
    }""")
    channels = [int(c) for c in color[color.index('(') + 1:color.index(')')].split(',')[:3]]
    assert max(channels) <= 80, color


def _assert_framed(server, view) -> None:
    """
    Check the loaded page looks at the body, which spans a quarter of its height or more.

    The page is the newest connection at each look: one that connects again meanwhile (a
    handshake failed) is the one turned and drawn. The camera is read while viser's threads
    write it, one field at a time: a look counts only when its position, orientation and
    look-at point agree.
    """
    turned = []

    def page_turned() -> bool:
        client = newest_client(server)
        if view.scene.shown is None or not camera_known(client):
            return False
        look_at = np.array(client.camera.look_at)
        camera = PinholeCamera(client.camera)
        sight = look_at - camera.position
        turned[:] = [camera] if (
            np.allclose(look_at, view.scene.shown.position, atol=0.05)
            and np.dot(camera.forward, sight) > (1.0 - 1e-6) * np.linalg.norm(sight)) else []
        return bool(turned)

    wait_for(page_turned, 60.0, 'the page turned to the body')
    camera, pose = turned[0], view.latest_pose()
    corners = [camera.pixel(world_point(pose, np.multiply(signs, BOX) / 2))
               for signs in itertools.product((-1.0, 1.0), repeat=3)]
    width, height = np.ptp(corners, axis=0)
    assert max(width, height) > FRAME_FRACTION * VIEWPORT['height'], (width, height)
    center = camera.pixel(pose.position)
    assert np.allclose(center, (VIEWPORT['width'] / 2, VIEWPORT['height'] / 2), atol=40.0)


def _chromaticity(rgb) -> np.ndarray:
    rgb = np.asarray(rgb, dtype=float)[:3]
    return rgb / max(rgb.sum(), 1e-9)


def _looks_like_the_body(rgb) -> bool:
    """
    Return whether a pixel's colour is the body's rather than the background's.

    Shading scales a colour, light on a face washes it out and the body's translucency mixes in
    what lies behind it, so the hue decides: the pixel's chromaticity leans away from the
    background's, which is neutral (the page's white, the floor's FLOOR_COLOR, the grid's grey),
    toward BODY_COLOR's by at least ``BODY_LEAN`` of BODY_COLOR's own lean.
    """
    neutral = _chromaticity(FLOOR_COLOR)
    body = _chromaticity(BODY_COLOR) - neutral
    lean = float(np.dot(_chromaticity(rgb) - neutral, body) / np.dot(body, body))
    return lean >= BODY_LEAN


def _distance_to_path(pixel, path) -> float:
    """Return the distance (px) from ``pixel`` to the polyline through the pixels ``path``."""
    pixel = np.asarray(pixel)
    distances = []
    for a, b in zip(path[:-1], path[1:]):
        a, b = np.asarray(a), np.asarray(b)
        t = np.clip(np.dot(pixel - a, b - a) / max(np.dot(b - a, b - a), 1e-9), 0.0, 1.0)
        distances.append(np.linalg.norm(pixel - (a + t * (b - a))))
    return float(min(distances))


def _check_the_picture(shot: Path, camera: PinholeCamera, poses, anchor, path) -> None:
    """
    Check the screenshot shows the body on the grabbed face and the background off the body.

    The body moves while the picture is taken: it is drawn between its poses before and after
    (``poses``), and a point of it is looked for between the two. The body's pixel is a point
    of the grabbed face (``anchor`` on it, in the body frame) away from its edges
    (``FACE_LINE``), the one farthest from the drawn anchor, target, line and trail (``path``:
    world points from the grab to the target); the background's is beside the body, as far
    again from it as its drawn corners reach, clear of the panel, the path and the world's
    axes.
    """
    image = np.asarray(Image.open(shot).convert('RGB'))
    scale = image.shape[1] / VIEWPORT['width']

    def colour(pixel) -> np.ndarray:
        column, row = (np.asarray(pixel) * scale).astype(int)
        return image[row, column]
    path_pixels = [camera.pixel(point) for point in path if point is not None]
    axis = int(np.argmax(np.abs(anchor) / np.array(BOX)))  # the face the anchor lies on
    longer, shorter = sorted((i for i in range(3) if i != axis), key=lambda i: -BOX[i])
    candidates = []
    for fraction in FACE_LINE:
        local = np.array(anchor, dtype=float)
        local[longer], local[shorter] = fraction * BOX[longer], 0.0
        candidates.append(np.mean([camera.pixel(world_point(pose, local)) for pose in poses],
                                  axis=0))
    on_body = max(candidates, key=lambda pixel: _distance_to_path(pixel, path_pixels))
    assert _distance_to_path(on_body, path_pixels) > CLEARANCE, (on_body, path_pixels)
    assert _looks_like_the_body(colour(on_body)), (
        f'no body at {on_body}: {colour(on_body)}, see {shot}')
    corners = np.array([camera.pixel(world_point(pose, np.multiply(signs, BOX) / 2))
                        for signs in itertools.product((-1.0, 1.0), repeat=3)
                        for pose in poses])
    middle = corners.mean(axis=0)
    reach = 2.0 * np.max(np.linalg.norm(corners - middle, axis=1)) + CLEARANCE
    origin = camera.pixel((0.0, 0.0, 0.0))
    beside = [middle + reach * np.array([np.cos(angle), np.sin(angle)])
              for angle in np.linspace(0.0, 2.0 * np.pi, 24, endpoint=False)]
    clear = [pixel for pixel in beside if clear_of_the_panel(pixel)
             and _distance_to_path(pixel, path_pixels) > CLEARANCE
             and np.linalg.norm(pixel - origin) > 4.0 * CLEARANCE]
    assert clear, f'no pixel beside the body clear of the rest: {middle}, {reach}'
    off_body = clear[0]
    assert not _looks_like_the_body(colour(off_body)), (
        f'the body at {off_body}: {colour(off_body)}, see {shot}')


def _facing(pose, local, camera: PinholeCamera) -> float:
    normal = Rotation.from_quat(pose.orientation).apply(np.sign(local) * (np.abs(local) > 0))
    return float(np.dot(normal, camera.forward))


def _aim(reports: CameraReports, view):
    """
    Return the browser's camera and the pixel of the centre of the face that looks at it.

    The camera is turned to the body again first, and taken once the page reports it: a press
    before the page has drawn the body orbits it.
    """
    camera = reports.framed(view)
    assert abs(camera.aspect - 1280 / 720) < 0.05
    pose = view.latest_pose()
    faces = [tuple(s * h if i == axis else 0.0 for i, h in enumerate(np.array(BOX) / 2))
             for axis in range(3) for s in (-1.0, 1.0)]
    local = min(faces, key=lambda face: _facing(pose, face, camera))
    press = camera.pixel(world_point(pose, local))
    assert clear_of_the_panel(press)
    return camera, press


def _grab(page, server, view, node, reports: CameraReports):
    """
    Press on the body and move past the drag threshold until the page's drag holds it.

    Each try aims anew, the camera put back where it starts.

    :returns: the camera and the pressed pixel of the try that grabbed.
    """
    return press_until_grabbed(page, lambda: _aim(reports, view),
                               lambda: held(server, view, node), GRAB_TIMEOUT,
                               missed=reports.turned, over=lambda: let_go(server, view, node))
