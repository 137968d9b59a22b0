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
The ``mouse_wrench`` command: push the body with a wrench on the relative topic ``wrench``.

``mouse_wrench --force FX FY FZ [--torque TX TY TZ] --duration D`` publishes the wrench (force
through the COM in N, torque in N m, world frame) at ``--rate`` for ``D`` seconds, then one zero
wrench so that the push ends at once rather than at the node's ``wrench_timeout``. The rate
must beat that timeout (default 0.5 s). Time is this command's clock: with
``--ros-args -p use_sim_time:=true`` the duration and the rate follow ``/clock``, so a push
lasts D simulated seconds whatever the node's ``real_time_factor``. A wrench the node would
ignore (non-finite, or over its default bounds of 1000 N and 100 N m) is refused here with exit
status 1, and so is having no subscriber within 10 s. Ctrl-C or SIGTERM during a push ends it
with the zero wrench (exit 0); before the push, it exits 128 + the signal having sent nothing.
"""

import argparse
import sys
import time
from typing import List, Optional

from geometry_msgs.msg import WrenchStamped
import rclpy
from rclpy.duration import Duration
from rclpy.executors import ExternalShutdownException, SingleThreadedExecutor
from rclpy.node import Node
from rclpy.signals import SignalHandlerOptions
from rclpy.utilities import remove_ros_args

from .help_text import plain_text
from ..inputs.wrench_gate import WrenchGate
from ..node.parameters import DEFAULTS
from ..timing.spin import spin_until, SpinEnd, StopRequest
from ..wire.interface import WRENCH_QOS, WRENCH_TOPIC
from ..wire.messages import wrench_message

# How long to wait for the node's subscription before giving up (s, wall time).
SUBSCRIBER_TIMEOUT = 10.0


def build_parser() -> argparse.ArgumentParser:
    """Return the command's argument parser; every option's help names its default."""
    parser = argparse.ArgumentParser(
        prog='mouse_wrench', description=plain_text(__doc__.split('\n\n')[0]),
        epilog='example: mouse_wrench --force 0 0 30 --duration 1.5')
    parser.add_argument('--force', nargs=3, type=float, default=[0.0, 0.0, 0.0],
                        metavar=('FX', 'FY', 'FZ'), help='force through the COM (N, default 0)')
    parser.add_argument('--torque', nargs=3, type=float, default=[0.0, 0.0, 0.0],
                        metavar=('TX', 'TY', 'TZ'), help='torque (N m, default 0)')
    parser.add_argument('--duration', type=float, default=1.0,
                        help="how long to push (s of this command's clock, default 1.0)")
    parser.add_argument('--rate', type=float, default=20.0,
                        help='publishing rate (Hz, default 20.0)')
    parser.add_argument('--frame', default='',
                        help="frame_id of the wrench (default: empty, the node's frame)")
    return parser


def main(args: Optional[List[str]] = None) -> int:
    """Publish the wrench for ``--duration``, then a zero one; return the exit status."""
    argv = sys.argv if args is None else ['mouse_wrench'] + list(args)
    options = build_parser().parse_args(remove_ros_args(argv)[1:])
    if not (options.duration >= 0.0 and options.rate > 0.0):
        print('mouse_wrench: --duration must be >= 0 and --rate > 0', file=sys.stderr)
        return 1
    gate = WrenchGate(options.frame or 'world', DEFAULTS['max_wrench_force'],
                      DEFAULTS['max_wrench_torque'])
    refusal = gate.refusal('', options.force, options.torque)
    if refusal is not None:
        print(f'mouse_wrench: wrench refused: {refusal.reason}', file=sys.stderr)
        return 1
    rclpy.init(args=argv, signal_handler_options=SignalHandlerOptions.NO)
    node = None
    try:
        with StopRequest() as stop:
            node = Node('mouse_wrench')
            publisher = node.create_publisher(WrenchStamped, WRENCH_TOPIC, WRENCH_QOS)
            executor = SingleThreadedExecutor(context=node.context)
            executor.add_node(node)
            push = wrench_message(options.force, options.torque, options.frame)
            clock = node.get_clock()
            node.create_timer(1.0 / options.rate, lambda: publisher.publish(push))
            matched = spin_until(
                executor, stop, condition=lambda: publisher.get_subscription_count() > 0,
                deadline=time.monotonic() + SUBSCRIBER_TIMEOUT)
            if matched is SpinEnd.DEADLINE:
                print(f'mouse_wrench: no subscriber on {publisher.topic_name} within '
                      f'{SUBSCRIBER_TIMEOUT:g} s', file=sys.stderr)
                return 1
            # With use_sim_time the clock reads 0 until a /clock comes.
            spin_until(executor, stop, condition=lambda: clock.now().nanoseconds != 0)
            if stop:
                return 128 + stop.signal  # Interrupted before the push: nothing was sent.
            publisher.publish(push)
            end = clock.now().nanoseconds + int(options.duration * 1e9)
            spin_until(executor, stop, condition=lambda: clock.now().nanoseconds >= end)
            publisher.publish(wrench_message((0.0,) * 3, (0.0,) * 3, options.frame))
            print(f'pushed with force {tuple(options.force)} N, torque '
                  f'{tuple(options.torque)} N m for {options.duration:g} s', flush=True)
            # The zero wrench must arrive: otherwise the push lasts until wrench_timeout.
            publisher.wait_for_all_acked(Duration(seconds=1.0))
    except ExternalShutdownException:
        pass
    finally:
        if node is not None:
            node.destroy_node()
        rclpy.try_shutdown()
    return 0


if __name__ == '__main__':
    sys.exit(main())
