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
Conversions between the physics core's data and ROS messages, all in one place.

The publishers reuse one message of each type and overwrite its fields every tick, so the
per-tick path builds no message objects (rclpy serializes on ``publish``, so reuse is safe).
"""

from typing import Tuple

from builtin_interfaces.msg import Time
from geometry_msgs.msg import (Point, PointStamped, PoseStamped, TransformStamped, TwistStamped,
                               WrenchStamped)
from nav_msgs.msg import Odometry
from std_msgs.msg import Float64MultiArray

from ..physics import BodyState
from ..physics.algebra import multiply_transposed, rotation_matrix, Vector3
from ..timing.tick_grid import NANOSECONDS_PER_SECOND


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


def felt_force(tick_impulse: Tuple[Vector3, float]) -> Vector3:
    """
    Return the force the pointer feels over a tick (N): minus the joint's impulse over its dt.

    ``tick_impulse`` is ``MouseSimulation.tick_impulse``: the impulse the joint gave the body
    over the tick, summed over the substeps, and the tick's dt. Its reaction, divided by dt,
    is the mean force on whatever holds the target: m (v' - v) = (-F + m g + F_wrench) dt
    for the tick, exactly, without linear damping and floor contact (their impulses change the
    momentum too). Zero with no target held (nothing holds the body) and before the first
    tick.
    """
    (x, y, z), dt = tick_impulse
    if dt <= 0.0:
        return (0.0, 0.0, 0.0)
    # 0.0 - x: no impulse reads as 0.0, not -0.0, in every echo and log of it.
    return ((0.0 - x) / dt, (0.0 - y) / dt, (0.0 - z) / dt)


def fill_felt_wrench(message: WrenchStamped, tick_impulse: Tuple[Vector3, float]) -> None:
    """
    Write the felt force of ``tick_impulse`` and a zero torque into ``message``.

    The torque is zero: the joint holds a point, and a force at a point has no moment about
    it. The angular friction (``angular_friction``), a torque that stops the body's spin about
    the anchor's line while a target is held, is not sent; the force the joint carries at the
    anchor as the friction turns the body about it is part of the reaction.
    """
    fill_force_wrench(message, felt_force(tick_impulse))


def fill_force_wrench(message: WrenchStamped, force: Vector3) -> None:
    """Write ``force`` (N) and a zero torque (the joint holds a point) into ``message``."""
    fill_point(message.wrench.force, force)
    fill_point(message.wrench.torque, (0.0, 0.0, 0.0))


def fill_force_array(message: Float64MultiArray, force: Vector3) -> None:
    """
    Write ``force`` (N) as ``data`` = [fx, fy, fz] into ``message``, its layout left empty.

    A ros2_control forward command controller takes such an array on its ``commands`` topic,
    one value per joint in the order of its ``joints``: for a device whose three joints are
    its x, y and z axes (forcedimension_ros2's fd_x, fd_y, fd_z), the force itself.
    """
    message.data = force


def point_from_message(message: PointStamped) -> Vector3:
    """Return the point of a ``PointStamped`` as a 3-tuple of floats."""
    point = message.point
    return (point.x, point.y, point.z)


def point_from_pose(message: PoseStamped) -> Vector3:
    """Return the position of a ``PoseStamped`` as a 3-tuple of floats (its target point)."""
    position = message.pose.position
    return (position.x, position.y, position.z)


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


def fill_transform(message: TransformStamped, state: BodyState) -> None:
    """
    Write the body's pose into a ``TransformStamped`` from ``frame_id`` to the body frame.

    The translation is the COM position and the rotation the orientation (x, y, z, w), so the
    transform maps body-frame coordinates to ``frame_id`` coordinates: the body frame's origin
    is the COM, as in ``BodyState``. The header and ``child_frame_id`` are left to the caller,
    who sets the frame ids once and the stamp per tick.
    """
    translation, rotation = message.transform.translation, message.transform.rotation
    translation.x, translation.y, translation.z = state.position
    rotation.x, rotation.y, rotation.z, rotation.w = state.orientation


def transform_message(state: BodyState, *, frame_id: str, body_frame_id: str,
                      nanoseconds: int) -> TransformStamped:
    """
    Return the ``TransformStamped`` ``frame_id`` -> ``body_frame_id`` of ``state``.

    :param state: the body state (world-frame velocities are not used).
    :param frame_id: the parent frame, the node's ``frame_id``.
    :param body_frame_id: the child frame, attached to the body at its COM.
    :param nanoseconds: the stamp in integer nanoseconds.
    """
    message = TransformStamped()
    message.header.frame_id = frame_id
    message.child_frame_id = body_frame_id
    set_stamp(message.header.stamp, nanoseconds)
    fill_transform(message, state)
    return message


def fill_odometry(message: Odometry, state: BodyState) -> None:
    """
    Write the COM pose and the body-frame twist of ``state`` into an ``Odometry``.

    nav_msgs/Odometry gives its pose in ``header.frame_id`` and its twist in
    ``child_frame_id``, the body frame. ``BodyState`` holds both velocities in the world frame,
    so they are rotated into the body frame: v_body = R^T v_world, w_body = R^T w_world, with R
    the body's rotation matrix. The ``twist`` topic (``fill_twist``) keeps the world frame.
    The covariances are left as the caller set them (all zeros by default: the state is exact).
    The header and ``child_frame_id`` are left to the caller, like ``fill_transform``.
    """
    pose = message.pose.pose
    position, orientation = pose.position, pose.orientation
    position.x, position.y, position.z = state.position
    orientation.x, orientation.y, orientation.z, orientation.w = state.orientation
    linear, angular = message.twist.twist.linear, message.twist.twist.angular
    (linear.x, linear.y, linear.z), (angular.x, angular.y, angular.z) = body_frame_twist(state)


def body_frame_twist(state: BodyState) -> Tuple[Vector3, Vector3]:
    """
    Return the linear and angular velocity of ``state`` in the body frame.

    v_body = R^T v_world and w_body = R^T w_world, with R the rotation matrix of the body's
    orientation: the twist of nav_msgs/Odometry, which is expressed in ``child_frame_id``.
    """
    rotation = rotation_matrix(state.orientation)
    return (multiply_transposed(state.linear_velocity, rotation),
            multiply_transposed(state.angular_velocity, rotation))


def odometry_message(state: BodyState, *, frame_id: str, body_frame_id: str,
                     nanoseconds: int) -> Odometry:
    """
    Return the ``Odometry`` of ``state``: pose in ``frame_id``, twist in ``body_frame_id``.

    :param state: the body state, velocities in the world frame.
    :param frame_id: ``header.frame_id``, the frame of the pose (the node's ``frame_id``).
    :param body_frame_id: ``child_frame_id``, the body frame the twist is expressed in.
    :param nanoseconds: the stamp in integer nanoseconds.
    """
    message = Odometry()
    message.header.frame_id = frame_id
    message.child_frame_id = body_frame_id
    set_stamp(message.header.stamp, nanoseconds)
    fill_odometry(message, state)
    return message


def wrench_message(force: Vector3, torque: Vector3, frame_id: str) -> WrenchStamped:
    """Return a ``WrenchStamped`` of ``force`` (N) and ``torque`` (N m) in ``frame_id``."""
    message = WrenchStamped()
    message.header.frame_id = frame_id
    f, t = message.wrench.force, message.wrench.torque
    f.x, f.y, f.z = (float(c) for c in force)
    t.x, t.y, t.z = (float(c) for c in torque)
    return message
