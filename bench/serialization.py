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
Serializing the node's messages: rclpy against the precompiled CDR layouts, in one run.

``python -m bench.serialization [--quick] [--domain N] [--json FILE]`` times, per message type
(PoseStamped, TwistStamped, nav_msgs/Odometry, rosgraph_msgs/Clock), interleaved rounds of:

- ``serialize``: filling a reused rclpy message (stamp and fields, as the node fills its pose)
  and ``rclpy.serialization.serialize_message`` of it;
- ``pack``: ``mouse_constraint_ros.wire.cdr``'s ``pack`` of the same values (same bytes);
- ``publish(msg)``: filling the message and ``Publisher.publish(msg)``;
- ``publish(bytes)``: ``Publisher.publish(layout.pack(...))``, which rclpy sends as it is.

and a ``tick`` row: what the node does per tick after its physics step (stamp, fill and publish
a pose and a twist) against packing and publishing both as bytes. The publishers have a reader
in another process on the same domain (this script with ``--subscriber``, its subscriptions
``raw`` so that it deserializes nothing), as a publisher without a matched reader sends nothing.
The publishers use the node's QoS (RELIABLE, KEEP_LAST 100) and publish back to back; the time
is wall time per call in this process (rmw's own threads run beside it).

Ratios come first, each the median over rounds of same-round ratios; then microseconds per
call (medians). ``--domain`` defaults to the bench domain of ``ros_process``.
"""

import argparse
import json
import os
from pathlib import Path
import signal
import subprocess
import sys
import time
from typing import Callable, Dict, List

from bench import ros_process
from bench.common import machine_info, median, paired_ratio, time_interleaved
from geometry_msgs.msg import PoseStamped, TwistStamped
from nav_msgs.msg import Odometry
import rclpy
from rclpy.executors import SingleThreadedExecutor
from rclpy.node import Node
from rclpy.qos import HistoryPolicy, QoSProfile, ReliabilityPolicy
from rclpy.serialization import serialize_message
from rclpy.signals import SignalHandlerOptions
from rosgraph_msgs.msg import Clock

from mouse_constraint_ros.physics import BodyState
from mouse_constraint_ros.wire.cdr.clock import ClockLayout
from mouse_constraint_ros.wire.cdr.geometry import PoseStampedLayout, TwistStampedLayout
from mouse_constraint_ros.wire.cdr.odometry import OdometryLayout
from mouse_constraint_ros.wire.messages import fill_pose, fill_twist, set_stamp

NAMESPACE = 'bench_serialization'
TOPICS = {'pose': PoseStamped, 'twist': TwistStamped, 'odom': Odometry, 'clock': Clock}
STATE_QOS = QoSProfile(history=HistoryPolicy.KEEP_LAST, depth=100,
                       reliability=ReliabilityPolicy.RELIABLE)
FRAME = 'world'
STATE = BodyState(position=(0.1234, -0.5678, 0.9012),
                  orientation=(0.1825741858, 0.3651483717, 0.5477225575, 0.7302967433),
                  linear_velocity=(1.5, -2.25, 0.125), angular_velocity=(-0.75, 3.0, 0.0625))
START_NS = 1_750_000_000_123_456_789


def subscriber() -> int:
    """Subscribe (raw) to every topic of the bench until SIGINT or SIGTERM."""
    rclpy.init(signal_handler_options=SignalHandlerOptions.NO)
    node = Node('bench_serialization_reader', namespace=NAMESPACE)
    counts = dict.fromkeys(TOPICS, 0)

    def counter(name: str) -> Callable[[bytes], None]:
        def count(_data: bytes) -> None:
            counts[name] += 1
        return count

    for name, message_type in TOPICS.items():
        node.create_subscription(message_type, name, counter(name), STATE_QOS, raw=True)
    stop: List[bool] = []
    for signum in (signal.SIGINT, signal.SIGTERM):
        signal.signal(signum, lambda _signum, _frame: stop.append(True))
    executor = SingleThreadedExecutor(context=node.context)
    executor.add_node(node)
    print('ready', flush=True)
    while not stop and node.context.ok():
        executor.spin_once(timeout_sec=0.1)
    print(json.dumps(counts), flush=True)
    executor.shutdown()
    node.destroy_node()
    rclpy.try_shutdown()
    return 0


def loops(publishers: Dict[str, object]) -> Dict[str, Dict[str, Callable[[int], None]]]:
    """Return, per row, the loops of the row's columns: each ``loop(n)`` makes n calls."""
    state = STATE
    position, orientation = state.position, state.orientation
    linear, angular = state.linear_velocity, state.angular_velocity
    pose, twist, odom, clock = PoseStamped(), TwistStamped(), Odometry(), Clock()
    pose.header.frame_id = twist.header.frame_id = odom.header.frame_id = FRAME
    odom.child_frame_id = 'body'
    pose_layout, twist_layout = PoseStampedLayout(FRAME), TwistStampedLayout(FRAME)
    odom_layout, clock_layout = OdometryLayout(FRAME, 'body'), ClockLayout()
    for layout in (pose_layout, twist_layout, odom_layout, clock_layout):
        assert layout.precompiled, f'{type(layout).__name__} falls back to rclpy here'

    def fill_odom(stamp: int) -> None:
        set_stamp(odom.header.stamp, stamp)
        p, q = odom.pose.pose.position, odom.pose.pose.orientation
        p.x, p.y, p.z = position
        q.x, q.y, q.z, q.w = orientation
        v, w = odom.twist.twist.linear, odom.twist.twist.angular
        v.x, v.y, v.z = linear
        w.x, w.y, w.z = angular

    def filler(message, fill) -> Callable[[int], None]:
        def fill_message(stamp: int) -> None:
            set_stamp(message.header.stamp, stamp)
            fill(message, state)
        return fill_message

    rows = {
        'PoseStamped': ('pose', pose, filler(pose, fill_pose),
                        lambda stamp: pose_layout.pack(stamp, position, orientation)),
        'TwistStamped': ('twist', twist, filler(twist, fill_twist),
                         lambda stamp: twist_layout.pack(stamp, linear, angular)),
        'Odometry': ('odom', odom, fill_odom,
                     lambda stamp: odom_layout.pack(stamp, position, orientation, linear,
                                                    angular)),
        'Clock': ('clock', clock, lambda stamp: set_stamp(clock.clock, stamp),
                  clock_layout.pack),
    }
    result = {}
    for row, (topic, message, fill, pack) in rows.items():
        publish = publishers[topic].publish

        def serialize_loop(n, fill=fill, message=message):
            for i in range(n):
                fill(START_NS + i)
                serialize_message(message)

        def pack_loop(n, pack=pack):
            for i in range(n):
                pack(START_NS + i)

        def publish_message_loop(n, fill=fill, message=message, publish=publish):
            for i in range(n):
                fill(START_NS + i)
                publish(message)

        def publish_bytes_loop(n, pack=pack, publish=publish):
            for i in range(n):
                publish(pack(START_NS + i))

        result[row] = {'serialize': serialize_loop, 'pack': pack_loop,
                       'publish_message': publish_message_loop,
                       'publish_bytes': publish_bytes_loop}

    publish_pose, publish_twist = publishers['pose'].publish, publishers['twist'].publish

    def tick_messages(n):
        """Do the node's tick after the step: stamp, fill and publish the pose and the twist."""
        for i in range(n):
            stamp = START_NS + i
            set_stamp(pose.header.stamp, stamp)
            set_stamp(twist.header.stamp, stamp)
            fill_pose(pose, state)
            fill_twist(twist, state)
            publish_pose(pose)
            publish_twist(twist)

    def tick_bytes(n):
        for i in range(n):
            stamp = START_NS + i
            publish_pose(pose_layout.pack(stamp, state.position, state.orientation))
            publish_twist(twist_layout.pack(stamp, state.linear_velocity,
                                            state.angular_velocity))

    result['tick (pose + twist)'] = {'publish_message': tick_messages,
                                     'publish_bytes': tick_bytes}
    return result


def wait_for_reader(node: Node, executor, publishers: Dict[str, object],
                    timeout: float = 30.0) -> None:
    deadline = time.monotonic() + timeout
    while any(p.get_subscription_count() == 0 for p in publishers.values()):
        if time.monotonic() > deadline:
            raise RuntimeError('the reader process did not match every publisher')
        executor.spin_once(timeout_sec=0.05)


def run(quick: bool, domain: int) -> dict:
    """Start the reader, time every row interleaved, return the table's rows and the facts."""
    ros_process.DOMAIN_ID = domain
    os.environ.update(ros_process.environment())
    repeats, seconds = (3, 0.05) if quick else (9, 0.3)
    reader = subprocess.Popen(ros_process.bench_command('serialization', '--subscriber'),
                              cwd=ros_process.ROOT,
                              env=ros_process.environment(), stdout=subprocess.PIPE,
                              stderr=subprocess.PIPE, text=True)
    rclpy.init(signal_handler_options=SignalHandlerOptions.NO)
    try:
        if reader.stdout.readline().strip() != 'ready':
            raise RuntimeError('reader failed: ' + reader.stderr.read()[-2000:])
        node = Node('bench_serialization_writer', namespace=NAMESPACE)
        publishers = {name: node.create_publisher(message_type, name, STATE_QOS)
                      for name, message_type in TOPICS.items()}
        executor = SingleThreadedExecutor(context=node.context)
        executor.add_node(node)
        wait_for_reader(node, executor, publishers)
        timed = {row: time_interleaved(columns, repeats, seconds)
                 for row, columns in loops(publishers).items()}
        node.destroy_node()
    finally:
        rclpy.try_shutdown()
        reader.send_signal(signal.SIGINT)
        try:
            reader_out, reader_log = reader.communicate(timeout=10.0)
        except subprocess.TimeoutExpired:
            reader.kill()
            reader_out, reader_log = reader.communicate()
    rows = []
    for row, samples in timed.items():
        entry = {'message': row}
        if 'serialize' in samples:
            entry['serialize_over_pack'] = paired_ratio(samples['serialize'], samples['pack'])
        entry['publish_ratio'] = paired_ratio(samples['publish_message'],
                                              samples['publish_bytes'])
        for column, values in samples.items():
            entry[column + '_us'] = median(values)
        entry['saved_us'] = entry['publish_message_us'] - entry['publish_bytes_us']
        rows.append(entry)
    try:
        received = json.loads(reader_out.strip().splitlines()[-1])
    except (IndexError, ValueError):
        received = f'unknown (reader exit {reader.returncode}: {reader_log.strip()[-300:]})'
    return {'rows': rows, 'repeats': repeats, 'seconds_per_repeat': seconds, 'domain': domain,
            'reader_received': received, 'machine': machine_info()}


def table(result: dict) -> str:
    """Return the rows as a markdown table, ratios first."""
    columns = [('message', 'message', ''),
               ('serialize_over_pack', 'serialize / pack', '.1f'),
               ('publish_ratio', 'publish(msg) / publish(bytes)', '.2f'),
               ('serialize_us', 'serialize us', '.2f'), ('pack_us', 'pack us', '.2f'),
               ('publish_message_us', 'publish(msg) us', '.2f'),
               ('publish_bytes_us', 'publish(bytes) us', '.2f'),
               ('saved_us', 'saved us', '.2f')]
    lines = ['| ' + ' | '.join(header for _, header, _ in columns) + ' |',
             '| --- |' + ' ---: |' * (len(columns) - 1)]
    for row in result['rows']:
        cells = []
        for key, _, spec in columns:
            value = row.get(key)
            cells.append('-' if value is None else format(value, spec) if spec else str(value))
        lines.append('| ' + ' | '.join(cells) + ' |')
    machine = result['machine']
    lines += ['', f'{result["repeats"]} interleaved rounds of ~{result["seconds_per_repeat"]:g} s'
              f' per column; domain {result["domain"]}; load at start '
              + ', '.join(f'{x:.2f}' for x in machine['load_average_at_start'])
              + f'; {machine["cpu"]}, {machine["cores"]} cores; Python {machine["python"]}; '
              f'reader received {result["reader_received"]}']
    return '\n'.join(lines)


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[1])
    parser.add_argument('--quick', action='store_true', help='a smoke run, not results')
    parser.add_argument('--domain', type=int, default=ros_process.DOMAIN_ID,
                        help='ROS_DOMAIN_ID of the writer and the reader')
    parser.add_argument('--json', type=Path, help='also write the numbers to this file')
    parser.add_argument('--subscriber', action='store_true', help=argparse.SUPPRESS)
    options = parser.parse_args(argv)
    if options.subscriber:
        return subscriber()
    result = run(options.quick, options.domain)
    print(table(result))
    if options.json is not None:
        options.json.write_text(json.dumps(result, indent=2) + '\n')
    return 0


if __name__ == '__main__':
    sys.exit(main())
