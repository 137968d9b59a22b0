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
Decoding raw stamped messages whose body is doubles: PointStamped, PoseStamped, TwistStamped.

``decode_stamped`` reads the bytes a subscription created with ``raw=True`` passes, a header
(stamp and frame id) followed by ``count`` float64, and returns its fields, or a ``Refusal``
that says what is wrong with the bytes; it never raises. A raw read is some 20 times cheaper
than ``deserialize_message``, which builds the message's Python objects: the recorder reads
every pose and twist of a 1 kHz node this way.
"""

import struct
from typing import NamedTuple, Tuple, Union

from .layout import ENCAPSULATION_SIZE, NANOSECONDS_PER_SECOND

_REPRESENTATIONS = {b'\x00\x00': '>', b'\x00\x01': '<'}  # CDR_BE, CDR_LE (XCDR1 plain)
# The number of float64 after the header: a point (x, y, z), a pose (position x, y, z and
# orientation x, y, z, w), a twist (linear x, y, z and angular x, y, z).
POINT, POSE, TWIST = 3, 7, 6


class StampedFields(NamedTuple):
    """A stamped message's header (frame id, stamp) and the doubles after it."""

    frame_id: str
    sec: int
    nanosec: int
    values: Tuple[float, ...]

    @property
    def stamp_ns(self) -> int:
        """The stamp in integer nanoseconds."""
        return self.sec * NANOSECONDS_PER_SECOND + self.nanosec


class Refusal(NamedTuple):
    """Why some bytes are not the stamped message the decoder reads."""

    reason: str


def decode_stamped(data: object, count: int) -> Union[StampedFields, Refusal]:
    """
    Return the header and the ``count`` doubles of the raw stamped message ``data``.

    Reads plain CDR (XCDR1) of either byte order, as any ROS 2 middleware sends it, and is
    stricter than Fast CDR where the bytes break the format: it refuses a string whose length is
    0, that has no terminating NUL or a NUL inside, or that is not UTF-8 (Fast CDR accepts the
    first three, and rclpy replaces bad UTF-8), and any other encapsulation (XCDR2, parameter
    lists). Bytes after the message are ignored, as Fast CDR ignores them. Whatever it accepts,
    ``deserialize_message`` reads as the same fields.

    :param data: ``bytes``, ``bytearray`` or ``memoryview``; anything else is refused.
    :param count: the number of float64 after the header (``POINT``, ``POSE``, ``TWIST``).
    """
    if not isinstance(data, (bytes, bytearray, memoryview)):
        return Refusal(f'expected bytes, got {type(data).__name__}')
    try:
        data = bytes(data)
    except (TypeError, ValueError, BufferError) as error:
        return Refusal(f'unreadable buffer: {error}')
    size = len(data)
    if size < ENCAPSULATION_SIZE:
        return Refusal(f'truncated: {size} bytes, shorter than the encapsulation header')
    order = _REPRESENTATIONS.get(data[:2])
    if order is None:
        return Refusal(f'encapsulation {data[:2].hex()} is not plain CDR (0000 or 0001)')
    start = ENCAPSULATION_SIZE
    if size < start + 12:
        return Refusal(f'truncated: {size} bytes end inside the header')
    sec, nanosec, length = struct.unpack_from(order + 'iII', data, start)
    if length == 0:
        return Refusal('frame_id has length 0: a CDR string counts its terminating NUL')
    text_start = start + 12
    text_end = text_start + length
    if text_end > size:
        return Refusal(f'truncated: frame_id of {length} bytes runs past the {size} bytes')
    if data[text_end - 1] != 0:
        return Refusal('frame_id has no terminating NUL')
    raw = data[text_start:text_end - 1]
    if b'\x00' in raw:
        return Refusal('frame_id holds a NUL before its end')
    try:
        frame_id = raw.decode('utf-8')
    except UnicodeDecodeError as error:
        return Refusal(f'frame_id is not UTF-8: {error}')
    body_start = text_end + (-(text_end - start) % 8)
    if body_start + 8 * count > size:
        return Refusal(f'truncated: {size} bytes end before the {count} doubles')
    return StampedFields(frame_id, sec, nanosec,
                         struct.unpack_from(f'{order}{count}d', data, body_start))
