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
The page that ``viser`` draws in the browser: the scene and the panel.

The scene holds the body and its anchor (``body_drawing``: the box of ``box_size``, or a URDF
link's pieces) or, for a whole robot, every link's pieces and the anchor (``robot_drawing``:
the body is hidden meanwhile), the target and the line between, a trail of the anchor, the
grid and axes, and the floor when the node has one; the panel the buttons and the numbers. A
page that loads is turned to the body (``framing``): the camera looks at the middle of its
drawn bounds (the robot's, at the poses shown) from where their longest edge spans a quarter of
the view's height; so is every page open when the first pose comes, or when the body's shape is
drawn anew.

``ViewScene`` builds them once on a ``viser.ViserServer`` and then only moves them: each push
sets a pose or a point, which viser sends to every browser attached. The colours and the
spheres' size are the RViz markers' (``markers`` module), so both views look alike. The pointer
callbacks and the buttons are handed in by the node; viser calls them on its own threads.

The panel starts with one line that says how to drag (``HINT``), gone at the first grab. Each
page runs ``PAGE_SCRIPT`` once: the "Hold on release" label in the text's colour (viser draws
input labels pale grey), and shift pressed mid-drag confirmed at once. viser ends a drag's
segment when a modifier goes down and starts the next only once the pointer moves or 0.1 s
passed, dropping it when the button is let go sooner; the script moves the pointer 4 px and
back (past viser's 3 px threshold) right after shift goes down, and again as the button goes up
with shift down (before viser sees the release), so that the next segment starts at once and
``Gestures`` takes it as the same drag: shift down at the release holds, however shortly
before.
"""

from collections import deque
from typing import Callable, Deque, Dict, List, Optional, Sequence, Tuple

import numpy as np
import viser
from viser import _messages

from .body_drawing import BodyDrawing
from .robot_drawing import RobotDrawing
from ..description.body_geometry import BodyGeometry
from ..monitoring.markers import LINE_FRACTION, SPHERE_FRACTION, TARGET_COLOR
from ..physics.algebra import Vector3
from ..pointer.geometry import framing, Pose, world_point, wxyz
from ..pointer.node_readouts import ViewParameters

# The trail keeps every TRAIL_EVERY-th anchor position pushed, TRAIL_LENGTH of them: about a
# second at 60 pushes a second.
TRAIL_EVERY, TRAIL_LENGTH = 3, 20
TRAIL_COLOR = (1.0, 0.75, 0.4)
FLOOR_COLOR = (0.55, 0.55, 0.55)
# The floor drawn: a square slab this wide (m) and thin, its top FLOOR_GAP times the body's
# longest edge below floor_height, so that the grid at z = 0 is drawn over it, not through it.
FLOOR_WIDTH, FLOOR_THICKNESS, FLOOR_GAP = 6.0, 0.002, 0.005
GRID_WIDTH, GRID_CELL = 4.0, 0.1
# The panel's first line until the first grab.
HINT = '*Press on the body and drag it; let go to release it.*'
# Run once by every page (see the module).
PAGE_SCRIPT = """
(() => {
  if (window.mouseViewPage) return;
  window.mouseViewPage = true;
  const style = document.createElement('style');
  style.textContent = ':has(> label[for]) { color: var(--mantine-color-text) !important; }';
  document.head.appendChild(style);
  let pressed = null;
  const nudge = (at) => {
    for (const dx of [4, 0]) {
      window.dispatchEvent(new PointerEvent('pointermove', {
        pointerId: at.id, pointerType: at.type, isPrimary: true, buttons: 1,
        clientX: at.x + dx, clientY: at.y, shiftKey: true}));
    }
  };
  window.addEventListener('pointerdown', (e) => {
    pressed = {id: e.pointerId, type: e.pointerType, x: e.clientX, y: e.clientY};
  }, true);
  window.addEventListener('pointermove', (e) => {
    if (pressed !== null && e.isTrusted && e.pointerId === pressed.id) {
      pressed.x = e.clientX;
      pressed.y = e.clientY;
    }
  }, true);
  const lift = (e) => {
    if (pressed === null || e.pointerId !== pressed.id) return;
    if (e.type === 'pointerup' && e.shiftKey) nudge(pressed);
    pressed = null;
  };
  window.addEventListener('pointerup', lift, true);
  window.addEventListener('pointercancel', lift, true);
  window.addEventListener('keydown', (e) => {
    if (e.key !== 'Shift' || e.repeat || pressed === null) return;
    const at = pressed;
    setTimeout(() => { if (pressed === at) nudge(at); }, 0);
  }, true);
})();
"""


def _rgb(color: Sequence[float]) -> tuple:
    return tuple(float(c) for c in color[:3])


class ViewScene:
    """
    The scene and the panel on one viser server.

    :param server: the viser server.
    :param parameters: the node's parameters as known now.
    """

    def __init__(self, server: viser.ViserServer, parameters: ViewParameters) -> None:
        """Add every scene node and panel element."""
        scene, gui = server.scene, server.gui
        self._server = server
        scene.world_axes.visible = True
        scene.add_grid('/grid', GRID_WIDTH, GRID_WIDTH, plane='xy', cell_size=GRID_CELL,
                       section_size=1.0)
        self.floor = scene.add_box('/floor', _rgb(FLOOR_COLOR),
                                   (FLOOR_WIDTH, FLOOR_WIDTH, FLOOR_THICKNESS), opacity=0.5,
                                   visible=False)
        self.drawing = BodyDrawing(scene, BodyGeometry.box(parameters.box_size))
        self.target = scene.add_icosphere('/target', 1.0, _rgb(TARGET_COLOR), visible=False)
        self.line = scene.add_line_segments('/constraint', np.zeros((1, 2, 3)),
                                            _rgb(TARGET_COLOR), visible=False)
        self._trail: Deque[Vector3] = deque(maxlen=TRAIL_LENGTH)
        self.trail = scene.add_line_segments('/trail', np.zeros((1, 2, 3)), _rgb(TRAIL_COLOR),
                                             visible=False)
        self.hint = gui.add_markdown(HINT)
        self.status = gui.add_markdown('')
        self.pause = gui.add_button('Pause')
        self.step = gui.add_button('Step')
        self.reset = gui.add_button('Reset')
        self.release = gui.add_button('Release')
        self.hold = gui.add_checkbox('Hold on release', False,
                                     hint='Keep the body held where it is let go (or hold '
                                          'shift while releasing).')
        self.numbers = gui.add_markdown('')
        self.reply = gui.add_markdown('')
        self.shown: Optional[Pose] = None
        self.robot: Optional[RobotDrawing] = None
        self.shown_links: Optional[Dict[str, Pose]] = None  # a robot's links as shown
        self._callbacks: List[Tuple[Callable, Callable]] = []
        self._pushes = 0
        self._anchor: Optional[Vector3] = None
        self._target: Optional[Vector3] = None
        self.apply_parameters(parameters)
        server.on_client_connect(self.frame)
        # Kept with the scene: every page, now or later, runs it once.
        gui._websock_interface.queue_message(_messages.RunJavascriptMessage(source=PAGE_SCRIPT))

    @property
    def body(self):
        """Return the body's scene node, ``/body``: the box, or the URDF link's frame."""
        return self.drawing.body

    @property
    def anchor(self):
        """Return the anchor sphere's scene node: a child of ``/body``, or the robot's."""
        return self.drawing.anchor if self.robot is None else self.robot.anchor

    def bind_body(self, on_drag: Callable, on_click: Callable) -> None:
        """
        Call ``on_drag`` and ``on_click`` on the body's drags and clicks (viser's threads).

        A robot's links, drawn now or later, call them too.
        """
        self._callbacks.append((on_drag, on_click))
        self.drawing.bind(on_drag, on_click)
        if self.robot is not None:
            self.robot.bind(on_drag, on_click)

    def grabbed(self) -> None:
        """Take the hint away: the body was grabbed."""
        if self.hint.visible:
            self.hint.visible = False

    def apply_parameters(self, parameters: ViewParameters,
                         geometry: Optional[BodyGeometry] = None, links=None) -> None:
        """
        Draw the body (or the robot), its anchor and the floor as the node's parameters say.

        The spheres and lines are the RViz markers' size for the body (``SPHERE_FRACTION``,
        ``LINE_FRACTION`` of its drawn longest edge; a robot's largest link's).

        :param parameters: the node's parameters as known.
        :param geometry: the body's shape (``pointer.body_shape``); None: the box of
            ``box_size``.
        :param links: a whole robot's links' pieces (``pointer.robot_shape``), drawn instead of
            the body; None: the body.
        """
        drawing = self.drawing
        if links is not None:
            longest = self._draw_robot(links)
        else:
            if self.robot is not None:
                self._remove_robot()
            if geometry is None:
                geometry = BodyGeometry.box(parameters.box_size)
            if drawing.draw(geometry) and self.shown is not None:
                for client in self._server.get_clients().values():
                    self.frame(client)
            longest = max(drawing.extents)
            self.anchor.position = parameters.anchor
        self.anchor.radius = self.target.radius = 0.5 * SPHERE_FRACTION * longest
        self.line.thickness = LINE_FRACTION * longest
        self.trail.thickness = 0.5 * LINE_FRACTION * longest
        self.floor.visible = parameters.floor
        self.floor.position = (0.0, 0.0, parameters.floor_height - FLOOR_GAP * longest
                               - 0.5 * FLOOR_THICKNESS)

    def _draw_robot(self, links) -> float:
        """Draw the robot of ``links`` unless drawn, the body hidden; return its longest edge."""
        if self.robot is None or self.robot.links is not links:
            if self.robot is not None:
                self.robot.remove()
            self.robot = RobotDrawing(self._server.scene, links)
            for callbacks in self._callbacks:
                self.robot.bind(*callbacks)
            self.drawing.body.visible = False
            self.shown = self.shown_links = None  # framed again at the first poses
        return self.robot.longest

    def _remove_robot(self) -> None:
        self.robot.remove()
        self.robot = None
        self.drawing.body.visible = True
        self.shown = self.shown_links = None

    def frame(self, client) -> None:
        """
        Turn a page's camera to the body at its latest pose (before the first pose: nothing).

        Also the camera a page starts with and returns to with its "Reset View".

        :param client: the page (a viser client handle).
        """
        shown = self.shown
        if shown is None:
            return
        drawing, robot = self.drawing, self.robot
        if robot is None:
            view = framing(world_point(shown, drawing.center), drawing.extents,
                           float(client.camera.fov))
        else:
            view = framing(robot.center, robot.extents, float(client.camera.fov))
        # The start first: whoever sees the page's camera turned (from another thread: this
        # runs in viser's) sees its "Reset View" turned too.
        initial = self._server.initial_camera
        initial.near, initial.position, initial.look_at = view.near, view.position, view.look_at
        with client.atomic():  # the position first: viser moves the look-at point with it
            client.camera.near = view.near
            client.camera.position = view.position
            client.camera.look_at = view.look_at

    def show_pose(self, pose: Pose, anchor: Vector3) -> None:
        """
        Move the body (and its anchor sphere) to ``pose``; extend the trail and the line.

        :param pose: the body's pose.
        :param anchor: the anchor's world position at ``pose``.
        """
        with self._server.atomic():  # position and orientation land in one frame
            self.drawing.move(pose.position, wxyz(pose.orientation))
        self._shown(pose, anchor)

    def show_robot(self, poses: Dict[str, Pose], tracked: Pose, anchor: Vector3) -> None:
        """
        Move each link of the robot (and the anchor sphere); extend the trail and the line.

        :param poses: each link's pose (world frame).
        :param tracked: the tracked link's pose (the node's ``pose``).
        :param anchor: the anchor's world position.
        """
        with self._server.atomic():  # every link lands in one frame
            self.robot.move(poses)
            self.robot.anchor.position = anchor
        self.shown_links = poses
        self._shown(tracked, anchor)

    def _shown(self, pose: Pose, anchor: Vector3) -> None:
        first = self.shown is None
        self.shown, self._anchor = pose, anchor
        if first:
            for client in self._server.get_clients().values():
                self.frame(client)
        self._pushes += 1
        if self._pushes % TRAIL_EVERY == 0:
            self._trail.append(anchor)
            if len(self._trail) >= 2:
                points = np.asarray(self._trail)
                self.trail.points = np.stack([points[:-1], points[1:]], axis=1)
                self.trail.visible = True
        if self._target is not None:
            self._update_line()

    def show_target(self, target: Optional[Vector3]) -> None:
        """Show the target and the line to it, or hide both (a free body)."""
        self._target = target
        self.target.visible = target is not None
        if target is not None:
            self.target.position = target
        self._update_line()

    def _update_line(self) -> None:
        target, anchor = self._target, self._anchor
        if target is None or anchor is None:
            self.line.visible = False
            return
        self.line.points = np.array([[anchor, target]])
        self.line.visible = True

    def show_text(self, *, status: str, numbers: str, paused: Optional[bool]) -> None:
        """Set the status line, the numbers and the pause button's label."""
        if self.status.content != status:
            self.status.content = status
        if self.numbers.content != numbers:
            self.numbers.content = numbers
        label = 'Resume' if paused else 'Pause'
        if self.pause.label != label:
            self.pause.label = label

    def show_reply(self, text: str) -> None:
        """Show the node's answer to the last button."""
        self.reply.content = text

    def on_button(self, button, callback: Callable[[], None]) -> None:
        """Call ``callback()`` when ``button`` is clicked."""
        button.on_click(lambda _event: callback())
