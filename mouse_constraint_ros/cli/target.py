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
The ``mouse_target`` command: publish mouse targets on the relative topic ``target``.

``mouse_target X Y Z`` publishes one target and exits once a subscriber has acknowledged it;
``mouse_target --circle`` moves the target around a circle until Ctrl-C (or ``--duration``);
``mouse_target --grab X Y Z`` publishes one grab on ``grab`` instead: the node makes that point of
the body the anchor. Before publishing it waits for ``--subscribers`` subscribers (default 1),
reads the node's ``frame_id`` and ``workspace_radius`` parameters (``--node``, default
``mouse_constraint`` in this command's namespace) and refuses, with the reason and exit status
1, a target (or grab) the node would ignore: another frame, or beyond the workspace (for
``--circle``, any point of the circle). A grab is also checked against the body: its latest
``pose`` and the node's ``box_size`` and ``grab_margin``, with the node's own test (``grab``
module), so a grab off the body is refused too. When the parameters or a pose do not come
within ``--timeout`` it says so and publishes unchecked, since the subscriber need not be
``mouse_constraint``. Ctrl-C or SIGTERM stops it at once, also while waiting.
ROS arguments work as for any node: ``--ros-args -r __ns:=/robot -r target:=/clicked_point``.
"""

import argparse
import math
import sys
import time
from typing import List, Optional

from geometry_msgs.msg import PointStamped
import rclpy
from rclpy.duration import Duration
from rclpy.executors import ExternalShutdownException, SingleThreadedExecutor
from rclpy.node import Node
from rclpy.signals import SignalHandlerOptions
from rclpy.utilities import remove_ros_args

from .help_text import plain_text
from .node_checks import fetch_gate, grab_refusal
from ..timing.spin import Interrupted, POLL_PERIOD, spin_until, SpinEnd, StopRequest, wait_until
from ..wire.interface import GRAB_TOPIC, NODE_NAME, TARGET_QOS, TARGET_TOPIC
from ..wire.messages import point_message

# The frame of the targets when the node's frame_id cannot be read.
FALLBACK_FRAME = 'world'


def build_parser() -> argparse.ArgumentParser:
    """Return the command's argument parser; every option's help names its default."""
    parser = argparse.ArgumentParser(
        prog='mouse_target', description=plain_text(__doc__.split('\n\n')[0]),
        epilog='examples: mouse_target 0.5 0 1 | mouse_target --circle --center 0 0 1 '
               '--radius 0.3 --period 2 | mouse_target --grab -0.2 0 1 | add --ros-args -r '
               'target:=/clicked_point to remap')
    parser.add_argument('point', nargs='*', type=float, metavar='X Y Z',
                        help='one target (m), published once (default: none, give --circle)')
    parser.add_argument('--grab', action='store_true',
                        help='publish X Y Z once on grab instead of target: a point on the body '
                             'becomes its anchor (default: off)')
    parser.add_argument('--frame', default=None,
                        help="frame_id of the targets (default: the node's frame_id parameter, "
                             f'{FALLBACK_FRAME} if it cannot be read)')
    parser.add_argument('--node', default=NODE_NAME,
                        help='the node whose frame_id and workspace_radius the targets must fit '
                             '(default: %(default)s, in this namespace)')
    parser.add_argument('--timeout', type=float, default=10.0,
                        help='seconds to wait for the subscribers, the parameters (and for a '
                             'grab the pose) and the acknowledgement (default: %(default)g)')
    parser.add_argument('--subscribers', type=int, default=1, metavar='N',
                        help='publish once N subscribers have matched, e.g. 2 for the node and '
                             'a mouse_record that must see every target (default: %(default)s)')
    circle = parser.add_argument_group('moving target')
    circle.add_argument('--circle', action='store_true',
                        help='move the target around a horizontal circle until Ctrl-C '
                             '(default: off)')
    circle.add_argument('--center', nargs=3, type=float, default=[0.0, 0.0, 1.0],
                        metavar=('X', 'Y', 'Z'), help='circle centre (m, default: 0 0 1)')
    circle.add_argument('--radius', type=float, default=0.3,
                        help='circle radius (m, default: %(default)g)')
    circle.add_argument('--period', type=float, default=2.0,
                        help='seconds per turn; negative turns clockwise (default: %(default)g)')
    circle.add_argument('--rate', type=float, default=50.0,
                        help='targets per second (default: %(default)g)')
    circle.add_argument('--duration', type=float, default=math.inf,
                        help='stop after this many seconds (default: until Ctrl-C)')
    return parser


def parse_arguments(argv: List[str]) -> argparse.Namespace:
    """Return the command's options from ``argv`` (ROS arguments already removed)."""
    parser = build_parser()
    options = parser.parse_args(argv)
    if options.circle == bool(options.point):
        parser.error('give either X Y Z or --circle')
    if options.grab and options.circle:
        parser.error('--grab takes X Y Z, not --circle')
    if options.point and len(options.point) != 3:
        parser.error(f'a target needs 3 coordinates, got {len(options.point)}')
    numbers = [*options.point, *options.center, options.radius, options.period, options.rate]
    if not all(math.isfinite(v) for v in numbers):
        parser.error('coordinates, radius, period and rate must be finite')
    if options.circle and (options.radius <= 0.0 or options.period == 0.0 or options.rate <= 0.0):
        parser.error('--radius and --rate must be > 0 and --period non-zero')
    if not options.timeout > 0.0:
        parser.error('--timeout must be > 0')
    if options.subscribers < 1:
        parser.error('--subscribers must be >= 1')
    return options


def circle_point(center: List[float], radius: float, period: float, t: float) -> List[float]:
    """Return the point of the horizontal circle at time ``t`` (s), starting at +x."""
    angle = 2.0 * math.pi * t / period
    return [center[0] + radius * math.cos(angle), center[1] + radius * math.sin(angle),
            center[2]]


class TargetPublisher(Node):
    """
    A node with one publisher, QoS-compatible with ``mouse_constraint``'s subscriptions.

    :param topic: ``target`` (default) or ``grab``.
    """

    def __init__(self, topic: str = TARGET_TOPIC, **kwargs) -> None:
        """Create the node ``mouse_target`` and its publisher on ``topic``."""
        super().__init__('mouse_target', **kwargs)
        self.publisher = self.create_publisher(PointStamped, topic, TARGET_QOS)

    def publish_point(self, point: List[float], frame_id: str) -> None:
        """Publish ``point`` in ``frame_id``, stamped now."""
        self.publisher.publish(
            point_message(point, frame_id, self.get_clock().now().nanoseconds))

    def wait_for_subscribers(self, executor, count: int, deadline: float,
                             stop: StopRequest) -> bool:
        """
        Spin until ``count`` subscribers have matched; return False at ``deadline`` (monotonic).

        :raises Interrupted: on Ctrl-C or SIGTERM.
        """
        return wait_until(executor, stop,
                          lambda: self.publisher.get_subscription_count() >= count,
                          deadline=deadline)

    def wait_for_ack(self, executor, deadline: float, stop: StopRequest) -> bool:
        """
        Wait until every subscriber has acknowledged what was published, or ``deadline``.

        Waits in slices of ``POLL_PERIOD``, spinning ``executor`` between them: Python runs
        signal handlers between calls, so one long ``wait_for_all_acked`` would hold Ctrl-C
        back until it returned.

        :raises Interrupted: on Ctrl-C or SIGTERM.
        """
        return wait_until(
            executor, stop,
            lambda: self.publisher.wait_for_all_acked(Duration(seconds=POLL_PERIOD)),
            deadline=deadline)


def main(args: Optional[List[str]] = None) -> int:
    """
    Publish one target or a moving one.

    :returns: 0 on success; 1 when nobody listened or the node would refuse the target;
        128 + the signal number when SIGINT or SIGTERM came before anything was published.
    """
    argv = sys.argv if args is None else args
    options = parse_arguments(remove_ros_args(argv)[1:])
    rclpy.init(args=argv, signal_handler_options=SignalHandlerOptions.NO)
    node = TargetPublisher(GRAB_TOPIC if options.grab else TARGET_TOPIC)
    what = 'grab' if options.grab else 'target'
    logger = node.get_logger()
    executor = SingleThreadedExecutor(context=node.context)
    executor.add_node(node)
    topic = node.publisher.topic_name
    deadline = time.monotonic() + options.timeout
    try:
        with StopRequest() as stop:
            try:
                wanted = options.subscribers
                logger.info(f'waiting up to {options.timeout:g} s for {wanted} '
                            f'subscriber{"s" if wanted > 1 else ""} on {topic}')
                if not node.wait_for_subscribers(executor, wanted, deadline, stop):
                    matched = node.publisher.get_subscription_count()
                    logger.error(
                        f'{f"{matched} of {wanted} subscribers" if matched else "no subscriber"}'
                        f' on {topic} after {options.timeout:g} s: is mouse_constraint running '
                        'with the same ROS_DOMAIN_ID, namespace and remappings?')
                    return 1
                frame = options.frame
                try:
                    gate = fetch_gate(node, executor, options.node, deadline, stop)
                except RuntimeError as error:
                    logger.warning(f'cannot check the {what} against {options.node}: {error} '
                                   f'within {options.timeout:g} s (is --node right?); '
                                   'publishing it unchecked')
                    gate = None
                if frame is None:
                    frame = FALLBACK_FRAME if gate is None else gate.frame_id
                if gate is not None:
                    refusal = (gate.circle_refusal(frame, options.center, options.radius)
                               if options.circle else gate.refusal(frame, options.point))
                    if refusal is not None:
                        logger.error(f'{options.node} would ignore {what} {refusal.reason}; '
                                     'nothing published')
                        return 1
                if gate is not None and options.grab:
                    try:
                        off = grab_refusal(node, executor, options.node, options.point,
                                           deadline, stop)
                    except RuntimeError as error:
                        logger.warning(f'cannot check the grab against the body: {error} '
                                       f'within {options.timeout:g} s; publishing it unchecked')
                        off = None
                    except ValueError as error:  # a shape this machine cannot read
                        logger.warning(f'cannot check the grab against the body here: {error};'
                                       ' publishing it unchecked')
                        off = None
                    if off is not None:
                        logger.error(f'{options.node} would ignore grab {off}; nothing '
                                     'published')
                        return 1
                if not options.circle:
                    node.publish_point(options.point, frame)
                    if not node.wait_for_ack(executor, deadline, stop):
                        logger.error(f'{what} on {topic} was not acknowledged in '
                                     f'{options.timeout:g} s')
                        return 1
                    logger.info(f'{what} {tuple(options.point)} in {frame!r} received on '
                                f'{topic}')
                    return 0
            except Interrupted as interrupted:
                return 128 + interrupted.signal
            start = time.monotonic()
            logger.info(
                f'circling {tuple(options.center)} at radius {options.radius:g} m in '
                f'{frame!r}, {abs(options.period):g} s per turn, {options.rate:g} Hz on {topic};'
                ' Ctrl-C stops')

            published = []

            def tick() -> None:
                published.append(circle_point(options.center, options.radius, options.period,
                                              time.monotonic() - start))
                node.publish_point(published[-1], frame)

            node.create_timer(1.0 / options.rate, tick)
            tick()
            # Ctrl-C is how a moving target ends: exit 0.
            end = spin_until(executor, stop, deadline=start + options.duration)
            if end is SpinEnd.SHUTDOWN:
                return 1
            # The last targets reach every subscriber before the publisher goes.
            acked = node.publisher.wait_for_all_acked(Duration(seconds=min(options.timeout, 1.0)))
            logger.info(f'{len(published)} targets published on {topic}'
                        + ('' if acked else ', the last not acknowledged'))
            return 0
    except ExternalShutdownException:
        return 1
    finally:
        node.destroy_node()
        rclpy.try_shutdown()


if __name__ == '__main__':
    sys.exit(main())
