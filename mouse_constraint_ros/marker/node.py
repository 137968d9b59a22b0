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
The ``mouse_marker`` node: the body as an RViz interactive marker, dragged with the Interact tool.

It serves one interactive marker (``updates``) over the three endpoints RViz's
InteractiveMarkers display uses, in the node's namespace: ``mouse_marker/update`` (the marker,
then its poses), ``mouse_marker/feedback`` (what the mouse does to it) and the service
``mouse_marker/get_interactive_markers`` (the marker as it is, for a display that starts or
lost track). The feedback goes to ``MarkerDrag``, whose grabs, targets and releases it sends to
the node, each stamped with the time it came (RViz's feedback stamps are zero or a TF time). It
wires ROS to pure parts like ``mouse_view``, and shares its ``NodeFollower``, ``NewestMessage``
and ``PushThrottle``:

- the body's newest pose is taken every ``WORK_PERIOD`` and offered to the marker's updates (at
  most 30 a second, only when it moved, none during a drag);
- inputs go out at most ``MAX_INPUT_RATE`` a second, grabs, targets and releases counted
  together over every client (``InputPacer``), each in its slot, in order, what a later one
  makes moot dropped (the newest target replaces the one held back): RViz sends one target per
  frame (30 a second), a client gone wrong as many targets, or press and release cycles, as it
  likes; nothing goes after a ``~/release`` until the node answered it (``ReleaseGate``), so
  that the node cannot take the next grab first;
- ``hold_on_release`` (a parameter of this node, false by default) keeps the body held where
  the drag ends instead of calling ``~/release``;
- a drag whose RViz closes or crashes ends as its release would, when a feedback publisher it
  hangs on (``presence``: the dragging RViz's own) has left the graph (looked for every
  ``PRESENCE_PERIOD``): RViz sends nothing while the mouse is held still, so silence alone
  cannot tell.

This is a server of its own, not ``interactive_markers``' Python server: that one is not on
PyPI (RViz's apt packages bring it), drops the feedback of a marker's first second and can
number its updates out of order under a multi-threaded executor; the protocol is three
endpoints and a counter.
"""

import time
from typing import Callable, FrozenSet, List, Optional, Tuple

from geometry_msgs.msg import PointStamped, PoseStamped
from rcl_interfaces.msg import ParameterDescriptor
from rclpy.clock import Clock, ClockType
from rclpy.node import Node
from rclpy.qos import QoSProfile, ReliabilityPolicy
from rclpy.serialization import deserialize_message
from std_srvs.srv import Trigger
from visualization_msgs.msg import InteractiveMarkerFeedback, InteractiveMarkerUpdate
from visualization_msgs.srv import GetInteractiveMarkers

from .drag import MarkerDrag
from .input_pacer import InputPacer
from .presence import departed, Endpoint, watched
from .updates import MARKER_NAME, MarkerUpdates, pose_of
from ..description.body_geometry import BodyGeometry
from ..pointer.body_shape import BodyShape
from ..pointer.geometry import Pose, unit_pose
from ..pointer.gestures import Action, GRAB, RELEASE
from ..pointer.newest_message import NewestMessage
from ..pointer.node_follower import DISCOVERY_SECONDS, NodeFollower
from ..pointer.node_readouts import ViewParameters
from ..pointer.release_order import ReleaseGate
from ..pointer.service_calls import ServiceCalls
from ..wire.interface import (GRAB_TOPIC, MARKER_FEEDBACK_TOPIC, MARKER_NODE_NAME, MARKER_QOS,
                              MARKER_SERVICE, MARKER_UPDATE_TOPIC, NODE_NAME, node_name,
                              POSE_TOPIC, RELEASE_SERVICE, TARGET_QOS, TARGET_TOPIC)
from ..wire.messages import point_message

# Only the newest pose matters: depth 1, best effort (a reliable publisher serves it).
LATEST_QOS = QoSProfile(depth=1, reliability=ReliabilityPolicy.BEST_EFFORT)
# Periods (s): the pose taken and the held updates and targets flushed; the look for the node.
WORK_PERIOD, PRESENCE_PERIOD = 0.01, 0.5
# Inputs (grabs, targets and releases together) a second at most, from all clients.
MAX_INPUT_RATE = 100.0
# The parameter that keeps the body held where a drag ends.
HOLD_PARAMETER = 'hold_on_release'


class MouseMarkerNode(Node):
    """
    The interactive marker of one ``mouse_constraint`` node in this namespace.

    :param clock: seconds of a monotonic clock (the throttles' time).
    :param discovery_seconds: how long it looks for the node before it says there is none.
    :param kwargs: passed to ``rclpy.node.Node``.
    """

    def __init__(self, *, clock: Callable[[], float] = time.monotonic,
                 discovery_seconds: float = DISCOVERY_SECONDS, **kwargs) -> None:
        """Create the server's endpoints, the node's inputs and the timers."""
        super().__init__(MARKER_NODE_NAME, **kwargs)
        self.declare_parameter(HOLD_PARAMETER, False, ParameterDescriptor(
            description='Keep the body held where a drag ends instead of calling ~/release.'))
        self._monotonic = clock
        self.drag = MarkerDrag()
        self.shape = BodyShape()
        self.updates = MarkerUpdates(self.get_fully_qualified_name())
        # The grabs, targets and releases that go to the node (a release has no message).
        self._inputs: InputPacer[Optional[PointStamped]] = InputPacer(MAX_INPUT_RATE)
        # Closed while a release is unanswered: a grab sent after it must not be taken first.
        self.release_gate = ReleaseGate()
        self._latest: Optional[Pose] = None
        self.feedback_taken = 0
        self.grab_publisher = self.create_publisher(PointStamped, GRAB_TOPIC, TARGET_QOS)
        self.target_publisher = self.create_publisher(PointStamped, TARGET_TOPIC, TARGET_QOS)
        self.release_client = self.create_client(Trigger, NODE_NAME + RELEASE_SERVICE[1:])
        self.calls = ServiceCalls(clock=clock)  # each given up when it goes unanswered
        self.update_publisher = self.create_publisher(InteractiveMarkerUpdate,
                                                      MARKER_UPDATE_TOPIC, MARKER_QOS)
        self.feedback_subscription = self.create_subscription(
            InteractiveMarkerFeedback, MARKER_FEEDBACK_TOPIC, self._on_feedback, MARKER_QOS)
        # The feedback publishers the drag hangs on (``presence``), set at its press.
        self._hung_on: FrozenSet[Tuple[int, ...]] = frozenset()
        self.create_service(GetInteractiveMarkers, MARKER_SERVICE, self._on_get_markers)
        # Never spun: its pose subscription is only taken from (NewestMessage).
        self.reader = Node(f'{MARKER_NODE_NAME}_reader', context=self.context,
                           namespace=self.get_namespace())
        self.pose_subscription = NewestMessage(self.reader, PoseStamped, POSE_TOPIC, LATEST_QOS)
        self.follower = NodeFollower(self, topic=self.pose_subscription.topic_name,
                                     on_parameters=self._parameters_changed,
                                     discovery_seconds=discovery_seconds, clock=clock)
        # On the steady clock: the marker stays live while a simulated clock stands still.
        steady = Clock(clock_type=ClockType.STEADY_TIME)
        self._timers = [self.create_timer(period, callback, clock=steady) for period, callback in (
            (WORK_PERIOD, self._work), (PRESENCE_PERIOD, self._look))]
        self.follower.look()

    @property
    def parameters(self) -> ViewParameters:
        """Return the node's parameters the marker is drawn with, as known."""
        return self.follower.parameters

    def latest_pose(self) -> Optional[Pose]:
        """Return the body's latest pose (None before the first)."""
        return self._latest

    def _publish(self, updates: List[InteractiveMarkerUpdate]) -> None:
        for update in updates:
            self.update_publisher.publish(update)

    def _draw(self) -> None:
        """Publish the whole marker (once the pose and the node's parameters are known)."""
        if self._latest is not None and self.follower.parameters_known:
            parameters = self.follower.parameters
            self._publish(self.updates.marker(frame_id=parameters.frame_id,
                                              geometry=self._geometry(parameters),
                                              pose=self._latest))

    def _geometry(self, parameters: ViewParameters) -> BodyGeometry:
        """Return the body's shape of ``parameters``; say once why a URDF is drawn as a box."""
        if self.shape.update(parameters) and self.shape.error is not None:
            self.get_logger().warning(self.shape.error)
        return self.shape.geometry

    def _parameters_changed(self, _parameters: ViewParameters) -> None:
        self._draw()

    def _work(self) -> None:
        now = self._monotonic()
        self.calls.give_up_late()
        raw = self.pose_subscription.take()
        if raw is not None:
            try:
                pose = unit_pose(pose_of(deserialize_message(raw, PoseStamped).pose))
            except Exception:  # A malformed pose is passed over.
                pose = None
            if pose is not None:
                first = self._latest is None
                self._latest = pose
                if first:
                    self._draw()
                else:
                    self._publish(self.updates.pose(pose, now))
        self._publish(self.updates.flush(now))
        self._send_ready(now)

    def _feedback_publishers(self) -> List[Endpoint]:
        return [(node_name(info.node_namespace, info.node_name), tuple(info.endpoint_gid))
                for info in self.get_publishers_info_by_topic(
                    self.feedback_subscription.topic_name)]

    def _look(self) -> None:
        """Look for the node, and end a drag whose client has left the graph."""
        self.follower.look()
        client = self.drag.client
        if client is not None and departed(self._hung_on, self._feedback_publishers()):
            self.get_logger().warning(f'{client} left mid-drag (its feedback publisher is '
                                      'gone): the drag ends')
            self._end_drag(client, self.get_clock().now().nanoseconds)

    def _end_drag(self, client: str, stamp_ns: int) -> None:
        """End ``client``'s drag: release (or hold) the body, and the marker back onto it."""
        dragging = self.drag.dragging
        actions = self.drag.release(client, hold=bool(self.get_parameter(HOLD_PARAMETER).value))
        self._send(actions, stamp_ns, self._monotonic())
        if dragging and not self.drag.dragging:
            self._publish(self.updates.drag_ended(self._latest))

    def _on_get_markers(self, _request, response):
        response.sequence_number = self.updates.sequence
        response.markers = self.updates.current(self.get_clock().now().nanoseconds)
        return response

    def _on_feedback(self, feedback: InteractiveMarkerFeedback) -> None:
        frame_id = self.follower.parameters.frame_id
        if feedback.marker_name != MARKER_NAME or feedback.header.frame_id not in ('', frame_id):
            return
        self.feedback_taken += 1
        stamp, now = self.get_clock().now().nanoseconds, self._monotonic()
        client, pose = feedback.client_id, pose_of(feedback.pose)
        kind = feedback.event_type
        if kind == InteractiveMarkerFeedback.MOUSE_DOWN:
            latest = self._latest
            if latest is None:
                return
            point = feedback.mouse_point
            hit = (point.x, point.y, point.z) if feedback.mouse_point_valid else None
            was, parameters = self.drag.client, self.follower.parameters
            actions = self.drag.press(client, shown=pose, hit=hit, now=latest,
                                      anchor=parameters.anchor,
                                      geometry=self._geometry(parameters),
                                      margin=parameters.grab_margin)
            if was is None and self.drag.client is not None:
                self._hung_on = watched(client, self._feedback_publishers())
            self.updates.dragging = self.drag.dragging
        elif kind == InteractiveMarkerFeedback.POSE_UPDATE:
            actions = self.drag.move(client, pose)
        elif kind == InteractiveMarkerFeedback.MOUSE_UP:
            self._end_drag(client, stamp)
            return
        else:
            return
        self._send(actions, stamp, now)

    def _send(self, actions: List[Action], stamp_ns: int, now: float) -> None:
        """Hand grabs, targets and releases to the pacer (MAX_INPUT_RATE); send what goes."""
        frame_id = self.follower.parameters.frame_id
        for action in actions:
            message = (None if action.kind == RELEASE else
                       point_message(action.point, frame_id, stamp_ns))
            self._inputs.add(action.kind, message)
            self._send_ready(now)

    def _send_ready(self, now: float) -> None:
        """Send the input the pacer lets go at ``now``, unless a release is unanswered."""
        item = self._inputs.flush(now) if self.release_gate.is_open(now) else None
        if item is None:
            return
        kind, message = item
        if kind == RELEASE:
            self._release(now)
        else:
            (self.grab_publisher if kind == GRAB else self.target_publisher).publish(message)

    def _release(self, now: float) -> None:
        if not self.release_client.service_is_ready():
            self.get_logger().warning(f'{self.release_client.srv_name}: no such service (is '
                                      'the node running?): the body stays held')
            return
        release = self.release_gate.released(now)
        # What waits goes at the next work (WORK_PERIOD), not from the future's callback.
        self.calls.call(self.release_client, Trigger.Request(),
                        on_answer=lambda _done: self.release_gate.answered(release))

    def destroy_node(self) -> None:
        """Stop the timers, then destroy the node."""
        for timer in self._timers:
            timer.cancel()
        self.reader.destroy_node()
        super().destroy_node()
