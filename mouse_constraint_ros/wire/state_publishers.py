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
The node's state outputs: pose, twist, TF, odometry and force of one tick, as raw CDR.

Pose and twist (and odometry) go to the middleware as the bytes of a precompiled layout
(``cdr``): ``Publisher.publish(bytes)`` sends them as they are, which skips the
conversion of a Python message into C and rmw's serialization. The bytes are those rclpy would
send for the message ``fill_pose`` / ``fill_twist`` / ``fill_odometry`` fill (the layouts check
that when they are compiled, and a test compares what a subscriber receives). Where a layout
reports that it does not apply (``precompiled`` is False: a frame id holding a NUL, a
middleware that writes other bytes) the message itself is filled and published instead.

TF: the transform ``frame_id`` -> ``body_frame_id`` (``fill_transform``) goes to a broadcaster
made by a factory the node is given, by default ``tf2_ros.TransformBroadcaster`` when tf2_ros
is importable. It is sent as one reused ``TransformStamped``, so a broadcaster must send it
before it returns (tf2_ros's does: it publishes, and rclpy serializes on publish). Without a
broadcaster TF is off and ``tf_status`` says why.

Odometry (``odom``): nav_msgs/Odometry with the pose in ``frame_id`` and the twist in
``body_frame_id`` (``body_frame_twist``), zero covariances: the state is exact.

Force (``force``, with ``publish_force``): the force the pointer feels over the tick, in N
in ``frame_id``, one per pose, with the pose's stamp (when a device's pose ran the tick, that
pose's stamp): minus the joint's impulse summed over
the tick's substeps, over dt (``messages.felt_force``), so that m (v' - v) = (-F + m g +
F_wrench) dt holds for every tick without linear damping and floor contact (they change the
momentum too, and are no force on the hand). Zero with no target held. Its torque is zero: the
joint holds a point (``messages.fill_felt_wrench``). It goes to the device through the device's
map (``physics.device_map``: f R^T F, in ``force_frame_id``), as a WrenchStamped on ``force``,
a Float64MultiArray on ``force_array`` or both (``force_output``), each from the same tick; it
is zero while ``force_muted`` (the device's poses stopped). Its publishers are made when the
force is first turned on and kept when it is turned off, silent.
"""

from typing import Any, Callable, Optional

from geometry_msgs.msg import PoseStamped, TransformStamped, TwistStamped, WrenchStamped
from nav_msgs.msg import Odometry
from rclpy.node import Node
from std_msgs.msg import Float64MultiArray

from .cdr.geometry import PoseStampedLayout, TwistStampedLayout, WrenchStampedLayout
from .cdr.odometry import OdometryLayout
from .interface import (FORCE_ARRAY_TOPIC, FORCE_QOS, FORCE_TOPIC, ODOM_TOPIC, POSE_TOPIC,
                        STATE_QOS, TWIST_TOPIC)
from .messages import (body_frame_twist, felt_force, fill_force_array, fill_force_wrench,
                       fill_odometry, fill_pose, fill_transform, fill_twist, set_stamp)
from ..physics import BodyState, MouseSimulation
from ..physics.body_frame import BodyFrame
from ..physics.device_map import DeviceMap

ZERO = (0.0, 0.0, 0.0)

BroadcasterFactory = Callable[[Node], Any]

try:
    from tf2_ros import TransformBroadcaster as _TransformBroadcaster
except ImportError as error:
    _TransformBroadcaster = None
    TF_UNAVAILABLE: Optional[str] = f'tf2_ros is not importable ({error})'
else:
    TF_UNAVAILABLE = None

# The broadcaster factory the node uses unless it is given one: tf2_ros's, or None without it.
DEFAULT_BROADCASTER: Optional[BroadcasterFactory] = _TransformBroadcaster


class StatePublishers:
    """
    The publishers of pose, twist, TF and odometry, and what one publish sends.

    :param node: the node that owns the publishers.
    :param broadcaster_factory: makes the TF broadcaster from ``node`` (called once, when TF is
        first on), or None: TF is off then.
    :param unavailable: why there is no broadcaster factory, for ``tf_status``.
    :param frame_id: the frame of pose and twist, TF's and odometry's parent.
    :param body_frame_id: the frame attached to the body, TF's and odometry's child.
    :param publish_tf: whether TF is wanted.
    :param publish_odometry: whether odometry is published.
    :param simulation: the body whose ``tick_impulse`` the force is made of; None: no force.
    :param publish_force: whether the force is published (with a simulation).
    :param force_output: 'wrench', 'array' or 'both': the force's messages.
    :param force_frame_id: the frame of the force sent (the device's); '' = ``frame_id``.
    :param device_map: the force's map back to the device.
    """

    def __init__(self, node: Node, *, broadcaster_factory: Optional[BroadcasterFactory],
                 unavailable: Optional[str], frame_id: str, body_frame_id: str,
                 publish_tf: bool, publish_odometry: bool,
                 simulation: Optional[MouseSimulation] = None,
                 publish_force: bool = False, body_frame: BodyFrame = BodyFrame(),
                 **device: Any) -> None:
        """Create the pose and twist publishers and apply the rest with ``configure``."""
        self._node = node
        self._factory = broadcaster_factory
        self._unavailable = unavailable or 'no transform broadcaster was given'
        self.pose_publisher = node.create_publisher(PoseStamped, POSE_TOPIC, STATE_QOS)
        self.twist_publisher = node.create_publisher(TwistStamped, TWIST_TOPIC, STATE_QOS)
        self.odometry_publisher = None
        self.force_publisher = self.force_array_publisher = None
        self._force_array = Float64MultiArray()
        # Set by the tick: while true the force sent is zero (the device's poses stopped).
        self.force_muted = False
        self._simulation = simulation
        self._force_layout = WrenchStampedLayout(frame_id)
        self._force = WrenchStamped()
        self._pose_layout = PoseStampedLayout(frame_id)
        self._twist_layout = TwistStampedLayout(frame_id)
        self._odometry_layout = OdometryLayout(frame_id, body_frame_id)
        # The messages of the fallback path and of TF, reused.
        self._pose, self._twist = PoseStamped(), TwistStamped()
        self._odometry, self._transform = Odometry(), TransformStamped()
        self._broadcaster = None
        self._send_transform = None
        self.tf_status = ''
        self.configure(frame_id=frame_id, body_frame_id=body_frame_id, publish_tf=publish_tf,
                       publish_odometry=publish_odometry, publish_force=publish_force,
                       body_frame=body_frame, **device)

    def configure(self, *, frame_id: str, body_frame_id: str, publish_tf: bool,
                  publish_odometry: bool, publish_force: bool = False,
                  body_frame: BodyFrame = BodyFrame(), force_output: str = 'wrench',
                  force_frame_id: str = '', device_map: DeviceMap = DeviceMap()) -> None:
        """
        Apply new frames and switches; layouts compile again only if a frame changed.

        :param body_frame: where the published frame (a URDF link's) has the COM: pose, twist,
            TF and odometry are of that frame, the twist's linear part the velocity of its
            origin.
        """
        self._to_link = None if body_frame.at_com else body_frame.link_state
        self._to_device = None if device_map == DeviceMap() else device_map.to_device
        self._force_layout.frame_id = self._force.header.frame_id = force_frame_id or frame_id
        self._raw_force = self._force_layout.precompiled
        # Made at the first on and kept when turned off: a reader that matched one keeps it, and
        # the forces after the next on reach it from the first (a new publisher's would go
        # nowhere until the reader's participant had discovered it).
        on = publish_force and self._simulation is not None
        self._send_array = on and force_output != 'wrench'
        self._send_wrench = on and force_output != 'array'
        if self._send_array and self.force_array_publisher is None:
            self.force_array_publisher = self._node.create_publisher(
                Float64MultiArray, FORCE_ARRAY_TOPIC, FORCE_QOS)
        if self._send_wrench and self.force_publisher is None:
            self.force_publisher = self._node.create_publisher(WrenchStamped, FORCE_TOPIC,
                                                               FORCE_QOS)
        self._pose_layout.frame_id = frame_id
        self._twist_layout.frame_id = frame_id
        self._odometry_layout.configure(frame_id=frame_id, child_frame_id=body_frame_id)
        self._raw_pose = self._pose_layout.precompiled
        self._raw_twist = self._twist_layout.precompiled
        self._raw_odometry = self._odometry_layout.precompiled
        for message in (self._pose, self._twist, self._odometry, self._transform):
            message.header.frame_id = frame_id
        self._odometry.child_frame_id = self._transform.child_frame_id = body_frame_id
        if publish_odometry and self.odometry_publisher is None:
            self.odometry_publisher = self._node.create_publisher(Odometry, ODOM_TOPIC,
                                                                  STATE_QOS)
        elif not publish_odometry and self.odometry_publisher is not None:
            self._node.destroy_publisher(self.odometry_publisher)
            self.odometry_publisher = None
        if not publish_tf:
            self._send_transform = None
            self.tf_status = 'off: publish_tf is false'
        elif self._factory is None:
            self._send_transform = None
            self.tf_status = f'off: {self._unavailable}'
        else:
            if self._broadcaster is None:
                self._broadcaster = self._factory(self._node)
            self._send_transform = self._broadcaster.sendTransform
            self.tf_status = f'{frame_id} -> {body_frame_id}'

    @property
    def tf_on(self) -> bool:
        """Whether ``publish`` sends the transform."""
        return self._send_transform is not None

    @property
    def send_transform(self):
        """Return the TF broadcaster's ``sendTransform``, or None while TF is off."""
        return self._send_transform

    def publish(self, stamp_ns: int, state: BodyState, *, force: bool = True,
                force_stamp: Optional[int] = None) -> None:
        """
        Publish the pose, twist and, where on, the transform, odometry and force.

        :param force: False: no force, whatever ``publish_force`` says (a state published out
            of a tick has no reaction of its own to send).
        :param force_stamp: the force's stamp (ns) if not ``stamp_ns``: that of the device's
            pose that ran the tick.
        """
        if self._to_link is not None:
            state = self._to_link(state)
        if self._raw_pose:
            self.pose_publisher.publish(
                self._pose_layout.pack(stamp_ns, state.position, state.orientation))
        else:
            set_stamp(self._pose.header.stamp, stamp_ns)
            fill_pose(self._pose, state)
            self.pose_publisher.publish(self._pose)
        if self._raw_twist:
            self.twist_publisher.publish(
                self._twist_layout.pack(stamp_ns, state.linear_velocity, state.angular_velocity))
        else:
            set_stamp(self._twist.header.stamp, stamp_ns)
            fill_twist(self._twist, state)
            self.twist_publisher.publish(self._twist)
        if self._send_transform is not None:
            set_stamp(self._transform.header.stamp, stamp_ns)
            fill_transform(self._transform, state)
            self._send_transform(self._transform)
        if self.odometry_publisher is not None:
            if self._raw_odometry:
                linear, angular = body_frame_twist(state)
                self.odometry_publisher.publish(self._odometry_layout.pack(
                    stamp_ns, state.position, state.orientation, linear, angular))
            else:
                set_stamp(self._odometry.header.stamp, stamp_ns)
                fill_odometry(self._odometry, state)
                self.odometry_publisher.publish(self._odometry)
        if force and (self._send_wrench or self._send_array):
            self._publish_force(stamp_ns if force_stamp is None else force_stamp)

    def _publish_force(self, stamp_ns: int) -> None:
        """Publish the force of the tick, mapped to the device, on each of its topics."""
        if self.force_muted:
            force = ZERO
        else:
            force = felt_force(self._simulation.tick_impulse)
            if self._to_device is not None:
                force = self._to_device(force)
        if self._send_wrench:
            if self._raw_force:
                self.force_publisher.publish(self._force_layout.pack(stamp_ns, force, ZERO))
            else:
                set_stamp(self._force.header.stamp, stamp_ns)
                fill_force_wrench(self._force, force)
                self.force_publisher.publish(self._force)
        if self._send_array:
            fill_force_array(self._force_array, force)
            self.force_array_publisher.publish(self._force_array)
