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
Precompiled CDR layouts, their common part: the compiler, the check, the fallback.

``Publisher.publish`` accepts ``bytes`` and hands them to the middleware as they are, skipping
the conversion of a Python message into C and its serialization (tens of microseconds for a
PoseStamped). A layout here is a ``struct.Struct`` per message type that writes those bytes
directly: the 4-byte encapsulation header (plain CDR, little endian: ``00 01 00 00``) and then
the fields in the order of the ``.msg`` definition, each primitive aligned to its own size
(8 for doubles) counted from the end of the encapsulation header, strings as a uint32 length
that includes the terminating NUL, then the UTF-8 bytes and the NUL, fixed arrays (the
covariances) as their elements without a length. That is XCDR version 1 as rmw_fastrtps_cpp
writes these types.

The frame ids are strings, and their length moves everything after them, so a layout is
compiled for its frame id(s) and compiled again when they change (they change rarely). The
padding bytes this module writes are zeros; rmw's serializer leaves whatever was in its buffer
there, which no reader looks at, so the bytes agree with ``serialize_message`` everywhere
except, possibly, in the padding.

Every compiled layout is checked once, when it is built, against
``rclpy.serialization.serialize_message`` of the same values in this process. Where a layout
does not apply, ``pack`` fills an rclpy message and returns ``serialize_message`` of it
instead (same bytes, none of the saving):

- a frame id holding a NUL character: rclpy cuts the string at the NUL, the layout would not;
- a middleware or a host whose serializer writes anything else (big-endian CDR, XCDR2, another
  alignment): the check at build time finds the difference.

tf2_msgs/TFMessage is not among the layouts: tf2_msgs is not installed with the rclpy wheels
this package uses, so its bytes could not be checked.

The layouts of each message family are in the modules beside this one: ``geometry``
(PoseStamped, TwistStamped), ``odometry`` (Odometry), ``clock`` (Clock), ``joint_state``
(JointState).
"""

import math
import struct
from typing import Iterable, List, Optional, Sequence, Tuple

from rclpy.serialization import serialize_message

NANOSECONDS_PER_SECOND = 1_000_000_000
# Encapsulation header: representation identifier CDR_LE (0x0001, big-endian on the wire),
# then two option bytes, zero.
ENCAPSULATION_LE = b'\x00\x01\x00\x00'
ENCAPSULATION_SIZE = len(ENCAPSULATION_LE)
COVARIANCE_SIZE = 36
ZERO_COVARIANCE = (0.0,) * COVARIANCE_SIZE

Vector = Sequence[float]


class Compiler:
    """
    Builds a little-endian struct format field by field, with XCDR1 alignment.

    Offsets count from the end of the encapsulation header, as CDR alignment does. Constant
    parts (the encapsulation header, a string with its length, a covariance) are ``Ns`` fields
    whose bytes the layout passes to every ``pack``.
    """

    def __init__(self) -> None:
        self.format = ['<']
        self.offset = -ENCAPSULATION_SIZE
        self.padding: List[int] = []
        self.constant(ENCAPSULATION_LE)

    def align(self, size: int) -> None:
        """Add the padding that brings the offset to a multiple of ``size``."""
        pad = -self.offset % size
        if pad:
            start = self.offset + ENCAPSULATION_SIZE
            self.padding.extend(range(start, start + pad))
            self.format.append(f'{pad}x')
            self.offset += pad

    def primitives(self, code: str, count: int = 1) -> None:
        """Add ``count`` aligned primitives of struct type ``code`` (i, I or d)."""
        size = struct.calcsize('<' + code)
        self.align(size)
        self.format.append(f'{count}{code}' if count > 1 else code)
        self.offset += size * count

    def constant(self, data: bytes) -> None:
        """Add bytes passed whole to ``pack`` (their alignment is the caller's)."""
        self.format.append(f'{len(data)}s')
        self.offset += len(data)

    def string(self, text: str) -> bytes:
        """Add a string field (uint32 length with the NUL, UTF-8, NUL); return its bytes."""
        self.align(4)
        encoded = text.encode('utf-8') + b'\x00'
        data = struct.pack('<I', len(encoded)) + encoded
        self.constant(data)
        return data

    def doubles(self, values: Sequence[float]) -> bytes:
        """Add a fixed array of doubles passed as constant bytes; return those bytes."""
        self.align(8)
        data = struct.pack(f'<{len(values)}d', *values)
        self.constant(data)
        return data

    def build(self) -> struct.Struct:
        """Return the Struct of everything added."""
        return struct.Struct(''.join(self.format))


def frame_text(name: str, value: object) -> str:
    if not isinstance(value, str):
        raise ValueError(f'{name} must be a str, got {value!r}')
    try:
        value.encode('utf-8')
    except UnicodeEncodeError as error:
        raise ValueError(f'{name} {value!r} is not encodable as UTF-8: {error}') from None
    return value


def covariance(name: str, values: Iterable[float]) -> Tuple[float, ...]:
    values = tuple(float(v) for v in values)
    if len(values) != COVARIANCE_SIZE:
        raise ValueError(f'{name} must have {COVARIANCE_SIZE} elements, got {len(values)}')
    return values


def fill_stamp(stamp, stamp_ns: int) -> None:
    stamp.sec, stamp.nanosec = divmod(stamp_ns, NANOSECONDS_PER_SECOND)


def fill_fields(message, names: str, values: Vector) -> None:
    for name, value in zip(names, values, strict=True):
        setattr(message, name, float(value))


class Layout:
    """
    Common part of the layouts: compile for the current strings, check, fall back.

    Attributes: ``precompiled`` says whether ``pack`` uses the compiled layout (True) or falls
    back to ``serialize_message`` (False) for the current strings, see the module docstring;
    ``padding`` holds the indices of the padding bytes in what ``pack`` returns (zeros).
    """

    message_type: type
    _PROBE: Tuple[Vector, ...] = ()

    def __init__(self) -> None:
        self._struct: Optional[struct.Struct] = None
        self.padding: Tuple[int, ...] = ()

    @property
    def precompiled(self) -> bool:
        """Whether the compiled layout applies (else ``pack`` falls back to rclpy)."""
        return self._struct is not None

    def _compile(self, compiler: Compiler) -> None:
        raise NotImplementedError

    def _strings(self) -> Tuple[str, ...]:
        raise NotImplementedError

    def message(self, stamp_ns: int, *fields: Vector):
        """Return the rclpy message that ``pack`` with the same arguments serializes."""
        raise NotImplementedError

    def _rebuild(self) -> None:
        """Compile for the current strings and keep the layout only if rmw agrees with it."""
        self._struct = None
        self.padding = ()
        if any('\x00' in text for text in self._strings()):
            return
        compiler = Compiler()
        self._compile(compiler)
        self._struct = compiler.build()
        self.padding = tuple(compiler.padding)
        # Distinct, non-trivial probe values, so that a misplaced field cannot go unnoticed.
        stamp_ns = 1_234_567_890_123_456_789
        probe = tuple(tuple(math.pi * (1 + i) + j / 7.0 for j in range(len(v)))
                      for i, v in enumerate(self._PROBE))
        expected = serialize_message(self.message(stamp_ns, *probe))
        if not same_bytes_but_padding(self.pack(stamp_ns, *probe), expected, self.padding):
            self._struct = None
            self.padding = ()

    def _fallback(self, stamp_ns: int, *fields: Vector) -> bytes:
        """Return ``serialize_message`` of the message (where no layout applies)."""
        return serialize_message(self.message(stamp_ns, *fields))

    def _error(self, stamp_ns: int, fields: Tuple[Vector, ...], error: Exception) -> ValueError:
        return ValueError(f'cannot pack {self.message_type.__name__} stamped {stamp_ns!r} with '
                          f'{fields!r}: {error}')


class StampedLayout(Layout):
    """A Header (stamp, frame id) followed by doubles only: PoseStamped, TwistStamped."""

    def __init__(self, frame_id: str) -> None:
        super().__init__()
        self._frame_id = frame_text('frame_id', frame_id)
        self._rebuild()

    @property
    def frame_id(self) -> str:
        """The header's frame id; setting a different one compiles the layout again."""
        return self._frame_id

    @frame_id.setter
    def frame_id(self, frame_id: str) -> None:
        frame_id = frame_text('frame_id', frame_id)
        if frame_id != self._frame_id:
            self._frame_id = frame_id
            self._rebuild()

    def _strings(self) -> Tuple[str, ...]:
        return (self._frame_id,)

    def _compile(self, compiler: Compiler) -> None:
        compiler.primitives('i')
        compiler.primitives('I')
        self._frame_bytes = compiler.string(self._frame_id)
        compiler.primitives('d', sum(len(v) for v in self._PROBE))


def same_bytes_but_padding(data: bytes, expected: bytes, padding: Iterable[int]) -> bool:
    """Return whether ``data`` and ``expected`` have one length and agree outside ``padding``."""
    if len(data) != len(expected):
        return False
    data, expected = bytearray(data), bytearray(expected)
    for index in padding:
        data[index] = expected[index] = 0
    return data == expected
