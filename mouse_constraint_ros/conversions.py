"""
Conversions between the physics core's data and ROS messages, all in one place.

The publishers reuse one message of each type and overwrite its fields every tick, so the
per-tick path builds no message objects (rclpy serializes on ``publish``, so reuse is safe).
"""

from builtin_interfaces.msg import Time
from geometry_msgs.msg import Point, PointStamped, PoseStamped, TwistStamped

from .physics import BodyState
from .physics.rotation import Vector3

NANOSECONDS_PER_SECOND = 1_000_000_000


def set_stamp(stamp: Time, nanoseconds: int) -> None:
    """Write a time given in integer nanoseconds into a ``builtin_interfaces/Time``."""
    stamp.sec, stamp.nanosec = divmod(nanoseconds, NANOSECONDS_PER_SECOND)


def stamp_nanoseconds(stamp: Time) -> int:
    """Return a ``builtin_interfaces/Time`` as integer nanoseconds."""
    return stamp.sec * NANOSECONDS_PER_SECOND + stamp.nanosec


def fill_pose(message: PoseStamped, state: BodyState) -> None:
    """Write the COM position and the orientation (x, y, z, w) of ``state`` into ``message``."""
    position, orientation = message.pose.position, message.pose.orientation
    position.x, position.y, position.z = state.position
    orientation.x, orientation.y, orientation.z, orientation.w = state.orientation


def fill_twist(message: TwistStamped, state: BodyState) -> None:
    """Write the COM linear and the angular velocity, both in the world frame, into ``message``."""
    linear, angular = message.twist.linear, message.twist.angular
    linear.x, linear.y, linear.z = state.linear_velocity
    angular.x, angular.y, angular.z = state.angular_velocity


def point_from_message(message: PointStamped) -> Vector3:
    """Return the point of a ``PointStamped`` as a 3-tuple of floats."""
    point = message.point
    return (point.x, point.y, point.z)


def point_message(point: Vector3, frame_id: str, nanoseconds: int) -> PointStamped:
    """Return a ``PointStamped`` at ``point`` in ``frame_id`` stamped ``nanoseconds``."""
    message = PointStamped()
    message.header.frame_id = frame_id
    set_stamp(message.header.stamp, nanoseconds)
    message.point.x, message.point.y, message.point.z = (float(c) for c in point)
    return message


def state_from_messages(pose: PoseStamped, twist: TwistStamped) -> BodyState:
    """Return the body state a pose and twist describe (the inverse of ``fill_*``)."""
    p, q = pose.pose.position, pose.pose.orientation
    v, w = twist.twist.linear, twist.twist.angular
    return BodyState((p.x, p.y, p.z), (q.x, q.y, q.z, q.w), (v.x, v.y, v.z), (w.x, w.y, w.z))


def fill_point(message: Point, vector: Vector3) -> None:
    """Write a 3-vector of floats into a ``geometry_msgs/Point`` (or Vector3: any x, y, z)."""
    message.x, message.y, message.z = vector
