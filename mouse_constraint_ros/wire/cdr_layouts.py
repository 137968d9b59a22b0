"""
Precompiled CDR layouts: the node's messages as the exact bytes rclpy would send.

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

``decode_point_stamped`` reads a raw geometry_msgs/PointStamped (a subscription created with
``raw=True`` passes ``bytes``) and returns its fields, or a ``Refusal`` that says what is wrong
with the bytes; it never raises.
"""

import math
import struct
from typing import Iterable, List, NamedTuple, Optional, Sequence, Tuple, Union

from geometry_msgs.msg import PointStamped, PoseStamped, TwistStamped
from nav_msgs.msg import Odometry
from rclpy.serialization import serialize_message
from rosgraph_msgs.msg import Clock

NANOSECONDS_PER_SECOND = 1_000_000_000
# Encapsulation header: representation identifier CDR_LE (0x0001, big-endian on the wire),
# then two option bytes, zero.
ENCAPSULATION_LE = b'\x00\x01\x00\x00'
ENCAPSULATION_SIZE = len(ENCAPSULATION_LE)
COVARIANCE_SIZE = 36
ZERO_COVARIANCE = (0.0,) * COVARIANCE_SIZE

Vector = Sequence[float]


class _Compiler:
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


def _frame_text(name: str, value: object) -> str:
    if not isinstance(value, str):
        raise ValueError(f'{name} must be a str, got {value!r}')
    try:
        value.encode('utf-8')
    except UnicodeEncodeError as error:
        raise ValueError(f'{name} {value!r} is not encodable as UTF-8: {error}') from None
    return value


def _covariance(name: str, values: Iterable[float]) -> Tuple[float, ...]:
    values = tuple(float(v) for v in values)
    if len(values) != COVARIANCE_SIZE:
        raise ValueError(f'{name} must have {COVARIANCE_SIZE} elements, got {len(values)}')
    return values


def _set_stamp(stamp, stamp_ns: int) -> None:
    stamp.sec, stamp.nanosec = divmod(stamp_ns, NANOSECONDS_PER_SECOND)


def _fill(message, names: str, values: Vector) -> None:
    for name, value in zip(names, values, strict=True):
        setattr(message, name, float(value))


class _Layout:
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

    def _compile(self, compiler: _Compiler) -> None:
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
        compiler = _Compiler()
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


class _StampedLayout(_Layout):
    """A Header (stamp, frame id) followed by doubles only: PoseStamped, TwistStamped."""

    def __init__(self, frame_id: str) -> None:
        super().__init__()
        self._frame_id = _frame_text('frame_id', frame_id)
        self._rebuild()

    @property
    def frame_id(self) -> str:
        """The header's frame id; setting a different one compiles the layout again."""
        return self._frame_id

    @frame_id.setter
    def frame_id(self, frame_id: str) -> None:
        frame_id = _frame_text('frame_id', frame_id)
        if frame_id != self._frame_id:
            self._frame_id = frame_id
            self._rebuild()

    def _strings(self) -> Tuple[str, ...]:
        return (self._frame_id,)

    def _compile(self, compiler: _Compiler) -> None:
        compiler.primitives('i')
        compiler.primitives('I')
        self._frame_bytes = compiler.string(self._frame_id)
        compiler.primitives('d', sum(len(v) for v in self._PROBE))


class PoseStampedLayout(_StampedLayout):
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
        _set_stamp(message.header.stamp, stamp_ns)
        _fill(message.pose.position, 'xyz', position)
        _fill(message.pose.orientation, 'xyzw', orientation)
        return message


class TwistStampedLayout(_StampedLayout):
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
        _set_stamp(message.header.stamp, stamp_ns)
        _fill(message.twist.linear, 'xyz', linear)
        _fill(message.twist.angular, 'xyz', angular)
        return message


class OdometryLayout(_Layout):
    """
    nav_msgs/Odometry: ``pack(stamp_ns, position, orientation, linear, angular)``.

    The frame ids and the two covariances (36 doubles each, row-major) are held by the layout,
    as they change rarely; setting any of them compiles the layout again.

    :param frame_id: the header's frame id (the pose's frame).
    :param child_frame_id: the twist's frame.
    :param pose_covariance: the pose's covariance; zeros by default.
    :param twist_covariance: the twist's covariance; zeros by default.
    """

    message_type = Odometry
    _PROBE = ((0.0,) * 3, (0.0,) * 4, (0.0,) * 3, (0.0,) * 3)

    def __init__(self, frame_id: str, child_frame_id: str, *,
                 pose_covariance: Iterable[float] = ZERO_COVARIANCE,
                 twist_covariance: Iterable[float] = ZERO_COVARIANCE) -> None:
        super().__init__()
        self._frame_id = _frame_text('frame_id', frame_id)
        self._child_frame_id = _frame_text('child_frame_id', child_frame_id)
        self._pose_covariance = _covariance('pose_covariance', pose_covariance)
        self._twist_covariance = _covariance('twist_covariance', twist_covariance)
        self._rebuild()

    def configure(self, **changes) -> None:
        """
        Set any of ``frame_id``, ``child_frame_id``, ``pose_covariance``, ``twist_covariance``.

        The layout is compiled again once, and only if something changed.
        """
        checks = {'frame_id': _frame_text, 'child_frame_id': _frame_text,
                  'pose_covariance': _covariance, 'twist_covariance': _covariance}
        unknown = set(changes) - set(checks)
        if unknown:
            raise ValueError(f'unknown Odometry layout settings: {sorted(unknown)}')
        new = {name: checks[name](name, value) for name, value in changes.items()}
        if any(getattr(self, '_' + name) != value for name, value in new.items()):
            for name, value in new.items():
                setattr(self, '_' + name, value)
            self._rebuild()

    frame_id = property(lambda self: self._frame_id,
                        lambda self, value: self.configure(frame_id=value),
                        doc="The header's frame id.")
    child_frame_id = property(lambda self: self._child_frame_id,
                              lambda self, value: self.configure(child_frame_id=value),
                              doc="The twist's frame id.")
    pose_covariance = property(lambda self: self._pose_covariance,
                               lambda self, value: self.configure(pose_covariance=value),
                               doc="The pose's 6x6 covariance, row-major.")
    twist_covariance = property(lambda self: self._twist_covariance,
                                lambda self, value: self.configure(twist_covariance=value),
                                doc="The twist's 6x6 covariance, row-major.")

    def _strings(self) -> Tuple[str, ...]:
        return (self._frame_id, self._child_frame_id)

    def _compile(self, compiler: _Compiler) -> None:
        compiler.primitives('i')
        compiler.primitives('I')
        self._frame_bytes = compiler.string(self._frame_id)
        self._child_bytes = compiler.string(self._child_frame_id)
        compiler.primitives('d', 7)
        self._pose_covariance_bytes = compiler.doubles(self._pose_covariance)
        compiler.primitives('d', 6)
        self._twist_covariance_bytes = compiler.doubles(self._twist_covariance)

    def pack(self, stamp_ns: int, position: Vector, orientation: Vector, linear: Vector,
             angular: Vector) -> bytes:
        """
        Return the bytes of the odometry with this pose and twist.

        :raises ValueError: as ``PoseStampedLayout.pack``.
        """
        fields = (position, orientation, linear, angular)
        if self._struct is None:
            return self._fallback(stamp_ns, *fields)
        sec, nanosec = divmod(stamp_ns, NANOSECONDS_PER_SECOND)
        try:
            return self._struct.pack(
                ENCAPSULATION_LE, sec, nanosec, self._frame_bytes, self._child_bytes,
                *position, *orientation, self._pose_covariance_bytes,
                *linear, *angular, self._twist_covariance_bytes)
        except (struct.error, TypeError) as error:
            raise self._error(stamp_ns, fields, error) from None

    def message(self, stamp_ns: int, position: Vector, orientation: Vector, linear: Vector,
                angular: Vector) -> Odometry:
        message = Odometry()
        message.header.frame_id = self._frame_id
        message.child_frame_id = self._child_frame_id
        _set_stamp(message.header.stamp, stamp_ns)
        _fill(message.pose.pose.position, 'xyz', position)
        _fill(message.pose.pose.orientation, 'xyzw', orientation)
        message.pose.covariance = list(self._pose_covariance)
        _fill(message.twist.twist.linear, 'xyz', linear)
        _fill(message.twist.twist.angular, 'xyz', angular)
        message.twist.covariance = list(self._twist_covariance)
        return message


class ClockLayout(_Layout):
    """rosgraph_msgs/Clock: ``pack(stamp_ns)``, the 12 bytes of one time."""

    message_type = Clock

    def __init__(self) -> None:
        super().__init__()
        self._rebuild()

    def _strings(self) -> Tuple[str, ...]:
        return ()

    def _compile(self, compiler: _Compiler) -> None:
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
        _set_stamp(message.clock, stamp_ns)
        return message


def same_bytes_but_padding(data: bytes, expected: bytes, padding: Iterable[int]) -> bool:
    """Return whether ``data`` and ``expected`` have one length and agree outside ``padding``."""
    if len(data) != len(expected):
        return False
    data, expected = bytearray(data), bytearray(expected)
    for index in padding:
        data[index] = expected[index] = 0
    return data == expected


# Decoding a raw PointStamped.

_REPRESENTATIONS = {b'\x00\x00': '>', b'\x00\x01': '<'}  # CDR_BE, CDR_LE (XCDR1 plain)


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


class Refusal(NamedTuple):
    """Why some bytes are not a PointStamped this decoder reads."""

    reason: str


def decode_point_stamped(data: object) -> Union[PointStampedFields, Refusal]:
    """
    Return the fields of the raw geometry_msgs/PointStamped ``data``, or why it is refused.

    Reads plain CDR (XCDR1) of either byte order, as any ROS 2 middleware sends it, and is
    stricter than Fast CDR where the bytes break the format: it refuses a string whose length is
    0, that has no terminating NUL or a NUL inside, or that is not UTF-8 (Fast CDR accepts the
    first three, and rclpy replaces bad UTF-8), and any other encapsulation (XCDR2, parameter
    lists). Bytes after the message are ignored, as Fast CDR ignores them. Whatever it accepts,
    ``deserialize_message`` reads as the same fields.

    :param data: ``bytes``, ``bytearray`` or ``memoryview``; anything else is refused.
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
    point_start = text_end + (-(text_end - start) % 8)
    if point_start + 24 > size:
        return Refusal(f'truncated: {size} bytes end before the point')
    x, y, z = struct.unpack_from(order + '3d', data, point_start)
    return PointStampedFields(frame_id, sec, nanosec, x, y, z)


def fields_of(message: PointStamped) -> PointStampedFields:
    """Return the fields of an rclpy PointStamped, as ``decode_point_stamped`` gives them."""
    header, point = message.header, message.point
    return PointStampedFields(header.frame_id, header.stamp.sec, header.stamp.nanosec,
                              point.x, point.y, point.z)
