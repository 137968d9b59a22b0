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
The recording itself: a node that takes every message of the recorded topics, and its progress.

``Recorder`` subscribes to ``TOPICS`` with deep RELIABLE queues and hands each message,
serialized as it arrived (``Received``), from the first message on, to its sink (the files,
written as they come: ``RecordingFiles``), and keeps it in ``received`` when asked; the
recorded time starts at the first pose. It also takes the recorded node's ``/parameter_events``
that change a parameter the rows follow (``received.NODE_PARAMETERS``: a ``grab`` makes the
grabbed point the node's anchor) and the service events of its ``~/reset`` and ``~/release``,
in the same stream, so that the rows follow the node's anchor and target from the moment they
changed. ``fetch_start`` reads those parameters at the start from the recorded node's parameter
service, and ``start_request`` asks for them without waiting, while the first pose is waited
for; ``capture`` spins it (``spin.spin_until``) while ``Progress`` draws the progress line.
"""

import math
import sys
import time
from typing import Callable, Dict, List, Optional, TextIO

from rcl_interfaces.msg import ParameterEvent
from rcl_interfaces.srv import GetParameters
from rclpy.executors import Executor
from rclpy.node import Node
from rclpy.qos import HistoryPolicy, qos_profile_parameter_events, QoSProfile, ReliabilityPolicy
from rclpy.serialization import deserialize_message
from service_msgs.msg import ServiceEventInfo

from .mcap_file import offered_qos_yaml
from .received import (BODY_PARAMETERS, COUNTED_TOPICS, header_stamp, MESSAGE_TYPES,
                       NODE_PARAMETERS, parameter_changes, PARAMETER_EVENTS_TOPIC, Received,
                       service_event_topic, SERVICE_EVENTS, TOPICS)
from ..timing.guarded_time_source import guard_time_source
from ..timing.spin import spin_until, SpinEnd, StopRequest
from ..wire.interface import (JOINT_STATES_TOPIC, NODE_NAME, POSE_TOPIC, SERVICE_EVENT_QOS,
                              TWIST_TOPIC)
from ..wire.remote_parameters import fetch_parameters, ParameterRequest

# Deep RELIABLE queues: a burst of caught-up ticks must not overwrite unread messages.
RECORD_QOS = QoSProfile(history=HistoryPolicy.KEEP_LAST, depth=1000,
                        reliability=ReliabilityPolicy.RELIABLE)


class Recorder(Node):
    """
    Subscribes to the recorded topics and keeps every message, serialized, as it arrives.

    :param target_node: the recorded node (resolved in this node's namespace), whose anchor
        changes on ``/parameter_events`` and service events of ``~/reset`` and ``~/release`` are
        kept.
    :param sink: called with each message kept, as it comes (``RecordingFiles.add``).
    :param keep: also keep the messages in ``received`` (a recording read back in-process).
    """

    def __init__(self, *, target_node: str = NODE_NAME,
                 sink: Optional[Callable[[Received], None]] = None, keep: bool = True,
                 **kwargs) -> None:
        """Create the node ``mouse_record`` and its subscriptions."""
        super().__init__('mouse_record', **kwargs)
        self._sink, self._keep = sink, keep
        guard_time_source(self, lambda text: self.get_logger().warning(
            text, throttle_duration_sec=2.0))
        self.target_name = self.resolve_topic_name(target_node)
        self.parameter_changes = 0
        self.received: List[Received] = []
        self.counts = dict.fromkeys(COUNTED_TOPICS, 0)
        self.offered_qos: Dict[str, str] = {}
        # The node's clock is the stamps: the first pose's, and the latest of pose and twist.
        self.first_pose_ns: Optional[int] = None
        self.latest_ns = {POSE_TOPIC: None, TWIST_TOPIC: None}
        # The recording keeps the ticks stamped up to this (ns), once the first pose came.
        self.duration_ns: Optional[int] = None
        # Whether a pose and a twist stamped after the recorded time came (not kept).
        self.beyond = {POSE_TOPIC: False, TWIST_TOPIC: False}
        # time.monotonic() of the latest pose.
        self.pose_seen_at = time.monotonic()
        self.recording = True
        self._clock = self.get_clock()
        # Made before the subscriptions: a participant announces its readers in order, so once
        # a pose came the recorded node has matched this client's reader of answers too, and an
        # answer asked for then is not lost (``start_request``).
        self.parameter_client = self.create_client(GetParameters, f'{target_node}/get_parameters')
        self.subscriptions_by_topic = {
            key: self.create_subscription(message_type, key, self._receiver(key), RECORD_QOS,
                                          raw=True)
            for key, message_type in TOPICS.items()}
        self.subscriptions_by_topic[PARAMETER_EVENTS_TOPIC] = self.create_subscription(
            ParameterEvent, PARAMETER_EVENTS_TOPIC, self._on_parameter_event,
            qos_profile_parameter_events, raw=True)
        for key in SERVICE_EVENTS:
            self.subscriptions_by_topic[key] = self.create_subscription(
                MESSAGE_TYPES[key], service_event_topic(self.target_name, key),
                self._service_receiver(key), SERVICE_EVENT_QOS, raw=True)

    def topic_name(self, key: str) -> str:
        """Return the resolved (namespaced, remapped) name of a recorded topic."""
        return self.subscriptions_by_topic[key].topic_name

    def topic_names(self) -> Dict[str, str]:
        """Return the resolved name of every recorded topic, by key (``MESSAGE_TYPES``)."""
        return {key: self.topic_name(key) for key in self.subscriptions_by_topic}

    def _on_parameter_event(self, data: bytes) -> None:
        """Keep the events of the recorded node that change a parameter the rows follow."""
        if not self.recording:
            return
        event = deserialize_message(data, ParameterEvent)
        if event.node != self.target_name or not parameter_changes(event):
            return
        self.parameter_changes += 1
        self._note_qos(PARAMETER_EVENTS_TOPIC)
        self._keep_message(Received(PARAMETER_EVENTS_TOPIC,
                                    self.get_clock().now().nanoseconds, data))

    def _keep_message(self, message: Received) -> None:
        if self._keep:
            self.received.append(message)
        if self._sink is not None:
            self._sink(message)

    def _note_qos(self, key: str) -> None:
        if key not in self.offered_qos:
            self.offered_qos[key] = offered_qos_yaml(
                [e.qos_profile for e in self.get_publishers_info_by_topic(
                    self.topic_name(key))])

    def _receiver(self, key: str):
        # Serialized messages (raw=True) and no message info: the EventsExecutor of this rclpy
        # (7.1.6) fails on callbacks that take one.
        counts, clock, latest, keep = self.counts, self._clock, self.latest_ns, self._keep_message
        counted, state = key in counts, key in latest
        # A robot's joint_states are the ticks' too: none stamped after the recorded time.
        stamped = state or key == JOINT_STATES_TOPIC

        def receive(data: bytes) -> None:
            if not self.recording:
                return
            if stamped:
                stamp = header_stamp(data)
                if stamp is None:
                    return
                if key == POSE_TOPIC:
                    self.pose_seen_at = time.monotonic()
                    if self.first_pose_ns is None:
                        self.first_pose_ns = stamp
                first = self.first_pose_ns
                if self.duration_ns is not None and first is not None and \
                        stamp > first + self.duration_ns:
                    if state:
                        self.beyond[key] = True
                    return
                if state and (latest[key] is None or stamp > latest[key]):
                    latest[key] = stamp
            if counted:
                counts[key] += 1
            if key not in self.offered_qos:
                self._note_qos(key)
            keep(Received(key, clock.now().nanoseconds, data))
        return receive

    def _service_receiver(self, key: str):
        receive = self._receiver(key)

        def receive_response(data: bytes) -> None:
            # The responses say what the call did; the requests carry nothing more.
            event = deserialize_message(data, MESSAGE_TYPES[key])
            if event.info.event_type == ServiceEventInfo.RESPONSE_SENT:
                receive(data)
        return receive_response

    def complete(self) -> bool:
        """Return whether the recorded time is over: pose and twist came stamped after it."""
        return all(self.beyond.values())

    def elapsed(self) -> float:
        """Return the seconds of stamps recorded since the first pose's, pose and twist both."""
        first, pose, twist = self.first_pose_ns, *self.latest_ns.values()
        if first is None or pose is None or twist is None:
            return 0.0
        return max(0.0, (min(pose, twist) - first) * 1e-9)


def fetch_start(node: Node, executor: Executor, stop: StopRequest, *, target_node: str,
                timeout: float) -> Dict[str, object]:
    """
    Return ``target_node``'s parameters of ``NODE_PARAMETERS`` and ``BODY_PARAMETERS``.

    Only ``anchor`` (in the body frame, m) must be there; without the others a reset's target
    and the grid are not known (``rows.NodeView``, ``missing_ticks``), nor a URDF body's outline
    (``body_outline``).

    :param timeout: seconds to wait for the parameter service, then as long for its answer.
    :raises RuntimeError: saying why they could not be read.
    :raises Interrupted: when ``stop`` is requested meanwhile.
    """
    types = {**NODE_PARAMETERS, **BODY_PARAMETERS}
    return fetch_parameters(node, executor, stop, target_node=target_node, types=types,
                            timeout=timeout, optional=set(types) - {'anchor'})


def start_request(node: Recorder, target_node: str) -> ParameterRequest:
    """
    Return the request of ``fetch_start``'s parameters on the recorder's own client, not yet sent.

    The recorder polls it while it waits for the first pose (``ParameterRequest.poll``), and
    asks again when that pose comes (``ParameterRequest.ask_again``): an answer to a request
    sent before may have gone to a client the node had not matched yet.
    """
    types = {**NODE_PARAMETERS, **BODY_PARAMETERS}
    return ParameterRequest(node.parameter_client, target_node=target_node, types=types,
                            optional=set(types) - {'anchor'})


def progress_bar(elapsed: float, duration: float, counts: Dict[str, int],
                 width: int = 30) -> str:
    """Return the progress line: a bar, the seconds recorded and the messages per topic."""
    share = min(1.0, elapsed / duration)
    filled = round(width * share)
    return (f'recording [{"#" * filled}{"." * (width - filled)}] {elapsed:5.1f}/{duration:g} s  '
            + '  '.join(f'{topic} {count}' for topic, count in counts.items()))


class Progress:
    """Draws the bar in place on a terminal, and a line per tenth of the duration otherwise."""

    def __init__(self, duration: float, stream: TextIO = sys.stderr) -> None:
        """Draw on ``stream``."""
        self._duration, self._stream = duration, stream
        self._terminal = stream.isatty()
        self._drawn_at = -math.inf
        self._tenth = -1

    def update(self, elapsed: float, counts: Dict[str, int], final: bool = False) -> None:
        """Redraw for ``elapsed`` seconds (at most 10 times a second on a terminal)."""
        # Called on every turn of the recording's spin loop: decide before building the line.
        if self._terminal:
            now = time.monotonic()
            if final or now - self._drawn_at >= 0.1:
                line = progress_bar(elapsed, self._duration, counts)
                self._stream.write('\r' + line + ('\n' if final else ''))
                self._stream.flush()
                self._drawn_at = now
        else:
            tenth = int(10.0 * min(1.0, elapsed / self._duration))
            if final or tenth > self._tenth:
                self._stream.write(progress_bar(elapsed, self._duration, counts) + '\n')
                self._stream.flush()
                self._tenth = tenth


def capture(node: Recorder, executor: Executor, stop: StopRequest, *, duration: float,
            idle_timeout: float, progress: Progress,
            each_turn: Callable[[], None] = lambda: None) -> SpinEnd:
    """
    Record ``duration`` seconds of the node's clock (the stamps) from the first pose, or less.

    It ends when pose and twist stamped ``duration`` after the first pose have come (later ones
    are not kept), on a stop, or when no pose came for ``idle_timeout`` seconds (wall time: the
    node paused or gone). Then the node stops keeping messages and the progress line is drawn
    a last time. Timed by the stamps, the recording needs no ``use_sim_time``.

    :param each_turn: called on each turn of the spin (``RecordingFiles.flush_due``).

    :returns: why it ended: ``CONDITION`` (the duration), ``STOPPED``, ``DEADLINE`` (no pose
        for ``idle_timeout``) or ``SHUTDOWN``.
    """
    if node.duration_ns is None:
        node.duration_ns = round(duration * 1e9)

    def done() -> bool:
        each_turn()
        progress.update(node.elapsed(), node.counts)
        return node.complete() or time.monotonic() - node.pose_seen_at > idle_timeout

    end = spin_until(executor, stop, condition=done)
    node.recording = False
    progress.update(duration if node.complete() else node.elapsed(), node.counts, final=True)
    if end is SpinEnd.CONDITION and not node.complete():
        return SpinEnd.DEADLINE
    return end
