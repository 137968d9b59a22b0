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
wrench stamped with the end, sent by a timer at the end rather than at the node's
``wrench_timeout``; ``--duration inf`` pushes until Ctrl-C. Time is this command's clock: with
``--ros-args -p use_sim_time:=true`` the duration and the rate follow ``/clock``, so a push
lasts D simulated seconds whatever the node's ``real_time_factor``. Before pushing it reads the
node's ``frame_id``, ``max_wrench_force``, ``max_wrench_torque`` and ``wrench_timeout``
(``--node``, default ``mouse_constraint`` in this command's namespace) and refuses, with the
reason and exit status 1, a wrench the node would ignore (another frame, non-finite, over a
bound) or cut short (fewer than two wrenches per ``wrench_timeout``); without an answer it
checks against the defaults and says so. It pushes once ``--subscribers`` subscribers (default
1) have matched: 2 for the node and a ``mouse_record`` that must see the push (a subscriber that
matches later never gets what was sent before); fewer within ``--timeout`` is exit status 1
too. Once the push is sent, the zero wrench is sent on every way out: the end, Ctrl-C or
SIGTERM (exit 0), an error. Before the push, a signal exits 128 + the signal, nothing sent.
"""

import argparse
import math
import sys
import time
from typing import List, Optional

from geometry_msgs.msg import WrenchStamped
from rcl_interfaces.msg import ParameterType
from rclpy.duration import Duration
from rclpy.executors import ExternalShutdownException, SingleThreadedExecutor
from rclpy.node import Node
from rclpy.utilities import remove_ros_args

from .command_node import command_node, SHUTDOWN_STATUS
from .help_text import plain_text
from ..inputs.wrench_gate import WrenchGate
from ..node.parameters import DEFAULTS
from ..timing.guarded_time_source import guard_time_source
from ..timing.spin import Interrupted, spin_until, SpinEnd, StopRequest, wait_until
from ..wire.interface import NODE_NAME, WRENCH_QOS, WRENCH_TOPIC
from ..wire.messages import set_stamp, wrench_message
from ..wire.remote_parameters import fetch_parameters

# The publishing rates that run (Hz): a period from 1 ms to 1000 s.
MIN_RATE = 1e-3
MAX_RATE = 1e3
# The longest finite push (s): its end, in nanoseconds, fits the timer's int64.
MAX_DURATION = 1e9
# The node's parameters a push is checked against, and their types.
NODE_PARAMETERS = {'frame_id': ParameterType.PARAMETER_STRING,
                   'max_wrench_force': ParameterType.PARAMETER_DOUBLE,
                   'max_wrench_torque': ParameterType.PARAMETER_DOUBLE,
                   'wrench_timeout': ParameterType.PARAMETER_DOUBLE}


def _number(name: str, low: float, high: float, infinite: bool = False):
    """Return an argparse type: a float in [low, high], or inf when ``infinite``."""
    def parse(text: str) -> float:
        value = float(text)
        if not (low <= value <= high or (infinite and value == math.inf)):
            raise argparse.ArgumentTypeError(
                f'{name} must be in [{low:g}, {high:g}]' + (' or inf' if infinite else '')
                + f', got {text}')
        return value
    return parse


def build_parser() -> argparse.ArgumentParser:
    """Return the command's argument parser; every option's help names its default."""
    parser = argparse.ArgumentParser(
        prog='mouse_wrench', description=plain_text(__doc__.split('\n\n')[0]),
        epilog='example: mouse_wrench --force 0 0 30 --duration 1.5')
    parser.add_argument('--force', nargs=3, type=float, default=[0.0, 0.0, 0.0],
                        metavar=('FX', 'FY', 'FZ'), help='force through the COM (N, default 0)')
    parser.add_argument('--torque', nargs=3, type=float, default=[0.0, 0.0, 0.0],
                        metavar=('TX', 'TY', 'TZ'), help='torque (N m, default 0)')
    parser.add_argument('--duration', type=_number('--duration', 0.0, MAX_DURATION, True),
                        default=1.0, help="how long to push (s of this command's clock; inf: "
                                          'until Ctrl-C; default 1.0)')
    parser.add_argument('--rate', type=_number('--rate', MIN_RATE, MAX_RATE), default=20.0,
                        help='publishing rate (Hz, default 20.0)')
    parser.add_argument('--frame', default='',
                        help="frame_id of the wrench (default: empty, the node's frame)")
    parser.add_argument('--node', default=NODE_NAME,
                        help='the node whose wrench parameters the push must fit '
                             '(default: %(default)s, in this namespace)')
    parser.add_argument('--timeout', type=_number('--timeout', 1e-3, 1e6), default=10.0,
                        help='seconds to wait for the subscribers and for the parameters '
                             '(default: %(default)g)')
    parser.add_argument('--subscribers', type=_count('--subscribers'), default=1, metavar='N',
                        help='push once N subscribers have matched, e.g. 2 for the node and a '
                             'mouse_record that must see the push (default: %(default)s)')
    return parser


def _count(name: str):
    """Return an argparse type: a whole number >= 1."""
    def parse(text: str) -> int:
        try:
            value = int(text)
        except ValueError:
            value = 0
        if value < 1:
            raise argparse.ArgumentTypeError(f'{name} must be a whole number >= 1, got {text}')
        return value
    return parse


def push_refusal(gate: WrenchGate, wrench_timeout: float, options: argparse.Namespace) -> \
        Optional[str]:
    """
    Return why the node would ignore the push or cut it short, or None when it takes it.

    The node drops a wrench ``wrench_timeout`` after the last one (0 = never): a push longer
    than half of it needs a wrench at least every half of it, so that one late message does not
    end it.
    """
    refusal = gate.refusal(options.frame, options.force, options.torque)
    if refusal is not None:
        return f'wrench refused: {refusal.reason}'
    period = 1.0 / options.rate
    if wrench_timeout > 0.0 and options.duration > 0.5 * wrench_timeout \
            and period > 0.5 * wrench_timeout:
        return (f'--rate {options.rate:g} Hz sends a wrench every {period:g} s; the node drops '
                f'a wrench wrench_timeout {wrench_timeout:g} s after the last one: give --rate '
                f'above {2.0 / wrench_timeout:g} Hz')
    return None


def _stamped(message: WrenchStamped, nanoseconds: int) -> WrenchStamped:
    set_stamp(message.header.stamp, nanoseconds)
    return message


def main(args: Optional[List[str]] = None) -> int:
    """Publish the wrench for ``--duration``, then a zero one; return the exit status."""
    argv = sys.argv if args is None else ['mouse_wrench'] + list(args)
    options = build_parser().parse_args(remove_ros_args(argv)[1:])
    # Non-finite values are refused by every node; the bounds and the frame are the node's.
    unbounded = WrenchGate(options.frame or 'world', math.inf, math.inf)
    refusal = push_refusal(unbounded, 0.0, options)
    if refusal is not None:
        print(f'mouse_wrench: {refusal}', file=sys.stderr)
        return 1
    push = Push(options)
    try:
        with command_node('mouse_wrench', argv) as (node, executor), StopRequest() as stop:
            guard_time_source(node, lambda text: node.get_logger().warning(
                text, throttle_duration_sec=2.0))
            try:
                return push.run(node, executor, stop)
            except Interrupted as interrupted:
                return 128 + interrupted.signal
            finally:
                push.end(node)
    except ExternalShutdownException:
        return SHUTDOWN_STATUS


class Push:
    """One push: the wrench from its start, the zero wrench at its end or on any way out."""

    def __init__(self, options: argparse.Namespace) -> None:
        """Push as ``options`` say."""
        self.options = options
        self.publisher = None
        self.started_ns: Optional[int] = None
        self.ended_ns: Optional[int] = None

    def run(self, node: Node, executor: SingleThreadedExecutor, stop: StopRequest) -> int:
        """
        Wait for the node, check the push against it, push; return the exit status.

        :raises Interrupted: on a signal before the push.
        """
        options = self.options
        logger = node.get_logger()
        self.publisher = publisher = node.create_publisher(WrenchStamped, WRENCH_TOPIC,
                                                           WRENCH_QOS)
        wanted = options.subscribers
        if not wait_until(executor, stop,
                          lambda: publisher.get_subscription_count() >= wanted,
                          deadline=time.monotonic() + options.timeout):
            matched = publisher.get_subscription_count()
            logger.error(f'{f"{matched} of {wanted} subscribers" if matched else "no subscriber"}'
                         f' on {publisher.topic_name} within {options.timeout:g} s')
            return 1
        try:
            values = fetch_parameters(node, executor, stop, target_node=options.node,
                                      types=NODE_PARAMETERS, timeout=options.timeout)
        except RuntimeError as error:
            logger.warning(f'cannot check the wrench against {options.node}: {error} (is '
                           '--node right?); checked against the defaults only')
            values = {**DEFAULTS, 'frame_id': options.frame or 'world'}
        gate = WrenchGate(values['frame_id'], values['max_wrench_force'],
                          values['max_wrench_torque'])
        refusal = push_refusal(gate, values['wrench_timeout'], options)
        if refusal is not None:
            logger.error(f'{options.node} would ignore or cut short the push: {refusal}; '
                         'nothing published')
            return 1
        clock = node.get_clock()
        # With use_sim_time the clock reads 0 until a /clock comes.
        wait_until(executor, stop, lambda: clock.now().nanoseconds != 0, deadline=math.inf)
        wrench = wrench_message(options.force, options.torque, options.frame)

        def repeat() -> None:
            publisher.publish(_stamped(wrench, clock.now().nanoseconds))

        def finish() -> None:
            self.end(node)

        node.create_timer(1.0 / options.rate, repeat)
        if math.isfinite(options.duration):
            node.create_timer(options.duration, finish)
        self.started_ns = clock.now().nanoseconds
        publisher.publish(_stamped(wrench, self.started_ns))
        what = (f'force {tuple(options.force)} N, torque {tuple(options.torque)} N m on '
                f'{publisher.topic_name}')
        if not math.isfinite(options.duration):
            logger.info(f'pushing with {what} until Ctrl-C')
        end = spin_until(executor, stop, condition=lambda: self.ended_ns is not None)
        if end is SpinEnd.SHUTDOWN:
            return 1
        self.end(node)
        pushed = (self.ended_ns - self.started_ns) * 1e-9
        print(f'pushed with {what} for {pushed:g} s', flush=True)
        return 0

    def end(self, node: Node) -> None:
        """Send the zero wrench once, if the push started, stamped with the push's end."""
        if self.started_ns is None or self.ended_ns is not None:
            return
        options = self.options
        if math.isfinite(options.duration):
            end_ns = self.started_ns + round(options.duration * 1e9)
        else:
            end_ns = node.get_clock().now().nanoseconds
        end_ns = min(end_ns, node.get_clock().now().nanoseconds)
        self.ended_ns = end_ns
        if not node.context.ok():
            return
        self.publisher.publish(_stamped(wrench_message((0.0,) * 3, (0.0,) * 3, options.frame),
                                        end_ns))
        # The zero wrench must arrive: otherwise the push lasts until wrench_timeout.
        self.publisher.wait_for_all_acked(Duration(seconds=1.0))


if __name__ == '__main__':
    sys.exit(main())
