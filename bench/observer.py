#!/usr/bin/env python3
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
The observer process of the node benchmarks: it watches a node from outside, over DDS.

Three modes, each writing an ``.npz`` file for the bench module to analyse afterwards:

- ``rate``: subscribe to ``pose`` and ``twist`` (raw: the serialized bytes, nothing
  deserialized, so that the observer keeps up at 5 kHz); after the first message and a
  warm-up, record for a window the receive time (CLOCK_REALTIME, the clock the node stamps
  with) and the header stamp of every message. Prints ``start <ns>`` and ``end <ns>`` on
  stdout at the window's edges, so that the caller can read the node's /proc counters at the
  same moments.
- ``latency``: publish targets (QoS of ``mouse_target``) at random intervals and record every
  ``pose`` and ``twist`` (raw bytes with receive times) and every target with its publish time.
  Which pose first reflects which target is found afterwards (``bench.latency``).
- ``exercise``: drive every path of the node for a while (``bench.memory``;
  ``bench.observer_exercise``).

The executor is the EventsExecutor spun with ``spin_once`` (the node's own loop). Each mode
prints ``ready`` once the node's publishers are matched.
"""

import argparse
import contextlib
import random
import struct
import sys
import time
from typing import Iterator, Tuple

from bench.observer_io import RECORD_QOS, say, spin_for, TARGET_QOS
from diagnostic_msgs.msg import DiagnosticArray
from geometry_msgs.msg import PointStamped, PoseStamped, TwistStamped, WrenchStamped
import numpy as np
import rclpy
from rclpy.experimental import EventsExecutor
from rclpy.node import Node
from rclpy.qos import HistoryPolicy, QoSProfile, ReliabilityPolicy
from rclpy.serialization import deserialize_message
from sensor_msgs.msg import JointState

from test_support.ros_harness import spin_until

# CDR: a 4-byte encapsulation header, then std_msgs/Header's stamp (int32 sec, uint32 nanosec).
STAMP = struct.Struct('<iI')


def stamp_of(raw: bytes) -> int:
    """Return the header stamp (ns) of a serialized stamped message (little-endian CDR)."""
    sec, nanosec = STAMP.unpack_from(raw, 4)
    return sec * 1_000_000_000 + nanosec


# The message type of a topic ``--also`` names; any other is a TwistStamped.
ALSO_TYPES = {'force': WrenchStamped, 'joint_states': JointState}


def observe_rate(node: Node, executor, options) -> dict:
    """Record (receive time, stamp) of every pose over the window; return the arrays."""
    received = []
    record = received.append
    qos = RECORD_QOS if not options.best_effort else QoSProfile(
        history=HistoryPolicy.KEEP_LAST, depth=RECORD_QOS.depth,
        reliability=ReliabilityPolicy.BEST_EFFORT)
    subscription = node.create_subscription(
        PoseStamped, options.topic, lambda raw: record((time.time_ns(), raw)), qos, raw=True)
    # The other state topic is read too (and counted): a publisher without a reader sends
    # nothing, and the node's cost is that of publishing both to a reader.
    others = []
    also = [node.create_subscription(ALSO_TYPES.get(topic, TwistStamped), topic, others.append,
                                     qos, raw=True)
            for topic in options.also]
    if not spin_until(executor, lambda: all(s.get_publisher_count() > 0
                                            for s in [subscription, *also]), 30.0):
        raise SystemExit(f'no publisher on {options.topic} and {options.also}')
    say('ready')
    # A publisher that matched but never publishes still gets its window, with nothing in it.
    if spin_until(executor, lambda: received, options.first_timeout):
        first = deserialize_message(received[0][1], PoseStamped)
        check = first.header.stamp.sec * 1_000_000_000 + first.header.stamp.nanosec
        if stamp_of(received[0][1]) != check:
            raise SystemExit('the raw stamp parser disagrees with deserialize_message')
    spin_for(executor, options.warmup)
    received.clear()
    others.clear()
    say(f'start {time.time_ns()}')
    spin_for(executor, options.seconds)
    end = time.time_ns()
    say(f'end {end}')
    window = list(received)
    return {
        'recv_ns': np.array([t for t, _ in window], dtype=np.int64),
        'stamp_ns': np.array([stamp_of(raw) for _, raw in window], dtype=np.int64),
        'end_ns': np.int64(end),
        'also_received': np.int64(len(others)),
    }


def observe_latency(node: Node, executor, options) -> dict:
    """
    Publish targets at random intervals, recording them and every pose and twist.

    With ``--force`` every force too, and the targets go out as poses on ``target_pose``, as
    a haptic device's driver sends them.
    """
    poses, twists, forces, inputs = [], [], [], {}
    node.create_subscription(PoseStamped, 'pose', lambda raw: poses.append(
        (time.time_ns(), raw)), RECORD_QOS, raw=True)
    node.create_subscription(TwistStamped, 'twist', lambda raw: twists.append(
        (time.time_ns(), raw)), RECORD_QOS, raw=True)
    if options.force:
        node.create_subscription(WrenchStamped, 'force', lambda raw: forces.append(
            (time.time_ns(), raw)), RECORD_QOS, raw=True)
        publisher = node.create_publisher(PoseStamped, 'target_pose', TARGET_QOS)
        node.create_subscription(DiagnosticArray, '/diagnostics',
                                 lambda array: inputs.update(_inputs_values(array)), 10)
        message = PoseStamped()
        message.pose.orientation.w = 1.0
        point = message.pose.position
    else:
        publisher = node.create_publisher(PointStamped, 'target', TARGET_QOS)
        message = PointStamped()
        point = message.point
    if not spin_until(executor, lambda: publisher.get_subscription_count() > 0 and poses
                      and twists and (forces or not options.force), 30.0):
        raise SystemExit('the node did not show up')
    say('ready')
    spin_for(executor, options.warmup)
    generator = random.Random(options.seed)
    center = np.array(options.center)
    targets, published, stamps = [], [], []
    message.header.frame_id = options.frame
    previous = center
    next_time = time.monotonic() + options.gap_min
    while len(targets) < options.trials:
        left = next_time - time.monotonic()
        if left > 0.0:
            executor.spin_once(timeout_sec=min(left, 0.05))
            continue
        while True:  # A new point at least min_jump away from the last one.
            target = center + np.array([generator.uniform(-options.spread, options.spread)
                                        for _ in range(3)])
            if np.linalg.norm(target - previous) >= options.min_jump:
                break
        previous = target
        point.x, point.y, point.z = (float(c) for c in target)
        now = time.time_ns()
        # A device at its rate stamps its k-th pose k periods after its first, however late
        # the publish call comes; else the stamp is the publish time.
        stamp = (stamps[0] + round(len(stamps) * options.gap_min * 1e9)
                 if options.nominal_stamps and stamps else now)
        message.header.stamp.sec, message.header.stamp.nanosec = divmod(stamp, 1_000_000_000)
        publisher.publish(message)
        published.append(now)
        stamps.append(stamp)
        targets.append(target)
        # On a schedule, as a device's loop keeps its period (from now if a gap behind).
        gap = generator.uniform(options.gap_min, options.gap_max)
        next_time = max(next_time, time.monotonic() - options.gap_max) + gap
    # The last target's answer, and with --force a report of the node's inputs after it.
    spin_for(executor, max(options.gap_max, 0.1))
    if options.force:
        inputs.clear()
        spin_until(executor, lambda: inputs, options.inputs_wait)
    say(f'end {time.time_ns()}')

    def stacked(records):
        return (np.array([t for t, _ in records], dtype=np.int64),
                np.array([np.frombuffer(raw, dtype=np.uint8) for _, raw in records]))

    pose_recv, pose_raw = stacked(poses)
    twist_recv, twist_raw = stacked(twists)
    recorded = {
        'target_pub_ns': np.array(published, dtype=np.int64),
        'target_stamp_ns': np.array(stamps, dtype=np.int64),
        'targets': np.array(targets),
        'pose_recv_ns': pose_recv, 'pose_raw': pose_raw,
        'twist_recv_ns': twist_recv, 'twist_raw': twist_raw,
    }
    if options.force:
        recorded['force_recv_ns'], recorded['force_raw'] = stacked(forces)
        # The node's own count (its inputs status, -1 without one): poses that ran a tick, lost.
        recorded['device_ticks'] = np.int64(_leading_int(inputs.get('device ticks (early, late)')))
        recorded['device_lost'] = np.int64(_leading_int(inputs.get('device poses lost')))
    return recorded


def _inputs_values(array: DiagnosticArray) -> dict:
    """Return the values of the inputs status in ``array`` (none: empty)."""
    for status in array.status:
        if status.name.endswith(': inputs'):
            return {value.key: value.value for value in status.values}
    return {}


def _leading_int(text) -> int:
    """Return the integer a status value starts with ('1000 (3, 2)': 1000), else -1."""
    word = (text or '').split(' ')[0]
    return int(word) if word.isdigit() else -1


@contextlib.contextmanager
def observer_node() -> Iterator[Tuple[Node, EventsExecutor]]:
    """Yield the observer's node on its executor; destroy it and shut rclpy down after."""
    rclpy.init()
    node = Node('bench_observer')
    executor = EventsExecutor(context=node.context)
    executor.add_node(node)
    try:
        yield node, executor
    finally:
        node.destroy_node()
        rclpy.try_shutdown()


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[1])
    parser.add_argument('mode', choices=('rate', 'latency', 'exercise'))
    parser.add_argument('--out', required=True, help='the .npz file to write')
    parser.add_argument('--topic', default='pose', help='rate: the topic to watch')
    parser.add_argument('--also', nargs='*', default=['twist'],
                        help='rate: TwistStamped topics also read (counted, not recorded)')
    parser.add_argument('--best-effort', action='store_true',
                        help='rate: subscribe BEST_EFFORT (default RELIABLE)')
    parser.add_argument('--seconds', type=float, default=10.0,
                        help='rate: the window; exercise: how long (s)')
    parser.add_argument('--first-timeout', type=float, default=10.0,
                        help='rate: how long to wait for the first message (s)')
    parser.add_argument('--warmup', type=float, default=1.0,
                        help='seconds after the first message before recording')
    parser.add_argument('--trials', type=int, default=300, help='latency: targets to publish')
    parser.add_argument('--gap-min', type=float, default=0.02,
                        help='latency: least time between targets (s)')
    parser.add_argument('--gap-max', type=float, default=0.04,
                        help='latency: most time between targets (s)')
    parser.add_argument('--center', type=float, nargs=3, default=[0.2, 0.1, 1.05],
                        help='latency, exercise: targets are drawn around this point (m)')
    parser.add_argument('--target-rate', type=float, default=500.0,
                        help='exercise: targets per second')
    parser.add_argument('--bad-every', type=int, default=50,
                        help='exercise: every n-th target is a bad one')
    parser.add_argument('--radius', type=float, default=0.1, help='exercise: circle radius (m)')
    parser.add_argument('--period', type=float, default=2.0, help='exercise: circle period (s)')
    parser.add_argument('--spread', type=float, default=0.01,
                        help='latency: half-width of the cube targets are drawn from (m)')
    parser.add_argument('--min-jump', type=float, default=0.005,
                        help='latency: least distance between successive targets (m)')
    parser.add_argument('--frame', default='world')
    parser.add_argument('--seed', type=int, default=1)
    parser.add_argument('--nominal-stamps', action='store_true',
                        help='latency: stamp the k-th target k gap-min after the first, as a '
                             'device at its rate does, not with its publish time')
    parser.add_argument('--inputs-wait', type=float, default=3.0,
                        help="latency --force: how long (s) to wait at the end for the node's "
                             'inputs status')
    parser.add_argument('--force', action='store_true',
                        help='latency: record the force too; targets as poses on target_pose')
    options = parser.parse_args(argv)
    if options.mode == 'exercise':
        from bench.observer_exercise import observe_exercise
        observe = observe_exercise
    else:
        observe = {'rate': observe_rate, 'latency': observe_latency}[options.mode]
    with observer_node() as (node, executor):
        np.savez(options.out, **observe(node, executor, options))
    return 0


if __name__ == '__main__':
    sys.exit(main())
