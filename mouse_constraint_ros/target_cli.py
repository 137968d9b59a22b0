"""
The ``mouse_target`` command: publish mouse targets on the relative topic ``target``.

``mouse_target X Y Z`` publishes one target and exits once a subscriber has acknowledged it;
``mouse_target --circle`` moves the target around a circle until Ctrl-C (or ``--duration``).
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

from .conversions import point_message
from .node import TARGET_QOS
from .signals import StopRequest


def parse_arguments(argv: List[str]) -> argparse.Namespace:
    """Return the command's options from ``argv`` (ROS arguments already removed)."""
    parser = argparse.ArgumentParser(
        prog='mouse_target', description=__doc__.split('\n\n')[0].strip(),
        epilog='examples: mouse_target 0.5 0 1 | mouse_target --circle --center 0 0 1 '
               '--radius 0.3 --period 2 | add --ros-args -r target:=/clicked_point to remap')
    parser.add_argument('point', nargs='*', type=float, metavar='X Y Z',
                        help='one target (m), published once')
    parser.add_argument('--frame', default='world', help='frame_id of the target (default world)')
    parser.add_argument('--timeout', type=float, default=10.0,
                        help='seconds to wait for a subscriber and its acknowledgement')
    circle = parser.add_argument_group('moving target')
    circle.add_argument('--circle', action='store_true',
                        help='move the target around a horizontal circle until Ctrl-C')
    circle.add_argument('--center', nargs=3, type=float, default=[0.0, 0.0, 1.0],
                        metavar=('X', 'Y', 'Z'), help='circle centre (m, default 0 0 1)')
    circle.add_argument('--radius', type=float, default=0.3, help='circle radius (m)')
    circle.add_argument('--period', type=float, default=2.0,
                        help='seconds per turn; negative turns clockwise')
    circle.add_argument('--rate', type=float, default=50.0, help='targets per second')
    circle.add_argument('--duration', type=float, default=math.inf,
                        help='stop after this many seconds (default: until Ctrl-C)')
    options = parser.parse_args(argv)
    if options.circle == bool(options.point):
        parser.error('give either X Y Z or --circle')
    if options.point and len(options.point) != 3:
        parser.error(f'a target needs 3 coordinates, got {len(options.point)}')
    numbers = [*options.point, *options.center, options.radius, options.period, options.rate]
    if not all(math.isfinite(v) for v in numbers):
        parser.error('coordinates, radius, period and rate must be finite')
    if options.circle and (options.radius <= 0.0 or options.period == 0.0 or options.rate <= 0.0):
        parser.error('--radius and --rate must be > 0 and --period non-zero')
    if not options.timeout > 0.0:
        parser.error('--timeout must be > 0')
    return options


def circle_point(center: List[float], radius: float, period: float, t: float) -> List[float]:
    """Return the point of the horizontal circle at time ``t`` (s), starting at +x."""
    angle = 2.0 * math.pi * t / period
    return [center[0] + radius * math.cos(angle), center[1] + radius * math.sin(angle),
            center[2]]


class TargetPublisher(Node):
    """A node with one publisher on ``target``, QoS-compatible with ``mouse_constraint``."""

    def __init__(self, **kwargs) -> None:
        """Create the node ``mouse_target`` and its publisher."""
        super().__init__('mouse_target', **kwargs)
        self.publisher = self.create_publisher(PointStamped, 'target', TARGET_QOS)

    def publish_point(self, point: List[float], frame_id: str) -> None:
        """Publish ``point`` in ``frame_id``, stamped now."""
        self.publisher.publish(
            point_message(point, frame_id, self.get_clock().now().nanoseconds))

    def wait_for_subscriber(self, executor, timeout: float) -> bool:
        """Spin until a subscriber has matched, for at most ``timeout`` seconds."""
        deadline = time.monotonic() + timeout
        while self.publisher.get_subscription_count() == 0:
            if time.monotonic() > deadline:
                return False
            executor.spin_once(timeout_sec=0.05)
        return True


def main(args: Optional[List[str]] = None) -> int:
    """Publish one target or a moving one; return 0 on success, 1 when nobody listened."""
    argv = sys.argv if args is None else args
    options = parse_arguments(remove_ros_args(argv)[1:])
    rclpy.init(args=argv, signal_handler_options=SignalHandlerOptions.NO)
    node = TargetPublisher()
    executor = SingleThreadedExecutor(context=node.context)
    executor.add_node(node)
    topic = node.publisher.topic_name
    try:
        if not node.wait_for_subscriber(executor, options.timeout):
            node.get_logger().error(
                f'no subscriber on {topic} after {options.timeout:g} s: is mouse_constraint '
                'running with the same ROS_DOMAIN_ID, namespace and remappings?')
            return 1
        if not options.circle:
            node.publish_point(options.point, options.frame)
            if not node.publisher.wait_for_all_acked(Duration(seconds=options.timeout)):
                node.get_logger().error(f'target on {topic} was not acknowledged in '
                                        f'{options.timeout:g} s')
                return 1
            node.get_logger().info(f'target {tuple(options.point)} in {options.frame!r} '
                                   f'received on {topic}')
            return 0
        start = time.monotonic()
        node.get_logger().info(
            f'circling {tuple(options.center)} at radius {options.radius:g} m, '
            f'{abs(options.period):g} s per turn, {options.rate:g} Hz on {topic}; Ctrl-C stops')

        def tick() -> None:
            node.publish_point(circle_point(options.center, options.radius, options.period,
                                            time.monotonic() - start), options.frame)

        node.create_timer(1.0 / options.rate, tick)
        tick()
        with StopRequest() as stop:
            while not stop and time.monotonic() - start < options.duration:
                executor.spin_once(timeout_sec=0.1)
        return 0
    except (KeyboardInterrupt, ExternalShutdownException):
        # Ctrl-C is how a moving target ends; a one-shot target it interrupts.
        return 0 if options.circle else 130
    finally:
        node.destroy_node()
        rclpy.try_shutdown()


if __name__ == '__main__':
    sys.exit(main())
