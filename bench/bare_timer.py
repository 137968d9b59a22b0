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
A bare rclpy timer that publishes one PoseStamped per tick: the floor under the node's cost.

``python -m bench.bare_timer --rate 1000 --executor single|events|events-until|events-spin
[--twist]`` runs
until SIGINT/SIGTERM. Each tick stamps the message with the clock and publishes it on ``pose``
(the node's QoS); no physics; with ``--twist`` also a TwistStamped on ``twist``, as the node
publishes both, and with ``--wrench`` a WrenchStamped on ``force``, as the node does with
``publish_force``. With ``--echo`` each PoseStamped on ``target_pose`` (the node's QoS) publishes
them at once, stamped with the pose's own stamp, and the timer publishes nothing from the first
pose on: the node's device-clocked ticks (``tick_source: target_pose``) without their physics,
the floor of a pose -> force round trip through rclpy. The executors:

- ``single``: SingleThreadedExecutor, ``spin_once(timeout_sec=0.1)`` in a loop;
- ``events``: rclpy.experimental.EventsExecutor, ``spin_once(timeout_sec=0.1)`` in a loop, as
  ``mouse_constraint_node`` spins;
- ``events-until``: the same executor, ``spin_until_future_complete(never_done,
  timeout_sec=0.1)`` in a loop: every event due within the 0.1 s in one call;
- ``events-spin``: the same executor's ``spin()``, which (in the rclpy of the results' machine
  facts) busy-waits and does not return to Python between callbacks, so this variant ends by
  the signals' default action;
- ``events-loop``: the same executor, no rclpy timer: the ticks come from the spin loop as the
  node's do (a ``LoopTimer`` as ``spin_until``'s pace, ``spin_once`` waiting until the next
  tick is due).

The node benchmarks use ``events --twist`` as the floor: a bare rclpy node, the node's executor
and spin loop and the two state topics the node publishes, so that the node's figures divided
by this one's leave what the node itself adds; ``events-loop --twist`` beside it drives its ticks
as the node does.
"""

import argparse
import signal
import sys

from geometry_msgs.msg import PoseStamped, TwistStamped, WrenchStamped
import rclpy
from rclpy.executors import SingleThreadedExecutor
from rclpy.experimental import EventsExecutor
from rclpy.node import Node
from rclpy.qos import HistoryPolicy, QoSProfile, ReliabilityPolicy
from rclpy.signals import SignalHandlerOptions
from rclpy.task import Future

from mouse_constraint_ros.timing.loop_timer import LoopTimer
from mouse_constraint_ros.timing.spin import spin_until, StopRequest
from mouse_constraint_ros.wire.interface import TARGET_POSE_QOS, TARGET_POSE_TOPIC

STATE_QOS = QoSProfile(history=HistoryPolicy.KEEP_LAST, depth=10,
                       reliability=ReliabilityPolicy.RELIABLE)


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[1])
    parser.add_argument('--rate', type=float, default=1000.0)
    parser.add_argument('--executor', choices=('single', 'events', 'events-until', 'events-spin',
                                               'events-loop'),
                        default='events')
    parser.add_argument('--twist', action='store_true',
                        help='also publish a TwistStamped on twist each tick, as the node does')
    parser.add_argument('--wrench', action='store_true',
                        help='also publish a WrenchStamped on force each tick (publish_force)')
    parser.add_argument('--echo', action='store_true',
                        help='publish at once for each pose on target_pose, with its stamp')
    options = parser.parse_args(argv)
    rclpy.init(signal_handler_options=SignalHandlerOptions.NO)
    node = Node('bench_bare_timer')
    publisher = node.create_publisher(PoseStamped, 'pose', STATE_QOS)
    message = PoseStamped()
    message.header.frame_id = 'world'
    twist_publisher = node.create_publisher(TwistStamped, 'twist', STATE_QOS)
    twist = TwistStamped()
    twist.header.frame_id = 'world'
    wrench_publisher = node.create_publisher(WrenchStamped, 'force', STATE_QOS)
    wrench = WrenchStamped()
    wrench.header.frame_id = 'world'
    clock = node.get_clock()
    echoing = []

    def tick() -> None:
        if not echoing:
            publish(*divmod(clock.now().nanoseconds, 1_000_000_000))

    def echo(pose: PoseStamped) -> None:
        echoing.append(True)
        publish(pose.header.stamp.sec, pose.header.stamp.nanosec)

    if options.echo:
        node.create_subscription(PoseStamped, TARGET_POSE_TOPIC, echo, TARGET_POSE_QOS)

    def publish(sec: int, nanosec: int) -> None:
        message.header.stamp.sec, message.header.stamp.nanosec = sec, nanosec
        publisher.publish(message)
        if options.twist:
            twist.header.stamp.sec, twist.header.stamp.nanosec = sec, nanosec
            twist_publisher.publish(twist)
        if options.wrench:
            wrench.header.stamp.sec, wrench.header.stamp.nanosec = sec, nanosec
            wrench_publisher.publish(wrench)

    loop_timer = None
    if options.executor == 'events-loop':
        loop_timer = LoopTimer(round(1e9 / options.rate))
    else:
        node.create_timer(1.0 / options.rate, tick)
    if options.executor == 'single':
        executor = SingleThreadedExecutor(context=node.context)
    else:
        executor = EventsExecutor(context=node.context)
    executor.add_node(node)
    if loop_timer is not None:
        def pace() -> float:
            if loop_timer.take():
                tick()
            return loop_timer.time_until_next_call() * 1e-9

        with StopRequest() as request:
            spin_until(executor, request, pace=pace)
        node.destroy_node()
        rclpy.try_shutdown()
        return 0
    stop = []
    if options.executor == 'events-spin':
        # spin() never returns to Python between callbacks here, so Python-level signal
        # handlers never run: SIGINT and SIGTERM keep their default action and end the process.
        for signum in (signal.SIGINT, signal.SIGTERM):
            signal.signal(signum, signal.SIG_DFL)
        executor.spin()
        return 0
    for signum in (signal.SIGINT, signal.SIGTERM):
        signal.signal(signum, lambda _signum, _frame: stop.append(True))
    never = Future()
    try:
        while not stop and node.context.ok():
            if options.executor == 'events-until':
                executor.spin_until_future_complete(never, timeout_sec=0.1)
            else:
                executor.spin_once(timeout_sec=0.1)
    finally:
        node.destroy_node()
        rclpy.try_shutdown()
    return 0


if __name__ == '__main__':
    sys.exit(main())
