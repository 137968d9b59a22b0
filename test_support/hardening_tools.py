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
``PoseRecorder``, ``NodeProcess`` (the installed ``mouse_constraint_node`` with its own ROS
arguments, its log in a file) and ``run_flood``, the measurement both the test and the
benchmark make; the process helpers are ``test_support.processes``.
"""

import argparse
import json
import math
import subprocess
import sys
import time
from typing import Dict, List, Optional, Sequence

import numpy as np

from test_support.processes import BIN
from test_support.processes import ChildProcess
from test_support.processes import cpu_seconds
from test_support.processes import finish
from test_support.processes import module_command
from test_support.processes import node_command
from test_support.processes import rss_bytes
from test_support.processes import run_delay_ns

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
    # publish of a message object costs about twice as much, too much for 20 000/s on a shared
    # 2-core machine. The circle is a table of CIRCLE_POINTS points, picked by the clock's
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
            time.sleep(0.0002)
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


def run_flood(ros, seconds: float, rate: float = 20000.0, hostile_every: int = 0,
              node_rate: float = 1000.0, messages: bool = False,
              node_prefix: Sequence[str] = (),
              node_environment: Optional[Dict[str, str]] = None) -> dict:
    """
    Flood a node process with targets from a flooder process; return what was measured.

    ``ros`` is a ``RosHarness`` (the observer, subscribed to pose and twist). The node runs at
    ``node_rate`` without gravity, with some damping, and workspace_radius 100 m; the flooder
    publishes ``rate`` targets/s (0: as fast as it can), pre-serialized or, with ``messages``,
    as message objects. The result: the flooder's summary (``flood``); the node's output rate
    over the flood counted by grid stamp and by DDS source timestamp (when the node wrote the
    message), the ticks missing from the stamps, and how late the node wrote them
    (``late_ms_*``: source timestamp - stamp, which the observer's own delays do not enter);
    its RSS (after start, after the first second of the flood, at the end), CPU share and how
    long its main thread waited for a CPU (``node_run_delay_ms``, over the flood: a machine too
    busy to run it); how far behind the targets the anchor runs (``lag_s``: per flood second,
    the median lag of the anchor's angle on the circle behind the target's phase at the pose
    stamp) and how far it is from the last target after it; after the flood, when the last
    missing tick was due (``recovered_s``, from the flood's end; 0 when none was missing) and
    whether the node warned of the ticks it dropped (``drops_warned``).

    ``node_prefix`` runs the node under a command (``NodeProcess``), ``node_environment`` is its
    environment (None: this one's); ``bench.flood_rate`` runs another tree's node so.
    """
    from geometry_msgs.msg import TwistStamped
    node = NodeProcess('-p', f'rate_hz:={node_rate!r}', '-p', 'gravity:=[0.0, 0.0, 0.0]',
                       '-p', 'linear_damping:=2.0', '-p', 'angular_damping:=2.0',
                       '-p', 'workspace_radius:=100.0', prefix=node_prefix,
                       environment=node_environment)
    flooder = None
    try:
        poses = PoseRecorder(ros.probe)
        twists = ros.collect(TwistStamped, 'twist', depth=100000)
        if not ros.spin_until(lambda: len(poses) > 200 and twists, timeout=20.0):
            raise RuntimeError('no pose and twist from the node:\n' + node.log())
        ros.spin_for(0.5)
        rss_start = rss_bytes(node.pid)
        delay_start = run_delay_ns(node.pid)
        flooder = ChildProcess(
            flood_command('--rate', repr(rate), '--duration', repr(seconds),
                          '--hostile-every', str(hostile_every),
                          *(['--messages'] if messages else [])),
            stdout=subprocess.PIPE)
        samples = []  # (time ns, node rss, node cpu s, flooder cpu s, observer cpu s)

        def sample() -> None:
            try:
                flooder_cpu = cpu_seconds(flooder.pid)
            except (OSError, IndexError):  # It has just exited.
                flooder_cpu = samples[-1][3] if samples else 0.0
            samples.append((time.time_ns(), rss_bytes(node.pid), cpu_seconds(node.pid),
                            flooder_cpu, time.process_time()))

        next_sample = 0.0
        while flooder.alive():
            ros.spin_for(0.05)
            if time.monotonic() >= next_sample:
                sample()
                next_sample = time.monotonic() + 0.25
        sample()
        delay_end = run_delay_ns(node.pid)
        stdout, _ = flooder.process.communicate()
        lines = [line for line in stdout.splitlines() if line.startswith('{')]
        if flooder.process.returncode != 0 or not lines:
            raise RuntimeError(f'flooder failed ({flooder.process.returncode}): {stdout}\n'
                               + flooder.log())
        flood = json.loads(lines[-1])
        # Serving on after the flood: a second of ticks (by stamp, so that neither a late node
        # nor a late observer cuts it short), long enough for the anchor to settle.
        ros.spin_until(lambda: poses.stamps[-1] >= flood['end_ns'] + NS, timeout=10.0)
        alive = node.alive()
    finally:
        exit_code, log = finish(node, flooder)
    start_ns, end_ns = flood['start_ns'], flood['end_ns']
    stamps = np.array(poses.stamps, dtype=np.int64)
    published = np.array(poses.published, dtype=np.int64)
    received = np.array(poses.received, dtype=np.int64)
    span = (end_ns - start_ns) / NS
    in_flood = (stamps >= start_ns) & (stamps < end_ns)
    written = (published >= start_ns) & (published < end_ns)
    # Lag of the anchor behind the target: the anchor's angle on the circle against the
    # target's phase at the pose's stamp.
    anchors = poses.anchors()
    angle = np.arctan2(anchors[:, 1] - CENTER[1], anchors[:, 0] - CENTER[0])
    phase = 2.0 * np.pi * ((stamps % int(PERIOD * NS)) / (PERIOD * NS))
    lag = np.angle(np.exp(1j * (phase - angle))) / (2.0 * np.pi / PERIOD)
    lag_per_second = []
    for k in range(int(span)):
        window = (stamps >= start_ns + k * NS) & (stamps < start_ns + (k + 1) * NS)
        lag_per_second.append(float(np.median(lag[window])) if window.any() else math.nan)
    flood_samples = [s for s in samples if s[0] >= start_ns + NS]

    def cpu_share(column: int) -> float:
        return ((samples[-1][column] - samples[0][column])
                / ((samples[-1][0] - samples[0][0]) / NS))

    last_valid = np.array(flood['last_valid'])
    final_error = float(np.linalg.norm(anchors[-1] - last_valid))
    gaps = np.diff(stamps[in_flood])
    period_ns = NS / node_rate
    # After the flood: the stamp that ends the last gap of more than one tick.
    after = stamps[stamps >= end_ns - period_ns]
    late_gaps = np.flatnonzero(np.diff(after) > 1.5 * period_ns)
    recovered = (after[late_gaps[-1] + 1] - end_ns) / NS if len(late_gaps) else 0.0
    missing = int(np.sum(np.round(gaps / period_ns) - 1)) if len(gaps) else 0
    return {
        'flood': flood,
        'node_rate_hz': node_rate,
        'flood_seconds': span,
        'stamp_rate_hz': int(in_flood.sum()) / span,
        'publish_rate_hz': int(written.sum()) / span,
        'twists': len(twists),
        'missing_ticks': missing,
        'late_ms_p99': float(np.percentile((published - stamps)[in_flood], 99) / 1e6),
        'late_ms_max': float(np.max((published - stamps)[in_flood]) / 1e6),
        'observer_late_ms_p99': float(np.percentile((received - published)[in_flood], 99)
                                      / 1e6),
        'rss_start_mb': rss_start / 2 ** 20,
        'rss_flood_1s_mb': flood_samples[0][1] / 2 ** 20 if flood_samples else math.nan,
        'rss_end_mb': samples[-1][1] / 2 ** 20,
        'rss_max_mb': max(s[1] for s in samples) / 2 ** 20,
        'node_run_delay_ms': (delay_end - delay_start) / 1e6,
        'node_cpu_share': cpu_share(2),
        'flooder_cpu_share': cpu_share(3),
        'observer_cpu_share': cpu_share(4),
        'lag_s': lag_per_second,
        'final_error_m': final_error,
        'all_finite': bool(np.isfinite(np.array(poses.positions)).all()
                           and np.isfinite(np.array(poses.orientations)).all()),
        'served_after_flood_s': (poses.stamps[-1] - end_ns) / NS,
        'recovered_s': float(recovered),
        'drops_warned': 'dropped' in log,
        'node_alive': alive,
        'node_exit_code': exit_code,
        'node_log_tail': log[-2000:],
    }


if __name__ == '__main__':
    commands = {'flood': flood_main, 'watch': watch_main}
    if len(sys.argv) < 2 or sys.argv[1] not in commands:
        sys.exit(f'usage: {sys.argv[0]} {{flood,watch}} [options]')
    sys.exit(commands[sys.argv[1]](sys.argv[2:]))
