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

"""sensor_msgs/JointState of fixed joints as precompiled CDR (see ``layout``)."""

import struct
from typing import Sequence, Tuple

from sensor_msgs.msg import JointState

from .layout import (Compiler, ENCAPSULATION_LE, fill_stamp, frame_text, Layout,
                     NANOSECONDS_PER_SECOND, Vector)


class JointStateLayout(Layout):
    """
    sensor_msgs/JointState of one robot: ``pack(stamp_ns, positions, velocities, efforts)``.

    The names, their number and the frame id are fixed when the layout is built: only the stamp
    and the three sequences' values change from one message to the next, each sequence as long
    as the names.

    :param names: the joints' names, in the order the values come.
    :param frame_id: the header's frame id (empty, as robot_state_publisher reads it).
    """

    message_type = JointState

    def __init__(self, names: Sequence[str], frame_id: str = '') -> None:
        super().__init__()
        self._names = tuple(frame_text('joint name', name) for name in names)
        self._frame_id = frame_text('frame_id', frame_id)
        count = len(self._names)
        self._PROBE = ((0.0,) * count,) * 3
        self._rebuild()

    def _strings(self) -> Tuple[str, ...]:
        return (self._frame_id,) + self._names

    def _compile(self, compiler: Compiler) -> None:
        compiler.primitives('i')
        compiler.primitives('I')
        head = [compiler.string(self._frame_id), _length(compiler, len(self._names))]
        head.extend(compiler.string(name) for name in self._names)
        self._head = tuple(head)
        count = len(self._names)
        for _ in range(3):  # position, velocity, effort
            self._count_bytes = _length(compiler, count)
            if count:
                compiler.primitives('d', count)

    def pack(self, stamp_ns: int, positions: Vector, velocities: Vector,
             efforts: Vector) -> bytes:
        """
        Return the bytes of the joints at ``positions``, ``velocities`` and ``efforts``.

        :raises ValueError: if the stamp's seconds do not fit an int32 or a sequence is not as
            long as the names.
        """
        if self._struct is None:
            return self._fallback(stamp_ns, positions, velocities, efforts)
        sec, nanosec = divmod(stamp_ns, NANOSECONDS_PER_SECOND)
        count = self._count_bytes
        try:
            return self._struct.pack(ENCAPSULATION_LE, sec, nanosec, *self._head, count,
                                     *positions, count, *velocities, count, *efforts)
        except (struct.error, TypeError) as error:
            raise self._error(stamp_ns, (positions, velocities, efforts), error) from None

    def message(self, stamp_ns: int, positions: Vector, velocities: Vector,
                efforts: Vector) -> JointState:
        message = JointState()
        message.header.frame_id = self._frame_id
        fill_stamp(message.header.stamp, stamp_ns)
        message.name = list(self._names)
        message.position = [float(x) for x in positions]
        message.velocity = [float(x) for x in velocities]
        message.effort = [float(x) for x in efforts]
        return message


def _length(compiler: Compiler, count: int) -> bytes:
    """Add a sequence's uint32 length, aligned, as constant bytes; return them."""
    compiler.align(4)
    data = struct.pack('<I', count)
    compiler.constant(data)
    return data
