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
The recording itself: a node that keeps every message of the recorded topics, and its progress.

``Recorder`` subscribes to ``TOPICS`` with deep RELIABLE queues and keeps each message serialized,
as it arrived (``Received``), from the first message on; the recorded time starts at the first
pose. It also keeps the recorded node's ``/parameter_events`` that change its ``anchor`` (a
``grab`` makes the grabbed point the node's anchor), in the same stream, so that the rows follow
the anchor from the moment it changed. ``fetch_anchor`` reads the body-frame anchor at the start
from the recorded node's parameter service, ``wait_for_first_pose`` and ``capture`` spin it
(``spin.spin_until``) while ``Progress`` draws the progress line.
"""

import math
import sys
import time
from typing import Dict, List, Optional, TextIO

from rcl_interfaces.msg import ParameterEvent, ParameterType
from rcl_interfaces.srv import GetParameters
from rclpy.executors import Executor
from rclpy.node import Node
from rclpy.qos import HistoryPolicy, qos_profile_parameter_events, QoSProfile, ReliabilityPolicy
from rclpy.serialization import deserialize_message

from .mcap_file import offered_qos_yaml
from .received import anchor_change, PARAMETER_EVENTS_TOPIC, Received, TOPICS
from ..physics.algebra import Vector3
from ..timing.spin import spin_until, SpinEnd, StopRequest, wait_until
from ..wire.interface import NODE_NAME, POSE_TOPIC

# Deep RELIABLE queues: a burst of caught-up ticks must not overwrite unread messages.
RECORD_QOS = QoSProfile(history=HistoryPolicy.KEEP_LAST, depth=1000,
                        reliability=ReliabilityPolicy.RELIABLE)


class Recorder(Node):
    """
    Subscribes to the recorded topics and keeps every message, serialized, as it arrives.

    :param target_node: the recorded node (resolved in this node's namespace), whose anchor
        changes on ``/parameter_events`` are kept.
    """

    def __init__(self, *, target_node: str = NODE_NAME, **kwargs) -> None:
        """Create the node ``mouse_record`` and its subscriptions."""
        super().__init__('mouse_record', **kwargs)
        self.target_name = self.resolve_topic_name(target_node)
        self.anchor_changes = 0
        self.received: List[Received] = []
        self.counts = dict.fromkeys(TOPICS, 0)
        self.offered_qos: Dict[str, str] = {}
        self.first_pose_ns: Optional[int] = None
        self.recording = True
        self.subscriptions_by_topic = {
            key: self.create_subscription(message_type, key, self._receiver(key), RECORD_QOS,
                                          raw=True)
            for key, message_type in TOPICS.items()}
        self.subscriptions_by_topic[PARAMETER_EVENTS_TOPIC] = self.create_subscription(
            ParameterEvent, PARAMETER_EVENTS_TOPIC, self._on_parameter_event,
            qos_profile_parameter_events, raw=True)

    def topic_name(self, key: str) -> str:
        """Return the resolved (namespaced, remapped) name of a recorded topic."""
        return self.subscriptions_by_topic[key].topic_name

    def topic_names(self) -> Dict[str, str]:
        """Return the resolved name of every recorded topic, by key (``MESSAGE_TYPES``)."""
        return {key: self.topic_name(key) for key in self.subscriptions_by_topic}

    def _on_parameter_event(self, data: bytes) -> None:
        """Keep the events of the recorded node that change its anchor."""
        if not self.recording:
            return
        event = deserialize_message(data, ParameterEvent)
        if event.node != self.target_name or anchor_change(event) is None:
            return
        self.received.append(Received(PARAMETER_EVENTS_TOPIC, self.get_clock().now().nanoseconds,
                                      data))
        self.anchor_changes += 1
        self._note_qos(PARAMETER_EVENTS_TOPIC)

    def _note_qos(self, key: str) -> None:
        if key not in self.offered_qos:
            self.offered_qos[key] = offered_qos_yaml(
                [e.qos_profile for e in self.get_publishers_info_by_topic(
                    self.topic_name(key))])

    def _receiver(self, key: str):
        # Serialized messages (raw=True) and no message info: the EventsExecutor of this rclpy
        # (7.1.6) fails on callbacks that take one.
        def receive(data: bytes) -> None:
            if not self.recording:
                return
            now = self.get_clock().now().nanoseconds
            self.received.append(Received(key, now, data))
            self.counts[key] += 1
            # With use_sim_time the clock reads 0 until /clock arrives: start once it runs.
            if key == POSE_TOPIC and self.first_pose_ns is None and now > 0:
                self.first_pose_ns = now
            self._note_qos(key)
        return receive

    def elapsed(self) -> float:
        """Return the seconds recorded since the first pose (0 before it)."""
        if self.first_pose_ns is None:
            return 0.0
        return max(0.0, (self.get_clock().now().nanoseconds - self.first_pose_ns) * 1e-9)


def fetch_anchor(node: Node, executor: Executor, stop: StopRequest, *, target_node: str,
                 timeout: float) -> Vector3:
    """
    Return ``target_node``'s ``anchor`` parameter (body frame, m).

    :param timeout: seconds to wait for the parameter service, then as long for its answer.
    :raises RuntimeError: saying why it could not be read.
    :raises Interrupted: when ``stop`` is requested meanwhile.
    """
    client = node.create_client(GetParameters, f'{target_node}/get_parameters')
    try:
        if not wait_until(executor, stop, client.service_is_ready,
                          deadline=time.monotonic() + timeout):
            raise RuntimeError(f'no parameter service {client.srv_name} after {timeout:g} s')
        future = client.call_async(GetParameters.Request(names=['anchor']))
        if not wait_until(executor, stop, future.done, deadline=time.monotonic() + timeout):
            raise RuntimeError(f'{client.srv_name} did not answer in {timeout:g} s')
        values = future.result().values
        if len(values) != 1 or values[0].type != ParameterType.PARAMETER_DOUBLE_ARRAY \
                or len(values[0].double_array_value) != 3:
            raise RuntimeError(f'{target_node} has no anchor parameter of 3 numbers')
        return tuple(float(v) for v in values[0].double_array_value)
    finally:
        node.destroy_client(client)


def wait_for_first_pose(node: Recorder, executor: Executor, stop: StopRequest, *,
                        timeout: float) -> None:
    """
    Spin until the first pose has come, which starts the recorded time.

    :raises RuntimeError: saying so after ``timeout`` seconds.
    :raises Interrupted: when ``stop`` is requested first.
    """
    if not wait_until(executor, stop, lambda: node.first_pose_ns is not None,
                      deadline=time.monotonic() + timeout):
        raise RuntimeError(f'no pose on {node.topic_name(POSE_TOPIC)} after {timeout:g} s')


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
        line = progress_bar(elapsed, self._duration, counts)
        if self._terminal:
            now = time.monotonic()
            if final or now - self._drawn_at >= 0.1:
                self._stream.write('\r' + line + ('\n' if final else ''))
                self._stream.flush()
                self._drawn_at = now
        else:
            tenth = int(10.0 * min(1.0, elapsed / self._duration))
            if final or tenth > self._tenth:
                self._stream.write(line + '\n')
                self._stream.flush()
                self._tenth = tenth


def capture(node: Recorder, executor: Executor, stop: StopRequest, *, duration: float,
            progress: Progress) -> SpinEnd:
    """
    Record until ``duration`` seconds of the node's clock since the first pose, or a stop.

    Then the node stops keeping messages and the progress line is drawn a last time.

    :returns: why it ended: ``CONDITION`` (the duration), ``STOPPED`` or ``SHUTDOWN``.
    """
    def done() -> bool:
        progress.update(node.elapsed(), node.counts)
        return node.elapsed() >= duration

    end = spin_until(executor, stop, condition=done)
    node.recording = False
    progress.update(min(node.elapsed(), duration), node.counts, final=True)
    return end
