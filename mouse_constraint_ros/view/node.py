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
The ``mouse_view`` node: serves the page (``scene``) and turns its gestures into the node's input.

It wires ROS to pure parts and holds no geometry of its own: ``Gestures`` says what a pointer
event sends, ``ReleaseOrder`` when (nothing past a release the node has not answered),
``PushThrottle`` how often a pose goes to the browser, ``node_readouts`` what the
node's parameters and /diagnostics say, ``NodeFollower`` whether the node is there and its
parameters, ``BodyShape`` the body's shape they give (a URDF link or the box: drawn, and met by
a click's ray), ``RobotView`` a whole robot's (every link placed by ``joint_states``, drawn, and
met by a click's ray), ``panel`` what the panel's buttons call and what its numbers say. All
names are the ``interface`` module's, relative to the view's namespace, so
``--ros-args -r __ns:=/robot`` views ``/robot/mouse_constraint``.

viser calls the pointer and button callbacks on its own threads; they only queue work with the
time of the event, which a timer runs every ``WORK_PERIOD`` on the executor's thread, so every
publish and service call happens there (the EventsExecutor has no guard conditions to wake it
sooner). The same timer takes the newest pose and joint_states (``NewestMessage``: no callback
per message) and offers them to the throttle; they are decoded only when used.
"""

import queue
import time
from typing import Callable, List, Optional, Tuple

from diagnostic_msgs.msg import DiagnosticArray
from geometry_msgs.msg import PointStamped, PoseStamped
from rclpy.clock import Clock, ClockType
from rclpy.node import Node
from rclpy.qos import QoSProfile, ReliabilityPolicy
from rclpy.serialization import deserialize_message
from visualization_msgs.msg import Marker, MarkerArray

from .panel import node_name, NodeServices, numbers_text, PanelReadings, status_text
from .robot_view import RobotView
from ..pointer.body_shape import BodyShape
from ..pointer.geometry import Pose, world_point
from ..pointer.gestures import Action, Camera, Gestures, GRAB, RELEASE
from ..pointer.newest_message import NewestMessage
from ..pointer.node_follower import DISCOVERY_SECONDS, NodeFollower
from ..pointer.node_readouts import Readouts, ViewParameters
from ..pointer.push_throttle import PushThrottle
from ..pointer.release_order import ReleaseOrder
from ..pointer.service_calls import ServiceCalls
from ..wire.interface import (DIAGNOSTICS_TOPIC, GRAB_TOPIC, MARKERS_TOPIC, MONITOR_DEPTH,
                              PAUSE_SERVICE, POSE_TOPIC, RELEASE_SERVICE, RESET_SERVICE,
                              STEP_SERVICE, TARGET_QOS, TARGET_TOPIC, VIEW_NODE_NAME)
from ..wire.messages import point_message

# Only the newest pose and twist matter to the view: depth 1, best effort (a reliable
# publisher serves it).
LATEST_QOS = QoSProfile(depth=1, reliability=ReliabilityPolicy.BEST_EFFORT)
# How often (s) the queued work runs and the throttle flushes.
WORK_PERIOD = 0.004
# How often (s) the panel's numbers are shown again.
PANEL_PERIOD = 0.2
# How often (s) the view looks for the node.
PRESENCE_PERIOD = 0.5


def _pose(message: PoseStamped) -> Pose:
    """Return the pose of a PoseStamped."""
    p = message.pose.position
    q = message.pose.orientation
    return Pose((p.x, p.y, p.z), (q.x, q.y, q.z, q.w))


def _camera(client) -> Optional[Camera]:
    """Return the browser's camera, or None before the browser has reported it."""
    try:
        camera = client.camera
        position = tuple(float(c) for c in camera.position)
        forward = tuple(float(a) - b for a, b in zip(camera.look_at, position))
    except (AssertionError, AttributeError, TypeError, ValueError):
        return None
    return Camera(position, forward)


class MouseViewNode(Node):
    """
    The view of one ``mouse_constraint`` node in this namespace.

    :param scene_factory: makes the page (``ViewScene``) from the node's parameters as known.
    :param clock: seconds of a monotonic clock (the throttle's time).
    :param discovery_seconds: how long it looks for the node before it says there is none.
    :param kwargs: passed to ``rclpy.node.Node``.
    """

    def __init__(self, *, scene_factory: Callable, clock: Callable[[], float] = time.monotonic,
                 discovery_seconds: float = DISCOVERY_SECONDS, **kwargs) -> None:
        """Create the topics, services, timers and the scene."""
        super().__init__(VIEW_NODE_NAME, **kwargs)
        self.readouts = Readouts()
        self.gestures = Gestures()
        self.throttle = PushThrottle()
        # What the gestures send, stamped: nothing after a release goes before its answer.
        self.outbox: ReleaseOrder[Tuple[Action, int]] = ReleaseOrder(
            lambda item: item[0].kind == RELEASE)
        self._monotonic = clock
        self._work: 'queue.SimpleQueue[Callable[[], None]]' = queue.SimpleQueue()
        self._pose_raw: Optional[bytes] = None
        self._latest: Optional[Pose] = None
        self.shape = BodyShape()
        self.pushes = 0  # poses pushed to the page
        self.grab_publisher = self.create_publisher(PointStamped, GRAB_TOPIC, TARGET_QOS)
        self.target_publisher = self.create_publisher(PointStamped, TARGET_TOPIC, TARGET_QOS)
        # Never spun: its pose and twist subscriptions are only taken from (NewestMessage).
        self.reader = Node(f'{VIEW_NODE_NAME}_reader', context=self.context,
                           namespace=self.get_namespace())
        self.pose_subscription = NewestMessage(self.reader, PoseStamped, POSE_TOPIC, LATEST_QOS)
        self.readings = PanelReadings(self.reader, LATEST_QOS)
        self.robot = RobotView(self.reader, LATEST_QOS)
        # Every grab, this view's or another client's: which link a robot's anchor is on.
        self.create_subscription(PointStamped, GRAB_TOPIC, self._on_grab, TARGET_QOS)
        self.create_subscription(MarkerArray, node_name(MARKERS_TOPIC), self._on_markers,
                                 MONITOR_DEPTH)
        self.create_subscription(DiagnosticArray, DIAGNOSTICS_TOPIC, self._on_diagnostics,
                                 MONITOR_DEPTH)
        self.follower = NodeFollower(self, topic=self.pose_subscription.topic_name,
                                     on_parameters=self._parameters_changed,
                                     discovery_seconds=discovery_seconds, clock=clock)
        self.target_node = self.follower.target_node
        self.calls = ServiceCalls(clock=clock)  # each given up when it goes unanswered
        self.node_services = NodeServices(self, self.target_node,
                                          lambda text: self.scene.show_reply(text), self.calls)
        self.scene = scene_factory(self.parameters)
        self._bind_scene()
        # On the steady clock: the page stays live while a simulated clock stands still.
        steady = Clock(clock_type=ClockType.STEADY_TIME)
        self._timers = [
            self.create_timer(WORK_PERIOD, self._run_work, clock=steady),
            self.create_timer(PANEL_PERIOD, self._update_panel, clock=steady),
            self.create_timer(PRESENCE_PERIOD, self._look_for_node, clock=steady),
        ]
        self._look_for_node()

    # Work from viser's threads: queued with the event's time, run on the executor's.

    def queue(self, work: Callable[[], None]) -> None:
        """Run ``work()`` on the executor's thread within ``WORK_PERIOD`` (thread-safe)."""
        self._work.put(work)

    def _run_work(self) -> None:
        """Offer the newest pose (or joint_states) to the throttle, run the queued work."""
        self.calls.give_up_late()
        raw = self.pose_subscription.take()
        joints = self.robot.take()
        if raw is not None:
            self._on_pose(raw)
        elif joints is not None:
            if self.throttle.offer(joints, self._monotonic()) is not None:
                self._push()
        elif self.throttle.flush(self._monotonic()) is not None:
            self._push()
        while True:
            try:
                work = self._work.get_nowait()
            except queue.Empty:
                break
            try:
                work()
            except Exception as error:  # A gesture or button must never end the view.
                self.get_logger().error(f'{type(error).__name__}: {error}')
        # After the queue: an end's next segment queued meanwhile goes on with its drag. What
        # waited on a release goes too, once the node answered it or the wait ran out.
        self.send(self.gestures.due(self._monotonic()), self._now_ns())

    def _bind_scene(self) -> None:
        """Have the body's gestures and the panel's buttons queue their work."""
        scene = self.scene
        scene.bind_body(self._on_drag, self._on_click)
        scene.on_button(scene.pause, lambda: self.queue(self.toggle_pause))
        scene.on_button(scene.release, lambda: self.queue(self.release))
        for button, service in ((scene.step, STEP_SERVICE), (scene.reset, RESET_SERVICE)):
            scene.on_button(button, lambda service=service: self.queue(
                lambda: self.call(service)))

    def _now_ns(self) -> int:
        return self.get_clock().now().nanoseconds

    async def _on_drag(self, event) -> None:
        """Queue a drag's start, move or end (on viser's thread), with the time it came at."""
        stamp = self._now_ns()
        at = self._monotonic()
        hold = bool(self.scene.hold.value)
        if event.phase == 'start':
            camera = _camera(event.client)
            # A robot: the link pressed, as the page names its scene node.
            link = None
            if self.scene.robot is not None:
                link = self.scene.robot.link_of(getattr(event, 'target', None))
            self.queue(lambda: self._start_drag(event.client_id, event.start_position,
                                                camera, stamp, at, link))
        elif event.phase == 'update':
            self.queue(lambda: self.send(
                self.gestures.move(event.client_id, event.end_position), stamp))
        else:
            self.queue(lambda: self.send(self.gestures.end(
                event.client_id, event.end_position, modifier=event.modifier, hold=hold, at=at),
                stamp))

    def _start_drag(self, client: int, pressed, camera: Optional[Camera], stamp: int,
                    at: float, link: Optional[str] = None) -> None:
        """Send what a press sends: a grab where it landed on the body as drawn, or nothing."""
        now = self.latest_pose()
        shown = self.scene.shown
        if now is None or shown is None:
            return
        if self.robot.active:
            # The pressed link's pose as drawn, and now.
            poses = self.robot.pressed(pressed, link, self.scene.shown_links, now)
            if poses is None:
                return
            shown, now = poses
        actions = self.gestures.start(client, pressed=pressed, camera=camera, shown=shown,
                                      now=now, at=at)
        if any(action.kind == GRAB for action in actions):
            self.scene.show_reply('')  # the answer to an earlier release no longer holds
        self.send(actions, stamp)

    async def _on_click(self, event) -> None:
        """Queue what a click sends: a grab where its ray meets the body, or nothing."""
        stamp = self._now_ns()
        hold = bool(self.scene.hold.value)

        def click() -> None:
            now = self.latest_pose()
            if now is not None and self.robot.active:
                self.send(Gestures.click_at(
                    self.robot.ray_hit(event.ray_origin, event.ray_direction, now),
                    modifier=event.modifier, hold=hold), stamp)
            elif now is not None:
                self.send(Gestures.click(event.ray_origin, event.ray_direction, now=now,
                                         geometry=self.shape.geometry,
                                         modifier=event.modifier, hold=hold), stamp)
        self.queue(click)

    # Inputs to the node.

    def send(self, actions: List[Action], stamp_ns: int) -> None:
        """
        Publish grabs and targets stamped ``stamp_ns``, call ``~/release`` for a release.

        In the order given, after what waits already: what follows a release goes once the
        node answered it (``ReleaseOrder``), at the next work after the answer.
        """
        self.outbox.add((action, stamp_ns) for action in actions)
        self._send_ready()

    def _send_ready(self) -> None:
        """Send what the outbox lets go: grabs and targets published, a release called."""
        while (item := self.outbox.take(self._monotonic())) is not None:
            action, stamp_ns = item
            if action.kind == RELEASE:
                release = self.outbox.sent
                if not self.call(RELEASE_SERVICE,
                                 on_answer=lambda: self.outbox.answered(release)):
                    self.outbox.answered(release)
                continue
            message = point_message(action.point, self.parameters.frame_id, stamp_ns)
            if action.kind == GRAB:
                self.grab_publisher.publish(message)
                self.scene.grabbed()
            else:
                self.target_publisher.publish(message)

    def call(self, service: str, data: Optional[bool] = None, *,
             on_answer: Optional[Callable[[], None]] = None) -> bool:
        """Call one of the node's services, its answer shown on the page (``NodeServices``)."""
        return self.node_services.call(service, data, on_answer=on_answer)

    def release(self) -> None:
        """Let the body go (the panel's Release): a release sent in order, as a gesture's."""
        self.send([Action(RELEASE)], self._now_ns())

    def toggle_pause(self) -> None:
        """Pause the node, or resume it when its diagnostics say it is paused."""
        self.call(PAUSE_SERVICE, not self.readouts.paused)
        self.readouts = self.readouts._replace(paused=not self.readouts.paused)

    # What the node publishes.

    def _on_pose(self, raw: bytes) -> None:
        """Take the newest pose (decoded when used) and offer it to the throttle."""
        self._pose_raw = raw
        self._latest = None
        if self.throttle.offer(raw, self._monotonic()) is not None:
            self._push()

    def latest_pose(self) -> Optional[Pose]:
        """Return the node's latest pose (None before the first), decoded once."""
        if self._latest is None and self._pose_raw is not None:
            try:
                self._latest = _pose(deserialize_message(self._pose_raw, PoseStamped))
            except Exception:  # A malformed pose is passed over.
                self._pose_raw = None
        return self._latest

    def _push(self) -> None:
        """Show the body (a robot's links) and its anchor at the latest pose."""
        pose = self.latest_pose()
        if pose is None:
            return
        if self.robot.active:
            poses = self.robot.link_poses(pose)
            if poses is None:
                return
            self.scene.show_robot(poses, pose,
                                  self.robot.anchor_point(poses, self.parameters.anchor))
        else:
            self.scene.show_pose(pose, world_point(pose, self.parameters.anchor))
        self.pushes += 1

    def _on_grab(self, message: PointStamped) -> None:
        """Tell the robot's view of a grab, this view's or another client's."""
        p = message.point
        self.robot.heard_grab((p.x, p.y, p.z), self.parameters.grab_margin, self.latest_pose())

    def _on_markers(self, array: MarkerArray) -> None:
        """Show the node's target marker, or none once it is deleted."""
        for marker in array.markers:
            if marker.ns == 'target':
                p = marker.pose.position
                self.scene.show_target((p.x, p.y, p.z) if marker.action == Marker.ADD
                                       else None)

    def _on_diagnostics(self, array: DiagnosticArray) -> None:
        """Read what the node's /diagnostics say of it (``Readouts``)."""
        self.readouts = self.readouts.updated(array, self.target_node)

    @property
    def parameters(self) -> ViewParameters:
        """Return the node's parameters the page is drawn with, as known."""
        return self.follower.parameters

    def _parameters_changed(self, parameters: ViewParameters) -> None:
        """Draw the body the node's parameters give: a robot's links, a URDF link or the box."""
        if self.robot.update(parameters) and self.robot.shape.error is not None:
            self.get_logger().warning(self.robot.shape.error)
        if self.robot.active:
            self.scene.apply_parameters(parameters, links=self.robot.shape.links)
            return
        if self.shape.update(parameters) and self.shape.error is not None:
            self.get_logger().warning(self.shape.error)
        self.scene.apply_parameters(parameters, self.shape.geometry)

    def _look_for_node(self) -> None:
        """Look for the node; forget its readouts once it is gone."""
        self.follower.look()
        if self.follower.present is False:
            self.readouts = Readouts()

    def _update_panel(self) -> None:
        """Show the panel's status line and numbers."""
        speed = self.readings.speed()
        readouts = self.readouts
        force = self.readings.force(self.follower.parameters.publish_force)
        self.scene.show_text(
            status=status_text(self.target_node, self.pose_subscription.topic_name,
                               self.follower.present),
            numbers=numbers_text(speed, readouts, force, self.parameters.mode),
            paused=readouts.paused)

    def destroy_node(self) -> None:
        """Stop the timers, then destroy the node."""
        for timer in self._timers:
            timer.cancel()
        self.reader.destroy_node()
        super().destroy_node()
