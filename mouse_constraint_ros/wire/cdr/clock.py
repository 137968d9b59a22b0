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

"""rosgraph_msgs/Clock as precompiled CDR (see ``layout``)."""

import struct
from typing import Tuple

from rosgraph_msgs.msg import Clock

from .layout import Compiler, ENCAPSULATION_LE, fill_stamp, Layout, NANOSECONDS_PER_SECOND


class ClockLayout(Layout):
    """rosgraph_msgs/Clock: ``pack(stamp_ns)``, the 12 bytes of one time."""

    message_type = Clock

    def __init__(self) -> None:
        super().__init__()
        self._rebuild()

    def _strings(self) -> Tuple[str, ...]:
        return ()

    def _compile(self, compiler: Compiler) -> None:
        compiler.primitives('i')
        compiler.primitives('I')

    def pack(self, stamp_ns: int) -> bytes:
        """
        Return the bytes of the clock at ``stamp_ns``.

        :raises ValueError: if the seconds do not fit an int32.
        """
        if self._struct is None:
            return self._fallback(stamp_ns)
        sec, nanosec = divmod(stamp_ns, NANOSECONDS_PER_SECOND)
        try:
            return self._struct.pack(ENCAPSULATION_LE, sec, nanosec)
        except struct.error as error:
            raise self._error(stamp_ns, (), error) from None

    def message(self, stamp_ns: int) -> Clock:
        message = Clock()
        fill_stamp(message.clock, stamp_ns)
        return message
