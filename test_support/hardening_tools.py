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
Tools for the hardening tests and ``bench/flood.py``.

A target flooder, a pose recorder, and the node as a process.

Run as a script it is one of two helper processes:

- ``flood``: publish targets on ``target`` at a fixed rate (20 000/s by default) for a duration,
  moving around a horizontal circle whose phase follows the system clock, optionally with a
  hostile message (NaN, inf, 1e300, a foreign frame, a point beyond the workspace, absurd
  stamps) every Nth message; print a JSON summary on stdout at the end.
- ``watch``: record ``pose`` for a duration and print a JSON summary (the two-host test runs it
  in the other network namespace).

Run them as ``python -m test_support.hardening_tools flood|watch`` from the repository's root
(``flood_command``, ``watch_command``). Imported, it gives the in-process side:
``PoseRecorder`` and ``NodeProcess`` (the installed ``mouse_constraint_node`` with its own ROS
arguments, its log in a file); ``test_support.flood_run`` makes the measurement both the test
and the benchmark make with them; the process helpers are ``test_support.processes``.
"""

import argparse
import json
import math
import sys
import time
from typing import Dict, List, Optional, Sequence

import numpy as np

from test_support.processes import BIN
from test_support.processes import ChildProcess
from test_support.processes import module_command
from test_support.processes import node_command

MODULE = 'test_support.hardening_tools'
TARGET_EXECUTABLE = BIN / 'mouse_target'
ANCHOR = (0.2, 0.1, 0.05)
NS = 1_000_000_000
# Circle of the flood's targets (centre, radius m, period s).
CENTER = (0.0, 0.0, 1.0)
RADIUS = 0.3
PERIOD = 2.0
# Points of the circle table the flooder picks from (a 0.1 degree step).
CIRCLE_POINTS = 3600


def circle_point(t_ns: int, center: Sequence[float] = CENTER, radius: float = RADIUS,
                 period: float = PERIOD) -> tuple:
    """Return the flood's target at system time ``t_ns``: the phase is the clock's."""
    angle = 2.0 * math.pi * ((t_ns % int(period * NS)) / (period * NS))
    return (center[0] + radius * math.cos(angle), center[1] + radius * math.sin(angle),
            center[2])


def hostile_messages(workspace_radius: float) -> List[tuple]:
    """
    Return the hostile (point, frame_id, stamp) cycle of ``flood``.

    A point of None is the circle's current point, a stamp of None the current time. All are
    ignored by a node with ``workspace_radius`` and frame ``world``, except the circle points
    with absurd stamps (2^31 - 1 s, -2^31 s, 0), which the node takes at receipt like any
    other target: it ignores the stamp.
    """
    return [
        ((math.nan, 0.0, 1.0), 'world', None),
        ((0.0, math.inf, 1.0), 'world', None),
        ((0.0, 0.0, -math.inf), 'world', None),
        ((1e300, -1e300, 1e300), 'world', None),
        ((workspace_radius * 1.5, 0.0, 1.0), 'world', None),
        (None, 'map', None),
        (None, '/world', None),
        (None, 'world', (2 ** 31 - 1, NS - 1)),
        (None, 'world', (-2 ** 31, 0)),
        (None, 'world', (0, 0)),
    ]


def _message(message_type, point: Sequence[float], frame_id: str, stamp: tuple):
    message = message_type()
    message.header.frame_id = frame_id
    message.header.stamp.sec, message.header.stamp.nanosec = stamp
    message.point.x, message.point.y, message.point.z = (float(c) for c in point)
    return message


def _serialized(message_type, point: Sequence[float], frame_id: str, stamp: tuple) -> bytes:
    from rclpy.serialization import serialize_message
    return serialize_message(_message(message_type, point, frame_id, stamp))


def flood_main(argv: Sequence[str]) -> int:
    """Publish the flood (see the module docstring); print its summary as JSON."""
    parser = argparse.ArgumentParser(prog='hardening_tools.py flood')
    parser.add_argument('--rate', type=float, default=20000.0,
                        help='messages per second; 0: as fast as the flooder can publish')
    parser.add_argument('--messages', action='store_true',
                        help='publish message objects, as a plain rclpy publisher does, rather '
                        'than pre-serialized bytes')
    parser.add_argument('--duration', type=float, default=10.0, help='seconds')
    parser.add_argument('--hostile-every', type=int, default=0,
                        help='replace every Nth message by a hostile one (0: none)')
    parser.add_argument('--workspace-radius', type=float, default=100.0)
    parser.add_argument('--constant', nargs=3, type=float, default=None,
                        help='publish this point every time instead of the circle')
    parser.add_argument('--timeout', type=float, default=15.0,
                        help='seconds to wait for the subscriber')
    options = parser.parse_args(argv)

    from geometry_msgs.msg import PointStamped
    import rclpy
    from rclpy.duration import Duration
    from rclpy.executors import SingleThreadedExecutor
    from rclpy.node import Node

    from mouse_constraint_ros.wire.interface import TARGET_QOS

    rclpy.init()
    node = Node('target_flood')
    publisher = node.create_publisher(PointStamped, 'target', TARGET_QOS)
    executor = SingleThreadedExecutor()
    executor.add_node(node)
    deadline = time.monotonic() + options.timeout
    while publisher.get_subscription_count() == 0:
        if time.monotonic() > deadline:
            print(json.dumps({'error': 'no subscriber'}), flush=True)
            return 1
        executor.spin_once(timeout_sec=0.05)
    # Messages are serialized beforehand and published as bytes (unless --messages): rclpy's
    # publish of a message object costs about twice as much, too much for 20 000/s on a small
    # shared machine. The circle is a table of CIRCLE_POINTS points, picked by the clock's
    # phase; a hostile message without a point of its own is the circle's current point in a
    # foreign frame or with an absurd stamp.
    now_stamp = divmod(time.time_ns(), NS)
    points = ([tuple(options.constant)] if options.constant is not None else
              [circle_point(k * PERIOD * NS // CIRCLE_POINTS) for k in range(CIRCLE_POINTS)])
    make = _message if options.messages else _serialized

    def table_of(points: Sequence[Sequence[float]], frame_id: str, stamp: tuple) -> list:
        return [make(PointStamped, point, frame_id, stamp) for point in points]

    def table(frame_id: str, stamp: Optional[tuple]) -> list:
        return table_of(points, frame_id, stamp or now_stamp)

    valid = table('world', None)
    hostile = []  # (serialized message or table, whether the node takes it)
    for point, frame_id, stamp in hostile_messages(options.workspace_radius):
        if point is None:
            hostile.append((table(frame_id, stamp), frame_id == 'world'))
        else:
            hostile.append((table_of([point], frame_id, stamp or now_stamp), False))
    period_ns = int(PERIOD * NS)
    sent = hostile_sent = 0
    last_valid = None
    start_ns = time.time_ns()
    start = time.monotonic()
    end = start + options.duration
    while True:
        now = time.monotonic()
        if now >= end:
            break
        due = int((now - start) * options.rate) if options.rate > 0.0 else sent + 1000
        if sent >= due:
            time.sleep(0.0002)  # not a wait: the stream paced at its rate
            continue
        for _ in range(min(due - sent, 1000)):
            sent += 1
            index = (time.time_ns() % period_ns) * len(points) // period_ns
            messages, taken = valid, True
            if options.hostile_every and sent % options.hostile_every == 0:
                messages, taken = hostile[hostile_sent % len(hostile)]
                hostile_sent += 1
            message = messages[index % len(messages)]
            publisher.publish(message)
            if taken:
                last_valid = points[index]
    end_ns = time.time_ns()
    elapsed = time.monotonic() - start
    # Exit only once the node has the last messages: a RELIABLE writer that exits at once may
    # take its last samples with it, and the node would rightly hold an older target.
    acked = publisher.wait_for_all_acked(Duration(seconds=5.0))
    print(json.dumps({'sent': sent, 'hostile': hostile_sent, 'start_ns': start_ns,
                      'end_ns': end_ns, 'rate': sent / elapsed, 'acked': acked,
                      'last_valid': last_valid}),
          flush=True)
    node.destroy_node()
    rclpy.try_shutdown()
    return 0


def watch_main(argv: Sequence[str]) -> int:
    """Record ``pose`` for a while; print how many came, the last one and the anchor's path."""
    parser = argparse.ArgumentParser(prog='hardening_tools.py watch')
    parser.add_argument('--duration', type=float, default=5.0)
    parser.add_argument('--first-timeout', type=float, default=20.0,
                        help='seconds to wait for the first pose')
    options = parser.parse_args(argv)

    from geometry_msgs.msg import PoseStamped
    import rclpy
    from rclpy.executors import SingleThreadedExecutor
    from rclpy.node import Node
    from rclpy.qos import QoSProfile, ReliabilityPolicy

    rclpy.init()
    node = Node('pose_watch')
    poses: list = []
    node.create_subscription(PoseStamped, 'pose', poses.append,
                             QoSProfile(depth=10000, reliability=ReliabilityPolicy.RELIABLE))
    executor = SingleThreadedExecutor()
    executor.add_node(node)
    deadline = time.monotonic() + options.first_timeout
    while not poses and time.monotonic() < deadline:
        executor.spin_once(timeout_sec=0.05)
    first_ns = time.time_ns()
    end = time.monotonic() + options.duration
    while poses and time.monotonic() < end:
        executor.spin_once(timeout_sec=0.05)
    anchors = [list(anchor_of(p)) for p in poses]
    print(json.dumps({'count': len(poses), 'first_pose_ns': first_ns if poses else None,
                      'anchors': anchors[::10] + anchors[-1:]}), flush=True)
    node.destroy_node()
    rclpy.try_shutdown()
    return 0


def anchor_of(pose, anchor: Sequence[float] = ANCHOR) -> np.ndarray:
    """Return the world position of ``anchor`` (body frame) for a ``PoseStamped``."""
    from scipy.spatial.transform import Rotation
    p, q = pose.pose.position, pose.pose.orientation
    return np.array([p.x, p.y, p.z]) + Rotation.from_quat([q.x, q.y, q.z, q.w]).apply(anchor)


def stamp_ns(message) -> int:
    """Return a message's header stamp in nanoseconds."""
    return message.header.stamp.sec * NS + message.header.stamp.nanosec


class PoseRecorder:
    """
    Record ``pose`` messages with their receipt time, on ``node`` (a probe in the test process).

    ``stamps`` (the header's), ``published`` (the DDS source timestamp: when the node wrote
    it) and ``received`` (when the callback ran here): int nanoseconds. ``positions`` and
    ``orientations``: raw floats as tuples, so that bit-for-bit comparisons see exactly what
    was published.
    """

    def __init__(self, node, topic: str = 'pose', depth: int = 100000) -> None:
        """Subscribe ``node`` to ``topic``, RELIABLE, keeping up to ``depth`` unread messages."""
        from geometry_msgs.msg import PoseStamped
        from rclpy.qos import QoSProfile, ReliabilityPolicy
        self.stamps: List[int] = []
        self.published: List[int] = []
        self.received: List[int] = []
        self.positions: List[tuple] = []
        self.orientations: List[tuple] = []
        self.subscription = node.create_subscription(
            PoseStamped, topic, self._on_pose,
            QoSProfile(depth=depth, reliability=ReliabilityPolicy.RELIABLE))

    def _on_pose(self, message, info) -> None:
        self.received.append(time.time_ns())
        self.published.append(info['source_timestamp'])
        self.stamps.append(stamp_ns(message))
        p, q = message.pose.position, message.pose.orientation
        self.positions.append((p.x, p.y, p.z))
        self.orientations.append((q.x, q.y, q.z, q.w))

    def __len__(self) -> int:
        """Return how many poses came."""
        return len(self.stamps)

    def anchors(self, since: int = 0) -> np.ndarray:
        """Return the world anchor of every pose from index ``since`` on, as an (n, 3) array."""
        from scipy.spatial.transform import Rotation
        positions = np.array(self.positions[since:]).reshape(-1, 3)
        if not len(positions):
            return positions
        return positions + Rotation.from_quat(np.array(self.orientations[since:])).apply(ANCHOR)


class NodeProcess(ChildProcess):
    """The installed ``mouse_constraint_node`` as a child process, its log in a temporary file."""

    def __init__(self, *ros_arguments: str, prefix: Sequence[str] = (),
                 environment: Optional[Dict[str, str]] = None) -> None:
        """Start the node with ``--ros-args ros_arguments``, run under ``prefix`` if given."""
        super().__init__(node_command(*ros_arguments, prefix=prefix), environment=environment)


def flood_command(*arguments: str) -> List[str]:
    """Return the command line of the flooder process."""
    return module_command(MODULE, 'flood', *arguments)


def watch_command(*arguments: str, prefix: Sequence[str] = ()) -> List[str]:
    """Return the command line of the pose watcher process, run under ``prefix`` if given."""
    return module_command(MODULE, 'watch', *arguments, prefix=prefix)


if __name__ == '__main__':
    commands = {'flood': flood_main, 'watch': watch_main}
    if len(sys.argv) < 2 or sys.argv[1] not in commands:
        sys.exit(f'usage: {sys.argv[0]} {{flood,watch}} [options]')
    sys.exit(commands[sys.argv[1]](sys.argv[2:]))
