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

"""geometry_msgs PoseStamped, TwistStamped and WrenchStamped as precompiled CDR (``layout``)."""

import struct

from geometry_msgs.msg import PoseStamped, TwistStamped, WrenchStamped

from .layout import (ENCAPSULATION_LE, fill_fields, fill_stamp, NANOSECONDS_PER_SECOND,
                     StampedLayout, Vector)


class PoseStampedLayout(StampedLayout):
    """
    geometry_msgs/PoseStamped in one frame: ``pack(stamp_ns, position, orientation)``.

    :param frame_id: the header's frame id.
    """

    message_type = PoseStamped
    _PROBE = ((0.0,) * 3, (0.0,) * 4)

    def pack(self, stamp_ns: int, position: Vector, orientation: Vector) -> bytes:
        """
        Return the bytes of the pose at ``position``, ``orientation`` (x, y, z, w).

        :raises ValueError: if the stamp's seconds do not fit an int32 or a field has the wrong
            number of elements.
        """
        if self._struct is None:
            return self._fallback(stamp_ns, position, orientation)
        sec, nanosec = divmod(stamp_ns, NANOSECONDS_PER_SECOND)
        try:
            return self._struct.pack(ENCAPSULATION_LE, sec, nanosec, self._frame_bytes,
                                     *position, *orientation)
        except (struct.error, TypeError) as error:
            raise self._error(stamp_ns, (position, orientation), error) from None

    def message(self, stamp_ns: int, position: Vector, orientation: Vector) -> PoseStamped:
        message = PoseStamped()
        message.header.frame_id = self._frame_id
        fill_stamp(message.header.stamp, stamp_ns)
        fill_fields(message.pose.position, 'xyz', position)
        fill_fields(message.pose.orientation, 'xyzw', orientation)
        return message


class TwistStampedLayout(StampedLayout):
    """
    geometry_msgs/TwistStamped in one frame: ``pack(stamp_ns, linear, angular)``.

    :param frame_id: the header's frame id.
    """

    message_type = TwistStamped
    _PROBE = ((0.0,) * 3, (0.0,) * 3)

    def pack(self, stamp_ns: int, linear: Vector, angular: Vector) -> bytes:
        """
        Return the bytes of the twist with ``linear`` and ``angular`` velocity.

        :raises ValueError: as ``PoseStampedLayout.pack``.
        """
        if self._struct is None:
            return self._fallback(stamp_ns, linear, angular)
        sec, nanosec = divmod(stamp_ns, NANOSECONDS_PER_SECOND)
        try:
            return self._struct.pack(ENCAPSULATION_LE, sec, nanosec, self._frame_bytes,
                                     *linear, *angular)
        except (struct.error, TypeError) as error:
            raise self._error(stamp_ns, (linear, angular), error) from None

    def message(self, stamp_ns: int, linear: Vector, angular: Vector) -> TwistStamped:
        message = TwistStamped()
        message.header.frame_id = self._frame_id
        fill_stamp(message.header.stamp, stamp_ns)
        fill_fields(message.twist.linear, 'xyz', linear)
        fill_fields(message.twist.angular, 'xyz', angular)
        return message


class WrenchStampedLayout(StampedLayout):
    """
    geometry_msgs/WrenchStamped in one frame: ``pack(stamp_ns, force, torque)``.

    :param frame_id: the header's frame id.
    """

    message_type = WrenchStamped
    _PROBE = ((0.0,) * 3, (0.0,) * 3)

    def pack(self, stamp_ns: int, force: Vector, torque: Vector) -> bytes:
        """
        Return the bytes of the wrench of ``force`` (N) and ``torque`` (N m).

        :raises ValueError: as ``PoseStampedLayout.pack``.
        """
        if self._struct is None:
            return self._fallback(stamp_ns, force, torque)
        sec, nanosec = divmod(stamp_ns, NANOSECONDS_PER_SECOND)
        try:
            return self._struct.pack(ENCAPSULATION_LE, sec, nanosec, self._frame_bytes,
                                     *force, *torque)
        except (struct.error, TypeError) as error:
            raise self._error(stamp_ns, (force, torque), error) from None

    def message(self, stamp_ns: int, force: Vector, torque: Vector) -> WrenchStamped:
        message = WrenchStamped()
        message.header.frame_id = self._frame_id
        fill_stamp(message.header.stamp, stamp_ns)
        fill_fields(message.wrench.force, 'xyz', force)
        fill_fields(message.wrench.torque, 'xyz', torque)
        return message
