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
The precompiled CDR layouts write what rclpy serializes, and the raw PointStamped decoder.

The reference is rclpy itself: ``serialize_message`` of a message the test fills field by field
(not the layout's own ``message``), and ``deserialize_message`` of the layout's bytes. rmw
leaves stale bytes in the padding, so the two byte strings are compared outside the layout's
padding; that the padding sits where CDR puts it is what makes every other byte agree and the
round trip give back every field.
"""

import math
import struct

from geometry_msgs.msg import PointStamped, PoseStamped, TwistStamped, WrenchStamped
from hypothesis import example, given, settings, strategies as st
from nav_msgs.msg import Odometry
import pytest
from rclpy.serialization import deserialize_message, serialize_message
from rosgraph_msgs.msg import Clock
from sensor_msgs.msg import JointState

from mouse_constraint_ros.wire.cdr.clock import ClockLayout
from mouse_constraint_ros.wire.cdr.geometry import (PoseStampedLayout, TwistStampedLayout,
                                                    WrenchStampedLayout)
from mouse_constraint_ros.wire.cdr.joint_state import JointStateLayout
from mouse_constraint_ros.wire.cdr.odometry import OdometryLayout
from mouse_constraint_ros.wire.cdr.point_stamped import (decode_point_stamped, fields_of,
                                                         PointStampedFields)
from mouse_constraint_ros.wire.cdr.stamped import decode_stamped, POSE, Refusal, TWIST

NS = 1_000_000_000
INT32 = 2 ** 31

# Doubles with NaN (any payload), infinities, signed zeros, subnormals and the extremes.
doubles = st.floats(allow_nan=True, allow_infinity=True) | st.sampled_from(
    [math.nan, -math.nan, math.inf, -math.inf, -0.0, 0.0, 5e-324, -5e-324,
     2.2250738585072014e-308, 1.7976931348623157e308, -1.7976931348623157e308])
vector3 = st.tuples(doubles, doubles, doubles)
vector4 = st.tuples(doubles, doubles, doubles, doubles)
# Frame ids: empty, 1 to 40 characters of any plane (NUL and lone surrogates aside: rclpy cuts
# at a NUL and cannot encode a surrogate; both have their own tests), non-ASCII ones often.
frame_characters = st.characters(blacklist_characters='\x00', blacklist_categories=('Cs',))
frames = (st.just('') | st.text(frame_characters, min_size=1, max_size=40)
          | st.text(st.characters(min_codepoint=0x80, blacklist_categories=('Cs',)),
                    min_size=1, max_size=40))
# Every stamp whose seconds fit the int32 of builtin_interfaces/Time.
stamps = st.integers(min_value=-INT32 * NS, max_value=INT32 * NS - 1)
covariances = st.lists(doubles, min_size=36, max_size=36)

SETTINGS = settings(max_examples=150, deadline=None)


def bits(value: float) -> bytes:
    """Return the IEEE 754 bytes of ``value``: equal bits, NaN payload and sign of zero too."""
    return struct.pack('<d', value)


def same_doubles(got, expected) -> bool:
    return len(got) == len(expected) and all(
        bits(a) == bits(b) for a, b in zip(got, expected))


def stamp_of(stamp_ns: int):
    return divmod(stamp_ns, NS)


def set_header(header, stamp_ns: int, frame_id: str) -> None:
    header.stamp.sec, header.stamp.nanosec = stamp_of(stamp_ns)
    header.frame_id = frame_id


def assert_same_bytes(packed: bytes, message, padding) -> None:
    """``packed`` is ``serialize_message(message)`` outside ``padding``, and zeros inside."""
    expected = serialize_message(message)
    assert len(packed) == len(expected)
    outside = [i for i in range(len(expected)) if i not in set(padding)]
    assert [packed[i] for i in outside] == [expected[i] for i in outside]
    assert all(packed[i] == 0 for i in padding)


def assert_header(header, stamp_ns: int, frame_id: str) -> None:
    assert (header.stamp.sec, header.stamp.nanosec) == stamp_of(stamp_ns)
    assert header.frame_id == frame_id


def xyz(v):
    return (v.x, v.y, v.z)


def xyzw(q):
    return (q.x, q.y, q.z, q.w)


@SETTINGS
@given(frame=frames, stamp_ns=stamps, position=vector3, orientation=vector4)
@example(frame='', stamp_ns=0, position=(-0.0, math.nan, math.inf),
         orientation=(5e-324, -math.inf, 1e308, -0.0))
def test_pose_stamped_bytes_are_rclpy_bytes(frame, stamp_ns, position, orientation):
    layout = PoseStampedLayout(frame)
    assert layout.precompiled
    packed = layout.pack(stamp_ns, position, orientation)
    message = PoseStamped()
    set_header(message.header, stamp_ns, frame)
    message.pose.position.x, message.pose.position.y, message.pose.position.z = position
    o = message.pose.orientation
    o.x, o.y, o.z, o.w = orientation
    assert_same_bytes(packed, message, layout.padding)

    back = deserialize_message(packed, PoseStamped)
    assert_header(back.header, stamp_ns, frame)
    assert same_doubles(xyz(back.pose.position), position)
    assert same_doubles(xyzw(back.pose.orientation), orientation)


@SETTINGS
@given(frame=frames, stamp_ns=stamps, linear=vector3, angular=vector3)
def test_twist_stamped_bytes_are_rclpy_bytes(frame, stamp_ns, linear, angular):
    layout = TwistStampedLayout(frame)
    assert layout.precompiled
    packed = layout.pack(stamp_ns, linear, angular)
    message = TwistStamped()
    set_header(message.header, stamp_ns, frame)
    message.twist.linear.x, message.twist.linear.y, message.twist.linear.z = linear
    message.twist.angular.x, message.twist.angular.y, message.twist.angular.z = angular
    assert_same_bytes(packed, message, layout.padding)

    back = deserialize_message(packed, TwistStamped)
    assert_header(back.header, stamp_ns, frame)
    assert same_doubles(xyz(back.twist.linear), linear)
    assert same_doubles(xyz(back.twist.angular), angular)


@SETTINGS
@given(frame=frames, stamp_ns=stamps, force=vector3, torque=vector3)
def test_wrench_stamped_bytes_are_rclpy_bytes(frame, stamp_ns, force, torque):
    layout = WrenchStampedLayout(frame)
    assert layout.precompiled
    packed = layout.pack(stamp_ns, force, torque)
    message = WrenchStamped()
    set_header(message.header, stamp_ns, frame)
    message.wrench.force.x, message.wrench.force.y, message.wrench.force.z = force
    message.wrench.torque.x, message.wrench.torque.y, message.wrench.torque.z = torque
    assert_same_bytes(packed, message, layout.padding)

    back = deserialize_message(packed, WrenchStamped)
    assert_header(back.header, stamp_ns, frame)
    assert same_doubles(xyz(back.wrench.force), force)
    assert same_doubles(xyz(back.wrench.torque), torque)


@SETTINGS
@given(frame=frames, child=frames, stamp_ns=stamps, position=vector3, orientation=vector4,
       linear=vector3, angular=vector3, pose_covariance=covariances,
       twist_covariance=covariances)
def test_odometry_bytes_are_rclpy_bytes(frame, child, stamp_ns, position, orientation, linear,
                                        angular, pose_covariance, twist_covariance):
    layout = OdometryLayout(frame, child, pose_covariance=pose_covariance,
                            twist_covariance=twist_covariance)
    assert layout.precompiled
    packed = layout.pack(stamp_ns, position, orientation, linear, angular)
    message = Odometry()
    set_header(message.header, stamp_ns, frame)
    message.child_frame_id = child
    pose, twist = message.pose, message.twist
    pose.pose.position.x, pose.pose.position.y, pose.pose.position.z = position
    o = pose.pose.orientation
    o.x, o.y, o.z, o.w = orientation
    pose.covariance = pose_covariance
    twist.twist.linear.x, twist.twist.linear.y, twist.twist.linear.z = linear
    twist.twist.angular.x, twist.twist.angular.y, twist.twist.angular.z = angular
    twist.covariance = twist_covariance
    assert_same_bytes(packed, message, layout.padding)

    back = deserialize_message(packed, Odometry)
    assert_header(back.header, stamp_ns, frame)
    assert back.child_frame_id == child
    assert same_doubles(xyz(back.pose.pose.position), position)
    assert same_doubles(xyzw(back.pose.pose.orientation), orientation)
    assert same_doubles(list(back.pose.covariance), pose_covariance)
    assert same_doubles(xyz(back.twist.twist.linear), linear)
    assert same_doubles(xyz(back.twist.twist.angular), angular)
    assert same_doubles(list(back.twist.covariance), twist_covariance)


@SETTINGS
@given(names=st.lists(frames, min_size=1, max_size=12), stamp_ns=stamps, data=st.data())
@example(names=['panda_joint1', 'panda_finger_joint2'], stamp_ns=0, data=None)
def test_joint_state_bytes_are_rclpy_bytes(names, stamp_ns, data):
    count = len(names)
    if data is None:
        fields = [(math.nan, -0.0)] * 3
    else:
        fields = [data.draw(st.lists(doubles, min_size=count, max_size=count)) for _ in range(3)]
    layout = JointStateLayout(names)
    assert layout.precompiled
    packed = layout.pack(stamp_ns, *fields)
    message = JointState()
    set_header(message.header, stamp_ns, '')
    message.name = list(names)
    message.position, message.velocity, message.effort = (list(f) for f in fields)
    assert_same_bytes(packed, message, layout.padding)

    back = deserialize_message(packed, JointState)
    assert_header(back.header, stamp_ns, '')
    assert list(back.name) == list(names)
    for got, expected in zip((back.position, back.velocity, back.effort), fields):
        assert same_doubles(list(got), expected)


def test_a_joint_state_of_no_joints_is_rclpys_own_bytes():
    layout = JointStateLayout([])
    packed = layout.pack(5 * NS + 7, (), (), ())
    message = JointState()
    set_header(message.header, 5 * NS + 7, '')
    assert packed == serialize_message(message)


def test_joint_state_values_not_one_per_name_are_a_value_error():
    layout = JointStateLayout(['shoulder', 'elbow'])
    with pytest.raises(ValueError, match='JointState'):
        layout.pack(0, (0.0,), (0.0, 0.0), (0.0, 0.0))


@SETTINGS
@given(stamp_ns=stamps)
def test_clock_bytes_are_rclpy_bytes(stamp_ns):
    layout = ClockLayout()
    assert layout.precompiled
    packed = layout.pack(stamp_ns)
    message = Clock()
    message.clock.sec, message.clock.nanosec = stamp_of(stamp_ns)
    assert packed == serialize_message(message)
    back = deserialize_message(packed, Clock)
    assert (back.clock.sec, back.clock.nanosec) == stamp_of(stamp_ns)


@SETTINGS
@given(first=frames, second=frames, stamp_ns=stamps, position=vector3, orientation=vector4)
def test_a_new_frame_recompiles_the_layout(first, second, stamp_ns, position, orientation):
    layout = PoseStampedLayout(first)
    layout.pack(stamp_ns, position, orientation)
    layout.frame_id = second
    back = deserialize_message(layout.pack(stamp_ns, position, orientation), PoseStamped)
    assert_header(back.header, stamp_ns, second)
    assert same_doubles(xyzw(back.pose.orientation), orientation)


@SETTINGS
@given(frames=st.tuples(frames, frames), stamp_ns=stamps, state=st.tuples(
    vector3, vector4, vector3, vector3), covariance=covariances)
def test_odometry_settings_recompile_the_layout(frames, stamp_ns, state, covariance):
    layout = OdometryLayout('a', 'b')
    layout.frame_id, layout.child_frame_id = frames
    layout.twist_covariance = covariance
    back = deserialize_message(layout.pack(stamp_ns, *state), Odometry)
    assert (back.header.frame_id, back.child_frame_id) == frames
    assert same_doubles(list(back.twist.covariance), covariance)
    assert same_doubles(xyz(back.twist.twist.angular), state[3])


@pytest.mark.parametrize('frame', ['a\x00b', '\x00', 'world\x00'])
def test_a_frame_with_a_nul_falls_back_to_rclpy(frame):
    """A NUL cuts an rclpy string: the layout steps aside and rclpy's own bytes go out."""
    layout = PoseStampedLayout(frame)
    assert not layout.precompiled
    message = PoseStamped()
    set_header(message.header, 7, frame)
    message.pose.orientation.w = 1.0
    assert layout.pack(7, (0.0, 0.0, 0.0), (0.0, 0.0, 0.0, 1.0)) == serialize_message(message)


def test_a_frame_that_is_not_utf8_is_refused():
    for layout_type in (PoseStampedLayout, TwistStampedLayout):
        with pytest.raises(ValueError, match='UTF-8'):
            layout_type('\udc80')
    with pytest.raises(ValueError, match='child_frame_id'):
        OdometryLayout('odom', '\ud800')
    with pytest.raises(ValueError, match='str'):
        PoseStampedLayout(None)


@pytest.mark.parametrize('stamp_ns', [INT32 * NS, -INT32 * NS - 1])
def test_a_stamp_beyond_int32_seconds_is_a_value_error(stamp_ns):
    with pytest.raises(ValueError, match='stamped'):
        PoseStampedLayout('world').pack(stamp_ns, (0.0,) * 3, (0.0,) * 4)


@pytest.mark.parametrize('position, orientation', [
    ((0.0,) * 2, (0.0,) * 4), ((0.0,) * 3, (0.0,) * 5), ((0.0,) * 3, ('x', 0.0, 0.0, 1.0))])
def test_a_field_of_the_wrong_shape_is_a_value_error(position, orientation):
    with pytest.raises(ValueError, match='cannot pack'):
        PoseStampedLayout('world').pack(0, position, orientation)


def test_a_covariance_of_the_wrong_size_is_a_value_error():
    with pytest.raises(ValueError, match='36'):
        OdometryLayout('odom', 'base', pose_covariance=[0.0] * 35)


# The PointStamped decoder.

def point_stamped(frame: str, stamp_ns: int, point) -> PointStamped:
    message = PointStamped()
    set_header(message.header, stamp_ns, frame)
    message.point.x, message.point.y, message.point.z = point
    return message


def same_fields(got: PointStampedFields, expected: PointStampedFields) -> bool:
    return got[:3] == expected[:3] and same_doubles(got[3:], expected[3:])


@SETTINGS
@given(frame=frames, stamp_ns=stamps, point=vector3)
def test_decoder_reads_what_rclpy_writes(frame, stamp_ns, point):
    data = serialize_message(point_stamped(frame, stamp_ns, point))
    decoded = decode_point_stamped(data)
    assert isinstance(decoded, PointStampedFields)
    assert same_fields(decoded, fields_of(deserialize_message(data, PointStamped)))
    assert decoded.stamp_ns == stamp_ns and same_doubles(decoded.point, point)
    assert same_fields(decode_point_stamped(memoryview(bytearray(data))), decoded)


@SETTINGS
@given(frame=frames, stamp_ns=stamps, point=vector3)
def test_decoder_reads_big_endian_cdr(frame, stamp_ns, point):
    """A big-endian writer's bytes: rclpy's, with every field turned around by hand."""
    little = serialize_message(point_stamped(frame, stamp_ns, point))
    encoded = frame.encode('utf-8')
    end = 16 + len(encoded) + 1
    point_start = end + (-(end - 4) % 8)
    big = bytearray(little)
    big[0:2] = b'\x00\x00'
    for start, size in ((4, 4), (8, 4), (12, 4),
                        (point_start, 8), (point_start + 8, 8), (point_start + 16, 8)):
        big[start:start + size] = little[start:start + size][::-1]
    decoded = decode_point_stamped(bytes(big))
    assert isinstance(decoded, PointStampedFields)
    assert same_fields(decoded, fields_of(deserialize_message(bytes(big), PointStamped)))
    assert decoded.stamp_ns == stamp_ns and same_doubles(decoded.point, point)


@SETTINGS
@given(frame=frames, stamp_ns=stamps, point=vector3, data=st.data())
def test_decoder_refuses_every_truncation(frame, stamp_ns, point, data):
    whole = serialize_message(point_stamped(frame, stamp_ns, point))
    cut = data.draw(st.integers(min_value=0, max_value=len(whole) - 1))
    assert isinstance(decode_point_stamped(whole[:cut]), Refusal)


def mutated(whole: bytes, draw) -> bytes:
    """Return ``whole`` with a few random overwrites, a cut or some junk appended."""
    data = bytearray(whole)
    for _ in range(draw(st.integers(min_value=1, max_value=4))):
        index = draw(st.integers(min_value=0, max_value=len(data) - 1))
        data[index] = draw(st.integers(min_value=0, max_value=255))
    if draw(st.booleans()):
        data = data[:draw(st.integers(min_value=0, max_value=len(data)))]
    return bytes(data) + draw(st.binary(max_size=8))


@settings(max_examples=400, deadline=None)
@given(frame=frames, stamp_ns=stamps, point=vector3, data=st.data())
def test_decoder_accepts_only_what_rclpy_reads_the_same(frame, stamp_ns, point, data):
    """Damaged bytes: refused, or read exactly as deserialize_message reads them."""
    damaged = mutated(serialize_message(point_stamped(frame, stamp_ns, point)), data.draw)
    decoded = decode_point_stamped(damaged)
    if isinstance(decoded, Refusal):
        assert decoded.reason
        return
    assert same_fields(decoded, fields_of(deserialize_message(damaged, PointStamped)))


@settings(max_examples=300, deadline=None)
@given(garbage=st.binary(max_size=80))
def test_decoder_never_raises_on_garbage(garbage):
    decoded = decode_point_stamped(garbage)
    if isinstance(decoded, Refusal):
        return
    assert same_fields(decoded, fields_of(deserialize_message(garbage, PointStamped)))


@pytest.mark.parametrize('edit, reason', [
    (lambda b: b[:10], 'truncated'),
    (lambda b: b'\x00\x07' + b[2:], 'encapsulation'),
    (lambda b: b[:12] + b'\x00\x00\x00\x00' + b[16:], 'length 0'),
    (lambda b: b[:18] + b'x' + b[19:], 'no terminating NUL'),
    (lambda b: b[:16] + b'\x00' + b[17:], 'NUL before'),
    (lambda b: b[:16] + b'\xff' + b[17:], 'not UTF-8'),
    (lambda b: b[:12] + b'\xff\xff\xff\x7f' + b[16:], 'runs past'),
])
def test_decoder_says_why(edit, reason):
    whole = serialize_message(point_stamped('ab', 5, (1.0, 2.0, 3.0)))
    refusal = decode_point_stamped(edit(whole))
    assert isinstance(refusal, Refusal) and reason in refusal.reason


@pytest.mark.parametrize('value', [None, 'abc', 3, [0, 1, 0, 0], object()])
def test_decoder_refuses_what_is_not_bytes(value):
    refusal = decode_point_stamped(value)
    assert isinstance(refusal, Refusal) and 'expected bytes' in refusal.reason


def pose_and_twist(frame: str, stamp_ns: int, values) -> tuple:
    """Return a PoseStamped of ``values[:7]`` and a TwistStamped of ``values[7:]``."""
    pose, twist = PoseStamped(), TwistStamped()
    for message in (pose, twist):
        set_header(message.header, stamp_ns, frame)
    p, q = pose.pose.position, pose.pose.orientation
    p.x, p.y, p.z, q.x, q.y, q.z, q.w = values[:7]
    linear, angular = twist.twist.linear, twist.twist.angular
    linear.x, linear.y, linear.z, angular.x, angular.y, angular.z = values[7:]
    return pose, twist


def stamped_fields(message) -> tuple:
    """Return the header and the doubles of an rclpy pose or twist, as decode_stamped does."""
    header = message.header
    if isinstance(message, PoseStamped):
        p, q = message.pose.position, message.pose.orientation
        values = (p.x, p.y, p.z, q.x, q.y, q.z, q.w)
    else:
        linear, angular = message.twist.linear, message.twist.angular
        values = (linear.x, linear.y, linear.z, angular.x, angular.y, angular.z)
    return header.frame_id, header.stamp.sec, header.stamp.nanosec, values


@settings(max_examples=300, deadline=None)
@given(frame=frames, stamp_ns=stamps, values=st.lists(doubles, min_size=13, max_size=13),
       data=st.data())
def test_the_stamped_decoder_reads_poses_and_twists_as_rclpy_does(frame, stamp_ns, values,
                                                                  data):
    """Whole, each reads as deserialize_message reads it; damaged, refused or read the same."""
    for message, count in zip(pose_and_twist(frame, stamp_ns, values), (POSE, TWIST)):
        whole = serialize_message(message)
        decoded = decode_stamped(whole, count)
        expected = stamped_fields(message)
        assert decoded[:3] == expected[:3] and same_doubles(decoded.values, expected[3])
        damaged = mutated(whole, data.draw)
        decoded = decode_stamped(damaged, count)
        if isinstance(decoded, Refusal):
            assert decoded.reason
            continue
        expected = stamped_fields(deserialize_message(damaged, type(message)))
        assert decoded[:3] == expected[:3] and same_doubles(decoded.values, expected[3])
