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
Decoding a raw geometry_msgs/PointStamped: ``decode_stamped`` with its three doubles.

``decode_point_stamped`` reads a raw geometry_msgs/PointStamped (a subscription created with
``raw=True`` passes ``bytes``) and returns its fields, or a ``Refusal`` that says what is wrong
with the bytes; it never raises.
"""

from typing import NamedTuple, Tuple, Union

from geometry_msgs.msg import PointStamped

from .layout import NANOSECONDS_PER_SECOND
from .stamped import decode_stamped, POINT, Refusal


class PointStampedFields(NamedTuple):
    """The fields of a geometry_msgs/PointStamped: frame id, stamp, point (m)."""

    frame_id: str
    sec: int
    nanosec: int
    x: float
    y: float
    z: float

    @property
    def stamp_ns(self) -> int:
        """The stamp in integer nanoseconds."""
        return self.sec * NANOSECONDS_PER_SECOND + self.nanosec

    @property
    def point(self) -> Tuple[float, float, float]:
        """The point as a 3-tuple."""
        return (self.x, self.y, self.z)


def decode_point_stamped(data: object) -> Union[PointStampedFields, Refusal]:
    """
    Return the fields of the raw geometry_msgs/PointStamped ``data``, or why it is refused.

    As ``decode_stamped`` reads it (its checks and their messages).

    :param data: ``bytes``, ``bytearray`` or ``memoryview``; anything else is refused.
    """
    fields = decode_stamped(data, POINT)
    if isinstance(fields, Refusal):
        return fields
    return PointStampedFields(fields.frame_id, fields.sec, fields.nanosec, *fields.values)


def fields_of(message: PointStamped) -> PointStampedFields:
    """Return the fields of an rclpy PointStamped, as ``decode_point_stamped`` gives them."""
    header, point = message.header, message.point
    return PointStampedFields(header.frame_id, header.stamp.sec, header.stamp.nanosec,
                              point.x, point.y, point.z)
