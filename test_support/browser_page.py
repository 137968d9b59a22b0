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
The browser tier's page and camera: Debian's chromium, headless, driven by Playwright.

``chromium_page`` opens a 1280x720 page (skipped where ``/usr/bin/chromium`` or Playwright is
missing) in the session's one browser, which ``close_browser`` closes; ``spinning`` spins an
in-process harness on a thread while Playwright drives the browser; ``PinholeCamera`` turns the
camera a page reports into pixels and rays, so that the mouse is aimed at a point of the body;
``newest_client`` is the page's connection to aim with; ``CameraReports`` keeps each camera the
pages report, and turns a page to the body and waits until it reports that camera;
``press_until_grabbed`` presses on the body until the page's drag holds it (``held``; the page's
first frame comes late in software rendering), letting a try go until the view and the node are
done with it (``let_go``); ``drag_and_follow`` drags it to a pixel and waits for the target and the
anchor to reach the pointer's plane point.
"""

import contextlib
import os
from pathlib import Path
import threading
import time
from types import SimpleNamespace
from typing import Callable, Dict, Iterator, Optional, Tuple

import numpy as np
import pytest
from scipy.spatial.transform import Rotation

from mouse_constraint_ros.pointer.geometry import camera_plane_point, world_point

CHROMIUM = '/usr/bin/chromium'
CHROMIUM_ARGS = ['--headless', '--no-sandbox', '--disable-gpu', '--disable-background-networking',
                 '--disable-component-update', '--disable-sync', '--no-first-run']
VIEWPORT = {'width': 1280, 'height': 720}
# Device pixels per CSS pixel: the browser answers each mouse event after a frame, and SwiftShader
# draws a sixteenth of the pixels at 0.25 (the test takes half the time it takes at 0.5); the
# mouse and the camera are in CSS pixels all the same. The screenshot for the docs
# (MOUSE_VIEW_SCREENSHOT set) is drawn at full size.
SCALE = 1.0 if 'MOUSE_VIEW_SCREENSHOT' in os.environ else 0.25
# How long a press may go untaken by the page before it is let go and tried again (s): a page
# drawing in software takes it within seconds, several times that on a loaded machine.
TRY_TIMEOUT = 60.0


# The session's browser, launched by the first page and closed by ``close_browser`` (the
# conftest's session end): a launch of chromium and Playwright's driver costs a second or more
# of a test's setup. Each page has a browser context of its own (cookies, storage, cache),
# closed with it; a browser that is no longer connected is launched again.
_SESSION = {}


def _browser():
    """Return the session's chromium, launched now if none is connected."""
    browser = _SESSION.get('browser')
    if browser is not None and browser.is_connected():
        return browser
    close_browser()
    sync_api = pytest.importorskip('playwright.sync_api')
    _SESSION['playwright'] = sync_api.sync_playwright().start()
    _SESSION['browser'] = _SESSION['playwright'].chromium.launch(
        executable_path=CHROMIUM, args=CHROMIUM_ARGS)
    return _SESSION['browser']


def close_browser() -> None:
    """Close the session's chromium and Playwright, if a page started them."""
    browser, playwright = _SESSION.pop('browser', None), _SESSION.pop('playwright', None)
    try:
        if browser is not None:
            browser.close()
    finally:
        if playwright is not None:
            playwright.stop()


@contextlib.contextmanager
def chromium_page() -> Iterator:
    """Yield a 1280x720 page of Debian's chromium, headless, in a browser context of its own."""
    if not os.access(CHROMIUM, os.X_OK):
        pytest.skip(f'no {CHROMIUM} (apt-get install chromium)')
    context = _browser().new_context(viewport=VIEWPORT, device_scale_factor=SCALE)
    try:
        yield context.new_page()
    finally:
        context.close()


@contextlib.contextmanager
def spinning(ros) -> Iterator[None]:
    """Spin the harness's executor on a thread until the block ends."""
    stop = threading.Event()

    def spin() -> None:
        while not stop.is_set():
            ros.executor.spin_once(timeout_sec=0.01)
    thread = threading.Thread(target=spin, daemon=True)
    thread.start()
    try:
        yield
    finally:
        stop.set()
        thread.join(timeout=5.0)


def wait_for(condition: Callable[[], bool], timeout: float, what: str) -> None:
    """Poll ``condition()`` until it holds; fail saying ``what`` after ``timeout`` s."""
    deadline = time.monotonic() + timeout
    while not condition():
        if time.monotonic() > deadline:
            pytest.fail(f'{what} within {timeout:g} s')
        time.sleep(0.05)


class PinholeCamera:
    """The browser's camera: pixels to rays and back (OpenCV axes: x right, y down, z ahead)."""

    def __init__(self, camera) -> None:
        """
        Read the position, orientation, vertical field of view and the image's aspect.

        The pixels are the page's (CSS px, where the mouse goes): the image the browser
        reports may be drawn smaller (viser lowers its resolution when frames come slowly).
        """
        self.position = np.array(camera.position, dtype=float)
        w, x, y, z = camera.wxyz
        self.rotation = Rotation.from_quat([x, y, z, w]).as_matrix()
        self.aspect = camera.image_width / camera.image_height
        self.width, self.height = VIEWPORT['width'], VIEWPORT['height']
        self.focal = 0.5 * self.height / np.tan(0.5 * camera.fov)

    def pixel(self, point) -> np.ndarray:
        """Return where the world ``point`` is drawn on the canvas (CSS px)."""
        x, y, z = self.rotation.T @ (np.asarray(point) - self.position)
        return np.array([0.5 * self.width + self.focal * x / z,
                         0.5 * self.height + self.focal * y / z])

    def ray(self, pixel) -> np.ndarray:
        """Return the world direction of the ray through ``pixel``."""
        u, v = pixel
        return self.rotation @ np.array([(u - 0.5 * self.width) / self.focal,
                                         (v - 0.5 * self.height) / self.focal, 1.0])

    @property
    def forward(self) -> np.ndarray:
        """Return the viewing direction."""
        return self.rotation[:, 2]


def camera_known(client) -> bool:
    """Return whether a page has reported its camera (viser raises before it has)."""
    try:
        return client.camera.image_height > 0 and client.camera.fov > 0.0
    except AssertionError:
        return False


def newest_client(server):
    """
    Return the page's client: the newest connection.

    A page that connected again (a websocket handshake failed) leaves an older connection whose
    camera is not the one drawn; aim with the newest.
    """
    clients = server.get_clients()
    return clients[max(clients)]


class CameraReports:
    """
    The camera each page reported last, whole as it came (a viser camera message).

    Made before the page connects: every report from its first on is kept. The camera a client
    handle holds is written field by field where the server sets it; a report is one message.

    :param server: the viser server the pages connect to.
    """

    def __init__(self, server) -> None:
        """Follow the camera of every page that connects to ``server`` from now on."""
        self._server = server
        self._latest: Dict[int, SimpleNamespace] = {}
        self._framed: Optional[Tuple[int, np.ndarray, np.ndarray]] = None
        server.on_client_connect(self._follow)

    async def _follow(self, client) -> None:  # async: on viser's loop, before its first report
        client.camera.on_update(self._report)

    async def _report(self, camera) -> None:
        self._latest[camera.client.client_id] = SimpleNamespace(
            position=np.array(camera.position), wxyz=np.array(camera.wxyz),
            look_at=np.array(camera.look_at), fov=float(camera.fov),
            image_width=camera.image_width, image_height=camera.image_height)

    def framed(self, view, timeout: float = 30.0) -> 'PinholeCamera':
        """
        Turn the newest page's camera to the body (``ViewScene.frame``); return it once reported.

        The page has taken the camera when it reports it back: its position and look-at point
        are the framing's (the server's initial camera, which ``frame`` sets), and it looks
        from the one to the other (a report made while the page turns may not yet).

        :param view: the ``MouseViewNode`` whose scene frames the body.
        """
        client = newest_client(self._server)
        view.scene.frame(client)
        initial = self._server.initial_camera
        position, look_at = np.array(initial.position), np.array(initial.look_at)
        sight = look_at - position

        def reported() -> bool:
            camera = self._latest.get(client.client_id)
            return (camera is not None and np.allclose(camera.position, position, atol=1e-3)
                    and np.allclose(camera.look_at, look_at, atol=1e-3)
                    and np.dot(PinholeCamera(camera).forward, sight)
                    > (1.0 - 1e-6) * np.linalg.norm(sight))
        wait_for(reported, timeout, 'the page reported the camera turned to the body')
        self._framed = (client.client_id, position, look_at)
        return PinholeCamera(self._latest[client.client_id])

    def turned(self) -> bool:
        """Return whether the page last framed has reported its view turned away since."""
        if self._framed is None:
            return False
        client_id, position, look_at = self._framed
        camera = self._latest[client_id]
        return not (np.allclose(camera.position, position, atol=1e-3)
                    and np.allclose(camera.look_at, look_at, atol=1e-3))


def held(server, view, node) -> bool:
    """
    Return whether the page's drag holds the body: its grab taken, nothing before it due.

    A try that the page took late ends with a release; the next try's grab goes once the node
    answered that release (``ReleaseOrder``): with nothing waiting in the view, a target in the
    node is this drag's.

    :param node: the ``MouseConstraintNode``.
    """
    return (view.gestures.dragging(newest_client(server).client_id) and view.outbox.waiting == 0
            and node.simulation.target is not None)


def let_go(server, view, node) -> bool:
    """
    Return whether a try let go is over: no drag in the view, nothing waiting, the node free.

    A drag the view took ends with a release a segment gap after the button (``Gestures``):
    until the node answered it, a press would go on with that drag.
    """
    return (not view.gestures.dragging(newest_client(server).client_id)
            and view.outbox.waiting == 0 and view.calls.pending == 0
            and node.simulation.target is None)


def clear_of_the_panel(pixel) -> bool:
    """Return whether ``pixel`` lies in the canvas away from the panel and the page's notes."""
    return 100 < pixel[0] < 900 and 150 < pixel[1] < 650


def press_until_grabbed(page, aim: Callable[[], Tuple[PinholeCamera, np.ndarray]],
                        grabbed: Callable[[], bool], timeout: float, *,
                        missed: Callable[[], bool], over: Callable[[], bool]):
    """
    Press on the body and move past the drag threshold until the node takes the grab.

    Each try aims anew (``aim``: the camera put back where it starts, and the pixel to press)
    and ends when the page took it: as a drag that holds the body (``grabbed``), or, pressed
    before the page drew the body there, as a turn of the view (``missed``); a try that neither
    within ``TRY_TIMEOUT`` counts as missed. A missed try is let go, and pressed again once it is
    over, until ``timeout`` s.

    :param grabbed: whether the page's drag holds the body (``held``).
    :param missed: whether the page turned the view since it was aimed
        (``CameraReports.turned``).
    :param over: whether a try let go is over (``let_go``).
    :returns: the camera and the pressed pixel of the try that grabbed.
    """
    deadline = time.monotonic() + timeout
    while True:
        camera, press = aim()
        page.mouse.move(*press)
        page.mouse.down()
        page.mouse.move(*(press + (6.0, 0.0)), steps=3)
        try:
            wait_for(lambda: grabbed() or missed(), TRY_TIMEOUT, 'the page took the press')
        except pytest.fail.Exception:
            pass
        if grabbed():
            return camera, press
        page.mouse.up()  # the page was not drawn yet: press again
        if time.monotonic() > deadline:
            shot = Path(os.environ.get('MOUSE_VIEW_SCREENSHOT', '/tmp/view.png'))
            page.screenshot(path=str(shot.with_name('view-no-grab.png')))
            pytest.fail(f'no grab reached the node within {timeout:g} s of pressing at '
                        f'{press}: see {shot.with_name("view-no-grab.png")}')
        wait_for(over, 30.0, 'the try let go was over')


def drag_and_follow(page, node, view, camera: PinholeCamera, pixel, *, anchor, steps: int,
                    tolerance: float) -> None:
    """
    Drag the held pointer to ``pixel``; wait until the target and the anchor follow it.

    Where they go is the point under ``pixel`` on the camera-facing plane through the grabbed
    point (the anchor's world point before the drag), as the view's drag places it.

    :param node: the ``MouseConstraintNode`` (its simulation's target).
    :param view: the ``MouseViewNode`` (its latest pose).
    :param anchor: the anchor, body frame (m).
    :param steps: Playwright's mouse move steps.
    :param tolerance: how near (m) the target and the anchor must come.
    """
    grabbed = world_point(view.latest_pose(), anchor)
    page.mouse.move(*pixel, steps=steps)
    expected = camera_plane_point(camera.position, camera.ray(pixel), through=grabbed,
                                  normal=camera.forward)
    wait_for(lambda: node.simulation.target is not None and np.linalg.norm(
        np.subtract(node.simulation.target, expected)) < tolerance, 10.0,
        "the target reached the pointer's plane point")
    wait_for(lambda: np.linalg.norm(np.subtract(world_point(
        view.latest_pose(), anchor), expected)) < tolerance, 10.0,
        "the anchor followed the drag to the pointer's plane point")
