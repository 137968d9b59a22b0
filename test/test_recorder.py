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
``mouse_record``: the CSV holds what was published, the PNG is a real image, the MCAP reads back.

One recording (the installed executable against the node in this process, the anchor read from
the node's parameter) serves the file tests; the rest are pure functions and the failure paths.
"""

import csv
import io
import math
from pathlib import Path
import signal
import subprocess
import sys
import threading
import time

from geometry_msgs.msg import PointStamped
from geometry_msgs.msg import PoseStamped
from geometry_msgs.msg import PoseWithCovarianceStamped
from geometry_msgs.msg import TwistStamped
import numpy as np
from PIL import Image
import pytest
from rcl_interfaces.msg import Parameter as ParameterMessage
from rcl_interfaces.msg import ParameterEvent
from rcl_interfaces.msg import ParameterType
from rcl_interfaces.msg import ParameterValue
from rclpy.parameter import Parameter
from rclpy.qos import QoSProfile
from rclpy.qos import ReliabilityPolicy
from rclpy.serialization import deserialize_message
from rclpy.serialization import serialize_message
from scipy.spatial.transform import Rotation
from service_msgs.msg import ServiceEventInfo
from std_srvs.srv import Trigger
from visualization_msgs.msg import Marker
import yaml

from mouse_constraint_ros.cli.record import parse_arguments
from mouse_constraint_ros.node.mouse_constraint_node import MouseConstraintNode
from mouse_constraint_ros.recording.capture import fetch_start
from mouse_constraint_ros.recording.capture import Progress
from mouse_constraint_ros.recording.capture import progress_bar
from mouse_constraint_ros.recording.capture import Recorder
from mouse_constraint_ros.recording.figure import FIGURE_DPI
from mouse_constraint_ros.recording.figure import FIGURE_INCHES
from mouse_constraint_ros.recording.mcap_file import message_definition
from mouse_constraint_ros.recording.mcap_file import schema_name
from mouse_constraint_ros.recording.missing_ticks import Grid
from mouse_constraint_ros.recording.missing_ticks import missing_ticks
from mouse_constraint_ros.recording.outputs import check_writable
from mouse_constraint_ros.recording.outputs import output_paths
from mouse_constraint_ros.recording.received import parameter_changes
from mouse_constraint_ros.recording.received import PARAMETER_EVENTS_TOPIC
from mouse_constraint_ros.recording.received import Received
from mouse_constraint_ros.recording.recording_files import FLUSH_SECONDS
from mouse_constraint_ros.recording.rows import COLUMNS
from mouse_constraint_ros.recording.rows import SETTLE_NS
from mouse_constraint_ros.recording.rows import tick_rows
from mouse_constraint_ros.timing.publish_ticks import PublishTicks
from mouse_constraint_ros.timing.spin import StopRequest
from mouse_constraint_ros.wire.messages import point_message
from mouse_constraint_ros.wire.messages import stamp_nanoseconds
from test_support.ros_harness import RosHarness

# The MCAP readers (mcap, mcap-ros2-support: requirements/viz.txt, package.xml's test_depend).
MCAP_MISSING = 'the mcap and mcap-ros2-support packages read the MCAP files: not installed'
make_reader = pytest.importorskip('mcap.reader', reason=MCAP_MISSING).make_reader
NonSeekingReader = pytest.importorskip('mcap.reader', reason=MCAP_MISSING).NonSeekingReader
EndOfFile = pytest.importorskip('mcap.exceptions', reason=MCAP_MISSING).EndOfFile
DecoderFactory = pytest.importorskip('mcap_ros2.decoder', reason=MCAP_MISSING).DecoderFactory

BIN = Path(sys.executable).parent
ANCHOR = (0.1, -0.05, 0.02)
RATE = 200.0
DURATION = 1.0


def xyz(vector) -> tuple:
    """Return the x, y, z of a message field."""
    return (vector.x, vector.y, vector.z)


def target_at(k: int) -> tuple:
    """Return the k-th target the test publishes: a slow circle around (0, 0, 1)."""
    return (0.2 * math.cos(0.3 * k), 0.2 * math.sin(0.3 * k), 1.0)


@pytest.fixture(scope='module')
def harness():
    """Yield a context with the node (anchor ANCHOR) spinning in this process; shut it down."""
    ros = RosHarness()
    ros.add(MouseConstraintNode(context=ros.context, parameter_overrides=[
        Parameter('rate_hz', value=RATE), Parameter('anchor', value=list(ANCHOR)),
        Parameter('marker_rate_hz', value=0.0), Parameter('diagnostics_rate_hz', value=0.0),
        Parameter('linear_damping', value=2.0), Parameter('angular_damping', value=2.0)]))
    yield ros
    ros.shutdown()


def start_recorder(*arguments: str):
    """Start ``mouse_record`` with ``arguments``: the process, its stderr lines, their reader."""
    process = subprocess.Popen([str(BIN / 'mouse_record'), *arguments], stdout=subprocess.DEVNULL,
                               stderr=subprocess.PIPE, text=True)
    lines = []
    reader = threading.Thread(target=lambda: lines.extend(process.stderr), daemon=True)
    reader.start()
    return process, lines, reader


def run_recorder(ros, arguments, publisher=None, signal_after=None, timeout=40.0):
    """
    Run ``mouse_record`` while the node spins, publishing a target every 0.05 s if asked.

    :param signal_after: send SIGINT this many seconds after the progress bar starts.
    :returns: the exit status, stderr and the targets published.
    """
    process = subprocess.Popen([str(BIN / 'mouse_record'), *arguments], stdout=subprocess.DEVNULL,
                               stderr=subprocess.PIPE, text=True)
    lines = []
    reader = threading.Thread(target=lambda: lines.extend(process.stderr), daemon=True)
    reader.start()
    published, started, deadline = [], None, time.monotonic() + timeout
    try:
        while process.poll() is None:
            assert time.monotonic() < deadline, 'mouse_record did not finish'
            ros.spin_for(0.05)
            # Targets go out once the recorder's subscription has matched too, as make demo's
            # do (volatile: what is sent before it matched never reaches it).
            if publisher is not None and publisher.get_subscription_count() >= 2:
                target = target_at(len(published))
                publisher.publish(point_message(target, 'world', 0))
                published.append(target)
            if signal_after is None:
                continue
            if started is None and any(line.startswith('recording') for line in lines):
                started = time.monotonic()
            if started is not None and time.monotonic() - started > signal_after:
                process.send_signal(signal.SIGINT)
                signal_after = None
    finally:
        if process.poll() is None:
            process.kill()
        process.wait()
        reader.join(timeout=5.0)
    return process.returncode, ''.join(lines), published


@pytest.fixture(scope='module')
def recording(harness, tmp_path_factory):
    """Record DURATION s with --mcap, the anchor from the node; return what was sent and kept."""
    ros = harness
    poses = ros.collect(PoseStamped, 'pose', depth=100000)
    twists = ros.collect(TwistStamped, 'twist', depth=100000)
    publisher = ros.probe.create_publisher(PointStamped, 'target', 10)
    assert ros.spin_until(lambda: publisher.get_subscription_count() > 0 and poses)
    prefix = tmp_path_factory.mktemp('recording') / 'sub' / 'run'
    status, stderr, targets = run_recorder(
        ros, ['--duration', str(DURATION), '--output', str(prefix), '--mcap', '--timeout', '20'],
        publisher)
    return {'status': status, 'stderr': stderr, 'prefix': prefix, 'targets': targets,
            'poses': {stamp_nanoseconds(p.header.stamp): p for p in poses},
            'twists': {stamp_nanoseconds(t.header.stamp): t for t in twists}}


def read_csv(path: Path) -> list:
    """Return the CSV's rows as dicts, numbers parsed, '' as None."""
    with open(path, newline='') as stream:
        reader = csv.DictReader(line for line in stream if not line.startswith('#'))
        assert tuple(reader.fieldnames) == COLUMNS
        return [{k: (None if v == '' else int(v) if k == 'stamp_ns' else float(v))
                 for k, v in row.items()} for row in reader]


def test_recorder_exits_cleanly_and_reports(recording):
    """Exit 0, a progress bar, the anchor from the node's parameter, the files it wrote."""
    assert recording['status'] == 0, recording['stderr']
    stderr = recording['stderr']
    assert 'recording [' in stderr and '##############################]' in stderr
    assert f'anchor {ANCHOR} m (body frame) from mouse_constraint' in stderr
    assert 'wrote' in stderr and 'Traceback' not in stderr


def test_csv_matches_what_was_published(recording):
    """Each row is a published pose and twist of one stamp, bit for bit, plus derived columns."""
    rows = read_csv(recording['prefix'].with_suffix('.csv'))
    poses, twists = recording['poses'], recording['twists']
    stamps = np.array([row['stamp_ns'] for row in rows])
    assert np.all(np.diff(stamps) > 0)
    # At least DURATION of the node's ticks, one row per tick with none beyond them; a loaded
    # machine may let the recorder run a little past DURATION before it sees the time.
    span = (stamps[-1] - stamps[0]) * 1e-9
    assert span >= DURATION - 0.25
    ticks = round(span * RATE) + 1
    assert 0.75 * ticks <= len(rows) <= ticks
    np.testing.assert_allclose([row['time'] for row in rows], (stamps - stamps[0]) * 1e-9)
    targets = recording['targets']
    with_target = 0
    for row in rows:
        pose, twist = poses[row['stamp_ns']], twists[row['stamp_ns']]
        q = pose.pose.orientation
        assert (row['x'], row['y'], row['z']) == xyz(pose.pose.position)
        assert (row['qx'], row['qy'], row['qz'], row['qw']) == (q.x, q.y, q.z, q.w)
        assert (row['vx'], row['vy'], row['vz']) == xyz(twist.twist.linear)
        assert (row['wx'], row['wy'], row['wz']) == xyz(twist.twist.angular)
        anchor = np.array(xyz(pose.pose.position)) + Rotation.from_quat(
            [q.x, q.y, q.z, q.w]).apply(ANCHOR)
        np.testing.assert_allclose((row['anchor_x'], row['anchor_y'], row['anchor_z']), anchor,
                                   atol=1e-12)
        assert row['speed'] == pytest.approx(np.linalg.norm(xyz(twist.twist.linear)))
        assert row['angular_speed'] == pytest.approx(np.linalg.norm(xyz(twist.twist.angular)))
        if row['target_x'] is not None:
            with_target += 1
            target = (row['target_x'], row['target_y'], row['target_z'])
            # A published target, or a point between two consecutive ones: the stream's path.
            assert on_path(target, targets)
            assert row['anchor_error'] == pytest.approx(np.linalg.norm(anchor - target))
    # From the first row with a target on, every row holds one (the node keeps it): the rows
    # before it are the recorder's ticks before the first target reached it.
    first = next(index for index, row in enumerate(rows) if row['target_x'] is not None)
    assert with_target == len(rows) - first and with_target > 0.5 * len(rows)


def on_path(point, targets) -> bool:
    """Return whether ``point`` is one of ``targets`` or between two consecutive ones."""
    p = np.asarray(point)
    for a, b in zip(np.asarray(targets), np.asarray(targets)[1:]):
        share = np.clip(np.dot(p - a, b - a) / max(np.dot(b - a, b - a), 1e-300), 0.0, 1.0)
        if np.linalg.norm(a + share * (b - a) - p) < 1e-12:
            return True
    return tuple(point) in set(targets)


def test_png_is_a_valid_image_of_the_expected_size(recording):
    """The figure is a PNG of FIGURE_INCHES at FIGURE_DPI with something drawn on it."""
    path = recording['prefix'].with_suffix('.png')
    with Image.open(path) as image:
        image.verify()
    with Image.open(path) as image:
        assert image.format == 'PNG'
        assert image.size == (FIGURE_INCHES[0] * FIGURE_DPI, FIGURE_INCHES[1] * FIGURE_DPI)
        pixels = np.asarray(image.convert('RGB')).astype(np.uint32)
    colours = np.unique((pixels[..., 0] << 16) | (pixels[..., 1] << 8) | pixels[..., 2])
    assert len(colours) > 50


def test_mcap_reads_back_with_the_mcap_library(recording):
    """ros2 profile, cdr on ros2msg schemas, the resolved topics; messages decode as published."""
    with open(recording['prefix'].with_suffix('.mcap'), 'rb') as stream:
        reader = make_reader(stream, decoder_factories=[DecoderFactory()])
        assert reader.get_header().profile == 'ros2'
        summary = reader.get_summary()
        channels = {c.topic: c for c in summary.channels.values()}
        assert set(channels) == {'/target', '/pose', '/twist', '/grab', '/wrench',
                                 '/parameter_events', '/mouse_constraint/reset/_service_event',
                                 '/mouse_constraint/release/_service_event'}
        for topic, message_type in (('/target', PointStamped), ('/pose', PoseStamped),
                                    ('/twist', TwistStamped)):
            channel = channels[topic]
            schema = summary.schemas[channel.schema_id]
            assert (channel.message_encoding, schema.encoding) == ('cdr', 'ros2msg')
            assert schema.name == schema_name(message_type)
            [offer] = yaml.safe_load(channel.metadata['offered_qos_profiles'])
            assert offer['reliability'] == 'reliable' and offer['durability'] == 'volatile'
        decoded = {topic: [] for topic in channels}
        for _, channel, message, ros_message in reader.iter_decoded_messages():
            decoded[channel.topic].append((message, ros_message))
    poses = recording['poses']
    # Every tick of the CSV, as received (the node in this process may drop ticks under load).
    rows = read_csv(recording['prefix'].with_suffix('.csv'))
    stamps = {row['stamp_ns'] for row in rows}
    assert len(rows) >= 0.75 * DURATION * RATE
    assert stamps <= {stamp_nanoseconds(pose.header.stamp) for _, pose in decoded['/pose']}
    for message, pose in decoded['/pose']:
        stamp = pose.header.stamp.sec * 1_000_000_000 + pose.header.stamp.nanosec
        published = poses[stamp]
        assert xyz(pose.pose.position) == xyz(published.pose.position)
        assert pose.header.frame_id == 'world'
        # The raw bytes are the CDR rclpy itself reads.
        assert deserialize_message(message.data, PoseStamped) == published
    targets = set(recording['targets'])
    assert decoded['/target'] and all(xyz(t.point) in targets for _, t in decoded['/target'])
    assert stamps <= {stamp_nanoseconds(twist.header.stamp) for _, twist in decoded['/twist']}


@pytest.mark.parametrize('message', [
    PoseWithCovarianceStamped(),
    Marker(ns='n', id=3, points=[point_message((1.0, 2.0, 3.0), '', 0).point] * 2,
           text='hello', frame_locked=True),
])
def test_message_definition_decodes_arrays_and_sequences(message):
    """Schemas built from the message classes decode fixed arrays, sequences, nested types."""
    if isinstance(message, PoseWithCovarianceStamped):
        message.pose.covariance = [float(i) for i in range(36)]
    message.header.frame_id = 'map'
    text = message_definition(type(message))
    factory = DecoderFactory()
    from mcap.records import Schema
    schema = Schema(id=1, name=schema_name(type(message)), encoding='ros2msg',
                    data=text.encode())
    decoded = factory.decoder_for('cdr', schema)(serialize_message(message))
    assert decoded.header.frame_id == 'map'
    if isinstance(message, Marker):
        assert [xyz(p) for p in decoded.points] == [(1.0, 2.0, 3.0)] * 2
        assert (decoded.text, decoded.id, decoded.frame_locked) == ('hello', 3, True)
    else:
        assert list(decoded.pose.covariance) == [float(i) for i in range(36)]


def test_tick_rows_join_pose_and_twist_and_follow_the_target_path():
    """
    Rows need a pose and a twist of one stamp; the target is where the target path is.

    Each unstamped target is placed at the stamp of the pose received before it: the first at
    10 ns, the second at 30 ns, a stream (0.25 s apart at most) whose line the rows follow.
    """
    def pose(ns):
        message = PoseStamped()
        message.header.stamp.sec, message.header.stamp.nanosec = divmod(ns, 1_000_000_000)
        message.pose.orientation.w = 1.0
        message.pose.position.z = 1.0
        return Received('pose', ns, serialize_message(message))

    def twist(ns, vx=3.0):
        message = TwistStamped()
        message.header.stamp.sec, message.header.stamp.nanosec = divmod(ns, 1_000_000_000)
        message.twist.linear.x = vx
        message.twist.linear.y = 4.0
        return Received('twist', ns, serialize_message(message))

    def target(point):
        return Received('target', 0, serialize_message(point_message(point, 'world', 0)))

    received = [pose(10), twist(10), target((1.0, 0.0, 1.0)), pose(20), twist(20), pose(30),
                target((0.0, 0.0, 1.0)), twist(30), twist(40)]
    rows = tick_rows(received, {'anchor': (1.0, 0.0, 0.0)})
    assert [row.stamp_ns for row in rows] == [10, 20, 30]
    assert [row.time for row in rows] == [0.0, 1e-8, 2e-8]
    assert [row.target for row in rows] == [None, (0.5, 0.0, 1.0), (0.0, 0.0, 1.0)]
    assert rows[0].anchor == (1.0, 0.0, 1.0)
    assert rows[0].anchor_error is None and rows[1].anchor_error == 0.5
    assert rows[0].speed == 5.0
    assert rows[0].fields()[-19:] == ['', '', '', '', 5.0, 0.0, 1.0, 0.0, 0.0, '', '', '', '',
                                      0.0, 0.0, 0.0, 0.0, 0.0, 0.0]
    assert all(row.body_anchor == (1.0, 0.0, 0.0) and row.grab is None for row in rows)


def test_tick_rows_read_a_stopped_stream_at_its_last_target_before_it_arrives():
    """
    A stamped stream that stops: the ticks between its last stamp and its arrival read it.

    Targets along x at 1 m/s, stamped every 20 ms, each received 3 ms after its stamp (after
    the poses of three later ticks); the stream stops at x = 0.1 m. From the first target's
    arrival on, each row's target is where the pointer was at its tick: on the line between
    two targets, then the last target from its stamp on, before it arrived too, never the
    target before it (20 mm back).
    """
    ms, start = 1_000_000, 5_000_000_000
    stamps = [start + 20 * ms * k for k in range(6)]
    received = []
    for tick in range(130):
        ns = start + tick * ms
        received += [state('pose', ns), state('twist', ns)]
        for k, stamp in enumerate(stamps):
            if ns == stamp + 3 * ms:
                message = point_message((0.02 * k, 0.0, 1.0), 'world', stamp)
                received.append(Received('target', ns, serialize_message(message)))
    rows = tick_rows(received, {'anchor': (0.0, 0.0, 0.0)})
    targets = {(row.stamp_ns - start) // ms: row.target for row in rows}
    assert sorted(targets) == list(range(130))
    assert all(targets[tick] is None for tick in range(4))
    for tick in range(4, 130):
        assert targets[tick] == pytest.approx((0.001 * min(tick, 100), 0.0, 1.0), abs=1e-12)


def anchor_event(node_name: str, anchor, stamp_ns: int = 0, name: str = 'anchor') -> Received:
    """Return a /parameter_events message of ``node_name`` that changes its anchor."""
    value = ParameterValue(type=ParameterType.PARAMETER_DOUBLE_ARRAY,
                           double_array_value=list(anchor))
    event = ParameterEvent(node=node_name, changed_parameters=[
        ParameterMessage(name=name, value=value)])
    event.stamp.sec, event.stamp.nanosec = divmod(stamp_ns, 1_000_000_000)
    return Received(PARAMETER_EVENTS_TOPIC, 0, serialize_message(event))


def state(kind: str, ns: int, position=(0.0, 0.0, 0.0)) -> Received:
    """Return a received pose (at ``position``, unturned) or twist (at rest) stamped ``ns``."""
    message = PoseStamped() if kind == 'pose' else TwistStamped()
    message.header.stamp.sec, message.header.stamp.nanosec = divmod(ns, 1_000_000_000)
    if kind == 'pose':
        message.pose.orientation.w = 1.0
        p = message.pose.position
        p.x, p.y, p.z = position
    return Received(kind, ns, serialize_message(message))


def point_received(topic: str, point) -> Received:
    """Return a received target or grab at ``point``."""
    return Received(topic, 0, serialize_message(point_message(point, 'world', 0)))


def service_event(key: str, success: bool = True, stamp_ns: int = 0) -> Received:
    """Return a received response event of the node's ``~/reset`` or ``~/release``."""
    event = Trigger.Event()
    event.info.event_type = ServiceEventInfo.RESPONSE_SENT
    event.info.stamp.sec, event.info.stamp.nanosec = divmod(stamp_ns, 1_000_000_000)
    event.response = [Trigger.Response(success=success, message='')]
    return Received(key, 0, serialize_message(event))


def test_tick_rows_take_a_grab_on_the_row_the_node_took_it():
    """
    A grab switches anchor, target and mark together, where the node took it.

    The grab comes before the node takes it: all switch on the first pose after the node's
    anchor change; the anchor error is the node's (zero there).
    """
    grabbed = (0.1, 0.0, 0.05)
    received = [state('pose', 10), state('twist', 10),
                point_received('target', (1.0, 0.0, 0.0)), point_received('grab', grabbed),
                state('pose', 20), state('twist', 20),
                anchor_event('/mouse_constraint', grabbed), state('pose', 30),
                state('twist', 30), state('pose', 40), state('twist', 40)]
    rows = tick_rows(received, {'anchor': (1.0, 0.0, 0.0)})
    assert [row.body_anchor for row in rows] == [(1.0, 0.0, 0.0)] * 2 + [grabbed] * 2
    assert [row.target for row in rows] == [None, (1.0, 0.0, 0.0), grabbed, grabbed]
    assert [row.anchor_error for row in rows] == [None, 0.0, 0.0, 0.0]
    assert [(row.grab, row.grab_taken) for row in rows] == [
        (None, None), (None, None), (grabbed, True), (None, None)]
    assert rows[2].fields()[-13:-6] == [*grabbed, *grabbed, 1]


def test_tick_rows_take_a_grab_whose_anchor_change_arrived_first():
    """
    The node's anchor change received before the grab it took (two topics, a loaded machine).

    The grab is taken from the change's row, as in the order the node acted; the configured
    anchor, which a reset restores (its world position the target, held), stays the one before
    the grab.
    """
    grabbed = (0.1, 0.0, 0.05)
    start = {'anchor': (1.0, 0.0, 0.0), 'hold_initial_anchor': True,
             'initial_position': (0.0, 0.0, 1.0), 'initial_orientation': (0.0, 0.0, 0.0, 1.0)}
    received = [state('pose', 10), state('twist', 10), point_received('target', (1.0, 0.0, 0.0)),
                anchor_event('/mouse_constraint', grabbed), point_received('grab', grabbed),
                state('pose', 20), state('twist', 20), service_event('reset'),
                anchor_event('/mouse_constraint', start['anchor']), state('pose', 30),
                state('twist', 30)]
    rows = tick_rows(received, start)
    assert [(row.grab, row.grab_taken) for row in rows] == [
        (None, None), (grabbed, True), (None, None)]
    assert [row.body_anchor for row in rows] == [start['anchor'], grabbed, start['anchor']]
    assert [row.target for row in rows[1:]] == [grabbed, (1.0, 0.0, 1.0)]
    # Arriving a pose late, the grab is still the change's: taken on that row.
    late = received[:4] + [state('pose', 20), state('twist', 20), received[4]] + received[7:]
    assert [(row.grab, row.grab_taken) for row in tick_rows(late, start)] == [
        (None, None), (grabbed, True), (None, None)]


def test_tick_rows_mark_an_ignored_grab_and_keep_the_target():
    """A grab with no anchor change of the node is marked ignored; target and anchor stay."""
    received = [state('pose', 10), state('twist', 10),
                point_received('target', (1.0, 0.0, 0.0)), point_received('grab', (5.0, 5.0, 5.0)),
                state('pose', 20), state('twist', 20),
                anchor_event('/mouse_constraint', (0.0, 1.0, 0.0)), state('pose', 30),
                state('twist', 30)]
    rows = tick_rows(received, {'anchor': (1.0, 0.0, 0.0)})
    assert [(row.grab, row.grab_taken) for row in rows] == [
        (None, None), ((5.0, 5.0, 5.0), False), (None, None)]
    # The later anchor change is a parameter change, not the grab: the target stays.
    assert [row.target for row in rows] == [None, (1.0, 0.0, 0.0), (1.0, 0.0, 0.0)]
    assert rows[2].body_anchor == (0.0, 1.0, 0.0)


def test_tick_rows_follow_reset_and_release():
    """
    ~/reset and ~/release set the target as the node does.

    ~/reset: the configured anchor back and the initial anchor's world position the target
    (when held); ~/release: no target. A failed reset changes nothing.
    """
    start = {'anchor': (0.2, 0.0, 0.0), 'hold_initial_anchor': True,
             'initial_position': (0.0, 0.0, 1.0), 'initial_orientation': (0.0, 0.0, 1.0, 0.0)}
    grabbed = (0.0, 0.1, 0.0)
    received = [state('pose', 10), state('twist', 10), point_received('grab', grabbed),
                anchor_event('/mouse_constraint', grabbed), state('pose', 20), state('twist', 20),
                service_event('reset', success=False), state('pose', 30), state('twist', 30),
                anchor_event('/mouse_constraint', start['anchor']), service_event('reset'),
                state('pose', 40, (0.0, 0.0, 1.0)), state('twist', 40), service_event('release'),
                state('pose', 50), state('twist', 50)]
    rows = tick_rows(received, start)
    assert [row.body_anchor for row in rows] == [start['anchor'], grabbed, grabbed,
                                                 start['anchor'], start['anchor']]
    # Turned half about z, the initial anchor (0.2, 0, 0) is at (-0.2, 0, 1).
    initial = rows[3].target
    np.testing.assert_allclose(initial, (-0.2, 0.0, 1.0), atol=1e-15)
    assert [row.target for row in rows] == [None, grabbed, grabbed, initial, None]
    without = tick_rows(received, {'anchor': start['anchor']})
    assert without[3].target is None


def test_tick_rows_keep_a_tick_published_again_by_a_reset_while_paused():
    """
    A reset while paused publishes the state it leaves at the paused tick's stamp: a row more.

    Pose and twist pair in the order they came, so the second row of the stamp is the reset's,
    with the target the reset leaves.
    """
    start = {'anchor': (0.2, 0.0, 0.0), 'hold_initial_anchor': True,
             'initial_position': (0.0, 0.0, 1.0), 'initial_orientation': (0.0, 0.0, 0.0, 1.0)}
    received = [state('pose', 10, (1.0, 0.0, 0.0)), state('twist', 10),
                point_received('target', (1.0, 1.0, 1.0)), service_event('reset'),
                state('pose', 10, (0.0, 0.0, 1.0)), state('twist', 10),
                state('pose', 20, (0.0, 0.0, 1.0)), state('twist', 20)]
    rows = tick_rows(received, start)
    assert [row.stamp_ns for row in rows] == [10, 10, 20]
    assert [row.position for row in rows] == [(1.0, 0.0, 0.0), (0.0, 0.0, 1.0), (0.0, 0.0, 1.0)]
    assert [row.target for row in rows] == [None, (0.2, 0.0, 1.0), (0.2, 0.0, 1.0)]


def test_tick_rows_apply_a_change_to_the_ticks_stamped_after_it():
    """A change received after a pose stamped later than the node's stamp of it applies there."""
    received = [state('pose', 10), state('twist', 10), state('pose', 20), state('twist', 20),
                state('pose', 30), state('twist', 30),
                anchor_event('/mouse_constraint', (0.0, 1.0, 0.0), stamp_ns=25),
                state('pose', 40), state('twist', 40)]
    rows = tick_rows(received, {'anchor': (1.0, 0.0, 0.0)})
    assert [row.body_anchor for row in rows] == [(1.0, 0.0, 0.0)] * 2 + [(0.0, 1.0, 0.0)] * 2
    # On another clock (far from the poses' stamps) the order of arrival decides.
    received[6] = anchor_event('/mouse_constraint', (0.0, 1.0, 0.0), stamp_ns=10 ** 18)
    rows = tick_rows(received, {'anchor': (1.0, 0.0, 0.0)})
    assert [row.body_anchor for row in rows] == [(1.0, 0.0, 0.0)] * 3 + [(0.0, 1.0, 0.0)]


def test_parameter_changes_read_only_the_followed_parameters():
    """Other parameters, and arrays of another length, set nothing."""
    event = deserialize_message(anchor_event('/n', (1.0, 2.0, 3.0)).data, ParameterEvent)
    assert parameter_changes(event) == {'anchor': (1.0, 2.0, 3.0)}
    event.changed_parameters[0].name = 'mass'
    assert parameter_changes(event) == {}
    event.changed_parameters[0].name = 'anchor'
    event.changed_parameters[0].value.double_array_value = [1.0, 2.0]
    assert parameter_changes(event) == {}
    event = deserialize_message(
        anchor_event('/n', (0.0, 0.0, 0.0, 1.0), name='initial_orientation').data, ParameterEvent)
    assert parameter_changes(event) == {'initial_orientation': (0.0, 0.0, 0.0, 1.0)}


def test_progress_bar_and_lines_off_a_terminal():
    """The bar fills with the time; off a terminal it prints one line per tenth, then the end."""
    assert progress_bar(3.0, 10.0, {'pose': 7}, width=10) == \
        'recording [###.......]   3.0/10 s  pose 7'
    stream = io.StringIO()
    progress = Progress(1.0, stream)
    for k in range(21):
        progress.update(k * 0.05, {'pose': k})
    progress.update(1.0, {'pose': 20}, final=True)
    lines = stream.getvalue().splitlines()
    assert len(lines) == 12 and lines[-1] == lines[-2]


@pytest.mark.parametrize('arguments', [
    ['--duration', '0'], ['--duration', 'inf'], ['--anchor', '0', 'nan', '0'], ['--anchor', '1'],
    ['--timeout', '-1'], ['extra'], ['--output', '/'], ['--output', '.'],
])
def test_bad_arguments_are_usage_errors(arguments, capsys):
    """Invalid durations, anchors and timeouts exit 2 with the usage."""
    with pytest.raises(SystemExit) as exit_info:
        parse_arguments(arguments)
    assert exit_info.value.code == 2
    assert 'usage: mouse_record' in capsys.readouterr().err


def test_default_output_is_timestamped():
    """Without --output the prefix is mouse_record_<date>_<time> in the working directory."""
    options = parse_arguments([])
    assert options.output.name.startswith('mouse_record_') and not options.mcap
    assert options.duration == 10.0 and options.anchor is None


def test_without_the_node_it_says_what_to_check(tmp_path):
    """No parameter service: exit 1 naming it and --anchor, nothing written."""
    result = subprocess.run([str(BIN / 'mouse_record'), '--timeout', '0.5', '--node',
                             'nobody_here', '-o', str(tmp_path / 'x')],
                            capture_output=True, text=True, timeout=30)
    assert result.returncode == 1
    assert 'no parameter service nobody_here/get_parameters' in result.stderr
    assert '--anchor X Y Z' in result.stderr and 'Traceback' not in result.stderr
    assert not list(tmp_path.iterdir())


def test_ctrl_c_ends_the_recording_early_and_keeps_it(harness, tmp_path):
    """SIGINT while recording: exit 0, the files hold what came so far."""
    prefix = tmp_path / 'early'
    status, stderr, _ = run_recorder(harness, ['--duration', '60', '--anchor', *map(str, ANCHOR),
                                               '--output', str(prefix)], signal_after=0.3)
    assert status == 0, stderr
    assert 'Traceback' not in stderr
    rows = read_csv(prefix.with_suffix('.csv'))
    assert 0.2 * RATE < len(rows) < 10 * RATE
    assert prefix.with_suffix('.png').is_file() and not prefix.with_suffix('.mcap').exists()


def test_a_push_given_while_recording_is_in_the_csv_and_the_figure(harness, tmp_path):
    """
    mouse_wrench --subscribers 2 beside mouse_record, as README's worked example runs them.

    The push waits until the node and the recorder both listen, so that the recorder, a
    subscriber that would otherwise match after the push was sent, holds it: its rows carry the
    force for the push's duration (its stamps, to a tick).
    """
    ros, force, duration = harness, 5.0, 0.1
    prefix = tmp_path / 'pushed'
    recorder, lines, reader = start_recorder('--duration', '60', '--output', str(prefix))
    push = None
    try:
        assert ros.spin_until(lambda: any(line.startswith('recording') for line in lines),
                              timeout=30.0), ''.join(lines)
        push = subprocess.Popen(
            [str(BIN / 'mouse_wrench'), '--subscribers', '2', '--force', '0', '0', str(force),
             '--duration', str(duration)], stdout=subprocess.PIPE, stderr=subprocess.PIPE,
            text=True)
        assert ros.spin_until(lambda: push.poll() is not None, timeout=40.0), \
            'mouse_wrench did not finish'
        # The push's zero wrench and a few poses after it reach the recorder; then it ends as
        # Ctrl-C ends it, keeping what came.
        ros.spin_for(0.3)
        recorder.send_signal(signal.SIGINT)
        assert ros.spin_until(lambda: recorder.poll() is not None, timeout=30.0), \
            'mouse_record did not finish'
    finally:
        for process in (recorder, push):
            if process is not None and process.poll() is None:
                process.kill()
        recorder.wait()
        reader.join(timeout=5.0)
    stdout, stderr = push.communicate(timeout=5.0)
    assert push.returncode == 0 and f'for {duration:g} s' in stdout, stderr
    assert recorder.returncode == 0, ''.join(lines)
    rows = read_csv(prefix.with_suffix('.csv'))
    pushed = [index for index, row in enumerate(rows) if row['wrench_fz'] != 0.0]
    assert pushed == list(range(pushed[0], pushed[-1] + 1))
    assert {(row['wrench_fx'], row['wrench_fy'], row['wrench_fz'], row['wrench_tz'])
            for row in (rows[index] for index in pushed)} == {(0.0, 0.0, force, 0.0)}
    assert abs(len(pushed) - duration * RATE) <= 1
    assert 'wrote' in ''.join(lines) and prefix.with_suffix('.png').is_file()


def unwritable_outputs(tmp_path: Path) -> list:
    """Return (arguments, the path that fails) for outputs that cannot be written."""
    a_file = tmp_path / 'a_file'
    a_file.write_text('kept')
    (tmp_path / 'png_is_a_directory.png').mkdir()
    (tmp_path / 'mcap_is_a_directory.mcap').mkdir()
    cases = [
        (['-o', str(a_file / 'run')], a_file / 'run.csv'),
        (['-o', str(a_file / 'sub' / 'run')], a_file / 'sub'),
        (['-o', str(tmp_path / 'png_is_a_directory')], tmp_path / 'png_is_a_directory.png'),
        (['-o', str(tmp_path / 'mcap_is_a_directory'), '--mcap'],
         tmp_path / 'mcap_is_a_directory.mcap'),
    ]
    if Path('/proc/self').is_dir():
        cases.append((['-o', '/proc/run'], Path('/proc/run.csv')))
    return cases


def tree(root: Path) -> dict:
    """Return every path under ``root`` with its content (None for directories)."""
    return {path: None if path.is_dir() else path.read_bytes() for path in root.rglob('*')}


def test_unwritable_output_fails_before_recording(tmp_path):
    """
    Exit 1 with one line naming the path, before any waiting; the file system as it was.

    The duration and the timeouts are long and no node runs: only a check made before
    recording can end the command before ``subprocess.run``'s timeout.
    """
    cases = unwritable_outputs(tmp_path)
    before = tree(tmp_path)
    for arguments, failing in cases:
        result = subprocess.run(
            [str(BIN / 'mouse_record'), '--duration', '600', '--timeout', '600', '--anchor',
             '0', '0', '0', *arguments], capture_output=True, text=True, timeout=60)
        assert result.returncode == 1, (arguments, result.stderr)
        [line] = result.stderr.strip().splitlines()
        assert line.startswith(f'mouse_record: cannot write {failing}: '), line
        assert tree(tmp_path) == before, arguments


def test_check_writable_leaves_nothing_behind(tmp_path):
    """A writable prefix passes; the directories and files the check made are gone again."""
    existing = tmp_path / 'run.csv'
    existing.write_text('old')
    check_writable(output_paths(tmp_path / 'run', mcap=True))
    check_writable(output_paths(tmp_path / 'new' / 'deeper' / 'run', mcap=False))
    assert tree(tmp_path) == {existing: b'old'}
    assert [p.name for p in output_paths(Path('x/run'), mcap=True)] == [
        'run.csv', 'run.png', 'run.mcap']


def test_a_recording_in_lockstep_holds_every_tick_bit_for_bit(simulated_body_factory):
    """
    The recorder node beside a body stepped in lockstep: one row per tick, none missing.

    Each row is the pose and twist the node published at that tick, bit for bit, with the target
    path at its time: the targets, sent every 10 ticks, are a stream, each placed at the stamp
    of the tick before it came, and a row between two is on the line between them, at the
    share of the ticks gone; the first target (before any tick) and the last hold; a grab moves
    the anchor from its row on, a release empties the target.
    """
    body = simulated_body_factory(rate_hz=RATE, anchor=list(ANCHOR), linear_damping=2.0,
                                  angular_damping=2.0, marker_rate_hz=0.0,
                                  diagnostics_rate_hz=0.0)
    recorder = body.add_node(Recorder(context=body.context))
    start = fetch_start(recorder, body.executor, StopRequest(), target_node='mouse_constraint',
                        timeout=5.0)
    assert start['anchor'] == ANCHOR and start['rate_hz'] == RATE
    published, held = [], []
    body.add_tick_callback(lambda b: (published.append((b.pose.message, b.twist.message)),
                                      held.append(b.node.simulation.target)))
    for k in range(20):
        body.target(target_at(k))
        body.step(10)
    grab = body.node.simulation.state.world_point((-0.15, 0.05, 0.0))
    body.grab(grab)
    body.step(40)
    body.release()
    body.step(40)
    rows = tick_rows(recorder.received, start)
    assert len(rows) == len(published) == 280
    assert [row.stamp_ns for row in rows] == [5_000_000 * n for n in range(1, 281)]
    for tick, (row, (pose, twist), target) in enumerate(zip(rows, published, held), start=1):
        q = pose.pose.orientation
        assert row.position == xyz(pose.pose.position)
        assert row.orientation == (q.x, q.y, q.z, q.w)
        assert row.linear_velocity == xyz(twist.twist.linear)
        assert row.angular_velocity == xyz(twist.twist.angular)
        sent = (tick - 1) // 10  # the target the node held: sent after tick 10 * sent
        if 1 <= sent < 19:
            share = (tick - 10 * sent) / 10
            start, end = np.array(target_at(sent)), np.array(target_at(sent + 1))
            assert target == target_at(sent)
            assert row.target == pytest.approx(tuple(start + share * (end - start)), abs=1e-15)
        else:
            assert row.target == target
    grabbed = tuple(body.node.get_parameter('anchor').value)
    assert [row.body_anchor for row in rows] == [ANCHOR] * 200 + [grabbed] * 80
    marked = [(row.grab, row.grab_taken) for row in rows if row.grab is not None]
    assert marked == [(grab, True)]


def test_the_anchor_error_of_a_streamed_circle_is_measured_against_its_path(
        simulated_body_factory):
    """
    A stamped 50 Hz circle the node follows to within 0.02 mm: the rows say so.

    The anchor error of each row within the stream is its distance to the line between the two
    targets around the tick's time, so it differs from the distance to the circle itself at
    that time by at most the chord's sagitta, R (1 - cos(w T / 2)) = 0.0625 mm; the distance to
    the latest target, one stream gap stale, reaches w R T = 10 mm.
    """
    radius, omega, period = 0.2, 2.5, 0.02
    body = simulated_body_factory(rate_hz=1000.0, marker_rate_hz=0.0, diagnostics_rate_hz=0.0,
                                  floor=False)
    recorder = body.add_node(Recorder(context=body.context))
    start = fetch_start(recorder, body.executor, StopRequest(), target_node='mouse_constraint',
                        timeout=5.0)
    center = np.subtract(body.node.simulation.state.world_point(start['anchor']),
                         (radius, 0.0, 0.0))

    def circle(t: float) -> np.ndarray:
        return center + radius * np.array([math.cos(omega * t), math.sin(omega * t), 0.0])
    sent = []
    for _ in range(150):
        sent.append((body.time, circle(body.time)))
        body.target(tuple(sent[-1][1]), stamp=body.time)
        body.step(round(period * 1000.0))
    rows = [row for row in tick_rows(recorder.received, start)
            if 1.0 < row.stamp_ns * 1e-9 <= sent[-1][0]]
    assert len(rows) > 1900
    recorded = np.array([row.anchor_error for row in rows])
    on_circle = np.array([np.linalg.norm(row.anchor - circle(row.stamp_ns * 1e-9))
                          for row in rows])
    latest = np.array([np.linalg.norm(row.anchor - max(
        (s for s in sent if s[0] <= row.stamp_ns * 1e-9), key=lambda s: s[0])[1])
        for row in rows])
    sagitta = radius * (1.0 - math.cos(omega * period / 2))
    assert on_circle.max() < 2e-5
    assert np.abs(recorded - on_circle).max() <= sagitta + 1e-9
    assert recorded.max() < 1e-4 and latest.max() > 0.9 * omega * radius * period


def test_a_recorder_killed_outright_leaves_what_it_recorded(harness, tmp_path):
    """
    SIGKILL 2 s into a 20 s recording: the CSV and the MCAP hold all but its last moments.

    The files are written while recording and flushed every FLUSH_SECONDS; the rows wait
    2 SETTLE_NS for their changes and targets. The MCAP file, without its summary, is read
    with the streaming reader, as ``mcap recover`` reads it.
    """
    prefix = tmp_path / 'killed'
    process, lines, reader = start_recorder('-d', '20', '-o', str(prefix), '--mcap',
                                            '--timeout', '20')
    try:
        deadline, started = time.monotonic() + 60.0, None
        while started is None or time.monotonic() - started < 2.0:
            assert process.poll() is None and time.monotonic() < deadline, ''.join(lines)
            harness.spin_for(0.05)
            if started is None and any(line.startswith('recording') for line in lines):
                started = time.monotonic()
        process.send_signal(signal.SIGKILL)
        process.wait(timeout=10)
    finally:
        if process.poll() is None:
            process.kill()
        reader.join(timeout=5.0)
    rows = read_csv(prefix.with_suffix('.csv'))
    recorded = rows[-1]['time']
    assert 2.0 - 2 * SETTLE_NS * 1e-9 - 2 * FLUSH_SECONDS - 0.5 < recorded < 2.5
    assert len(rows) >= 0.75 * recorded * RATE
    assert not prefix.with_suffix('.png').exists()
    poses = []
    with open(prefix.with_suffix('.mcap'), 'rb') as stream:
        reader = NonSeekingReader(stream, decoder_factories=[DecoderFactory()])
        with pytest.raises(EndOfFile):  # no summary, no footer: cut where it was killed
            for _, channel, _, pose in reader.iter_decoded_messages(log_time_order=False):
                if channel.topic == '/pose':
                    poses.append(stamp_nanoseconds(pose.header.stamp))
    assert {row['stamp_ns'] for row in rows} <= set(poses)


def csv_rows_now(path: Path) -> list:
    """Return the rows of a CSV being written: its complete lines, none while it is not there."""
    try:
        text = path.read_text()
    except FileNotFoundError:
        return []
    lines = [line for line in text[:text.rfind('\n') + 1].splitlines()
             if not line.startswith('#')]
    return list(csv.DictReader(lines))


def test_a_recorder_killed_after_its_first_row_keeps_every_row_it_had_written(harness, tmp_path):
    """
    SIGKILL 2 s after the first row appeared in the CSV: the rows in the file then are kept.

    The wait is on the file, read from this process: the first row there (the recorder writes it
    to the operating system as it comes), then the rows there just before the kill.
    """
    path = tmp_path / 'first.csv'
    process, lines, reader = start_recorder('-d', '60', '-o', str(path.with_suffix('')),
                                            '--timeout', '20')
    try:
        deadline = time.monotonic() + 60.0
        while not (first := csv_rows_now(path)):
            assert process.poll() is None and time.monotonic() < deadline, ''.join(lines)
            harness.spin_for(0.05)
        harness.spin_for(2.0)
        before = csv_rows_now(path)
        process.send_signal(signal.SIGKILL)
        process.wait(timeout=10)
    finally:
        if process.poll() is None:
            process.kill()
        reader.join(timeout=5.0)
    kept = csv_rows_now(path)
    assert kept[:len(before)] == before and before[:len(first)] == first
    assert float(before[-1]['time']) > float(first[-1]['time'])


def damped_node(ros, namespace: str) -> MouseConstraintNode:
    """Return a node in ``namespace`` at RATE with ANCHOR, damped, without monitors."""
    return MouseConstraintNode(context=ros.context, namespace=namespace, parameter_overrides=[
        Parameter('rate_hz', value=RATE), Parameter('anchor', value=list(ANCHOR)),
        Parameter('marker_rate_hz', value=0.0), Parameter('diagnostics_rate_hz', value=0.0),
        Parameter('linear_damping', value=2.0), Parameter('angular_damping', value=2.0)])


def test_recording_follows_a_grab(tmp_path):
    """
    A grab during the recording: the rows use the grabbed anchor from then on, the grab is marked.

    A node of its own, in a namespace, in this process; the recorder in that namespace reads
    its anchor at the start and follows its /parameter_events. The grab is a point on the
    body (a body-frame point away from ANCHOR, placed by the latest pose).
    """
    ros = RosHarness()
    try:
        node = ros.add(damped_node(ros, 'grabbed'))
        poses = ros.collect(PoseStamped, 'grabbed/pose', depth=100000)
        grabs = ros.probe.create_publisher(PointStamped, 'grabbed/grab', 10)
        assert ros.spin_until(lambda: grabs.get_subscription_count() > 0 and poses)
        prefix = tmp_path / 'grab'
        process, lines, reader = start_recorder('-d', '1.5', '-o', str(prefix), '--mcap',
                                                '--timeout', '20', '--ros-args', '-r',
                                                '__ns:=/grabbed')
        deadline, grabbed, point = time.monotonic() + 40.0, None, None
        while process.poll() is None:
            assert time.monotonic() < deadline, 'mouse_record did not finish'
            ros.spin_for(0.05)
            if grabbed is None and any(line.startswith('recording') for line in lines):
                grabbed = time.monotonic()
            if point is None and grabbed is not None and time.monotonic() - grabbed > 0.5:
                point = node.simulation.state.world_point((-0.15, 0.05, 0.0))
                grabs.publish(point_message(point, 'world', 0))
        reader.join(timeout=5.0)
        assert process.returncode == 0, ''.join(lines)
        assert point is not None
        new_anchor = tuple(node.get_parameter('anchor').value)
        assert new_anchor != ANCHOR
    finally:
        ros.shutdown()
    rows = read_csv(prefix.with_suffix('.csv'))
    body = [(row['body_anchor_x'], row['body_anchor_y'], row['body_anchor_z']) for row in rows]
    changed = body.index(new_anchor)
    assert 0 < changed < len(rows) - 10
    assert set(body[:changed]) == {ANCHOR} and set(body[changed:]) == {new_anchor}
    marked = [i for i, row in enumerate(rows) if row['grab_x'] is not None]
    # Marked on the row from which the node holds it, taken; from there it is the target.
    assert marked == [changed] and rows[changed]['grab_taken'] == 1
    assert (rows[changed]['grab_x'], rows[changed]['grab_y'],
            rows[changed]['grab_z']) == tuple(point)
    assert all(row['target_x'] is None for row in rows[:changed])
    assert {(row['target_x'], row['target_y'], row['target_z'])
            for row in rows[changed:]} == {tuple(point)}
    # The node placed the grabbed point where it was: no jump, and a rigid joint holds it. The
    # body swings on its anchor (the angular friction stops only its spin) and goes on some
    # millimetres while the grab is on its way; a jump would be the centimetres between the
    # two anchors.
    assert rows[changed]['anchor_error'] < 5e-3
    assert max(row['anchor_error'] for row in rows[changed:]) < 0.01
    for row, anchor in zip(rows, body):
        q = [row['qx'], row['qy'], row['qz'], row['qw']]
        world = np.array([row['x'], row['y'], row['z']]) + Rotation.from_quat(q).apply(anchor)
        np.testing.assert_allclose((row['anchor_x'], row['anchor_y'], row['anchor_z']), world,
                                   atol=1e-12)
    with open(prefix.with_suffix('.mcap'), 'rb') as stream:
        reader = make_reader(stream, decoder_factories=[DecoderFactory()])
        decoded = [(channel.topic, message) for _, channel, _, message
                   in reader.iter_decoded_messages()]
    assert [xyz(m.point) for topic, m in decoded if topic == '/grabbed/grab'] == [tuple(point)]
    events = [m for topic, m in decoded if topic == '/parameter_events']
    assert [e.node for e in events] == ['/grabbed/mouse_constraint']
    assert tuple(events[0].changed_parameters[0].value.double_array_value) == new_anchor


def resting_rows(count: int = 50, target=None) -> list:
    """Return the rows of a body at rest at (0, 0, 1) + 1e-12 noise, with ``target`` or none."""
    received = []
    for k in range(count):
        ns = 1_000_000 * (k + 1)
        received += [state('pose', ns, (0.2, 0.1, 1.0 + 1e-12 * (k % 3))), state('twist', ns)]
        if target is not None and k == 0:
            received.append(point_received('target', target))
    return tick_rows(received, {'anchor': (0.0, 0.0, 0.0)})


def test_the_figure_of_a_body_at_rest_reads_plainly():
    """
    The figure of a body at rest: plain labels, a note, both speed lines in view.

    Plain tick labels (no offset), a note for the empty anchor error panel, and the zero speed
    drawn inside the axes, under a dashed zero angular speed.
    """
    from mouse_constraint_ros.recording.figure import draw_figure

    figure = draw_figure(resting_rows(), anchor=(0.0, 0.0, 0.0), frame_id='world')
    figure.canvas.draw()
    top, side, error, speed, spin = figure.axes
    for axes in (top, side, speed, spin):
        for axis in (axes.xaxis, axes.yaxis):
            # Each label is its tick's value (to the label's digits), not an offset from one.
            locations = axis.get_ticklocs()
            labels = [float(t.get_text().replace('\u2212', '-')) for t in axis.get_ticklabels()]
            step = np.min(np.diff(locations))
            np.testing.assert_allclose(labels, locations, atol=step / 2, err_msg=str(axis))
    assert [t.get_text() for t in error.texts] == [
        'no target: the node held none while recorded']
    for axes in (speed, spin):
        [line] = [line for line in axes.get_lines() if not line.get_label().startswith('_')]
        low, high = axes.get_ylim()
        assert low < 0.0 == line.get_ydata().max() < high
    assert spin.get_lines()[0].get_linestyle() == '--'
    assert speed.get_lines()[0].get_linestyle() == '-'
    figure = draw_figure(resting_rows(target=(0.2, 0.1, 1.5)), anchor=(0.0, 0.0, 0.0),
                         frame_id='world')
    assert not figure.axes[2].texts and figure.axes[2].get_lines()


def test_the_figure_escapes_what_its_font_cannot_draw(tmp_path):
    """An emoji frame id is drawn as its escape, without a missing-glyph warning."""
    import warnings

    from mouse_constraint_ros.recording.figure import drawable, write_figure

    assert drawable('world') == 'world' and drawable('m\u00e8tre') == 'm\u00e8tre'
    assert drawable('\U0001f916 arm') == '\\U0001f916 arm'
    with warnings.catch_warnings():
        warnings.simplefilter('error')
        write_figure(tmp_path / 'emoji.png', resting_rows(), anchor=(0.0, 0.0, 0.0),
                     frame_id='\U0001f916', title='robot \U0001f916')
    assert (tmp_path / 'emoji.png').stat().st_size > 0


def test_missing_ticks_count_the_gaps_on_the_grid():
    """Gaps on the grid count as missing ticks; a step back or off the grid is a restart."""
    ms = 1_000_000
    stamps = [0, ms, 2 * ms, 5 * ms, 6 * ms, 16 * ms]
    lacking = missing_ticks(stamps, Grid(1000.0))
    assert (lacking.expected, lacking.recorded, lacking.missing) == (17, 6, 11)
    assert (lacking.longest_gap, lacking.gap_at, lacking.restarts) == (0.01, 0.006, 0)
    assert missing_ticks(stamps, None).missing == 11
    # A restart (back in time, or off the grid) counts nothing across it.
    restarted = missing_ticks([0, ms, 2 * ms, ms // 2, ms // 2 + ms, 2 * ms + 777], Grid(1000.0))
    assert (restarted.missing, restarted.restarts) == (0, 2)
    # A tick published twice (a reset while paused) is neither a gap nor a restart.
    again = missing_ticks([0, ms, ms, 2 * ms], Grid(1000.0))
    assert (again.missing, again.restarts, again.recorded) == (0, 0, 4)
    # 300 Hz published at 1 kHz: gaps of 3 and 4 ticks are no loss; 13 ticks lack 3 publishes.
    ticks = PublishTicks(1000.0, 300.0)
    published = [n * ms for n in range(100) if ticks.due(n)]
    assert missing_ticks(published, Grid(1000.0, 300.0)).missing == 0
    assert missing_ticks(published[:5] + published[8:], Grid(1000.0, 300.0)).missing == 3
    assert 'ticks_missing: 3' in missing_ticks(published[:5] + published[8:],
                                               Grid(1000.0, 300.0)).lines()


def test_a_recording_says_which_ticks_it_lacks(tmp_path):
    """
    Ticks absent from the grid: the exit warning and the CSV's header count them.

    The test publishes the stamped poses and twists itself (1 ms apart from 5 s, without
    ticks 100 to 109 and 300 to 304), so the gaps are known; without the node's parameters
    (``--anchor``) the grid is the smallest step. The recording ends at 0.5 s of stamps.
    """
    ros = RosHarness()
    try:
        qos = QoSProfile(depth=10000, reliability=ReliabilityPolicy.RELIABLE)
        poses = ros.probe.create_publisher(PoseStamped, 'lacking/pose', qos)
        twists = ros.probe.create_publisher(TwistStamped, 'lacking/twist', qos)
        process = subprocess.Popen(
            [str(BIN / 'mouse_record'), '-d', '0.5', '-o', str(tmp_path / 'lacking'), '--anchor',
             '0', '0', '0', '--timeout', '20', '--ros-args', '-r', '__ns:=/lacking'],
            stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True)
        assert ros.spin_until(lambda: poses.get_subscription_count() > 0
                              and twists.get_subscription_count() > 0, timeout=20.0)
        # The recorder's readers match these writers too: none of the burst is lost.
        assert ros.discovered_by('/lacking/mouse_record')
        kept = [n for n in range(700) if not (100 <= n < 110 or 300 <= n < 305)]
        for n in kept:
            for publisher, kind in ((poses, 'pose'), (twists, 'twist')):
                publisher.publish(deserialize_message(
                    state(kind, 5_000_000_000 + n * 1_000_000).data,
                    PoseStamped if kind == 'pose' else TwistStamped))
            ros.spin_for(0.0005)
        assert ros.spin_until(lambda: process.poll() is not None, timeout=30.0)
        stderr = process.stderr.read()
    finally:
        if process.poll() is None:
            process.kill()
        ros.shutdown()
    assert process.returncode == 0, stderr
    assert '15 of 501 ticks missing from the recording (longest gap 0.011 s' in stderr, stderr
    with open(tmp_path / 'lacking.csv') as stream:
        header = [line for line in stream if line.startswith('#')]
    assert '# ticks_missing: 15\n' in header and '# ticks_recorded: 486\n' in header
    assert len(read_csv(tmp_path / 'lacking.csv')) == 486


def test_recording_follows_a_reset(tmp_path):
    """
    ~/reset during a recording: from the row after it, the target is the initial anchor.

    The node holds its initial anchor, then follows a target 0.3 m away; the reset puts the
    body back and holds the initial anchor again. The recorder learns of the reset from the
    node's service events and of the initial pose from its parameters, so the rows after it
    show the node's small anchor error, not the distance to the old target.
    """
    ros = RosHarness()
    try:
        node = ros.add(damped_node(ros, 'resetting'))
        held = node.simulation.target
        targets = ros.probe.create_publisher(PointStamped, 'resetting/target', 10)
        reset = ros.probe.create_client(Trigger, 'resetting/mouse_constraint/reset')
        assert ros.spin_until(lambda: targets.get_subscription_count() > 0
                              and reset.service_is_ready())
        moved = (held[0] + 0.3, held[1], held[2])
        targets.publish(point_message(moved, 'world', 0))
        process, lines, reader = start_recorder('-d', '1.5', '-o', str(tmp_path / 'reset'),
                                                '--timeout', '20', '--ros-args', '-r',
                                                '__ns:=/resetting')
        deadline, started, future = time.monotonic() + 40.0, None, None
        while process.poll() is None:
            assert time.monotonic() < deadline, 'mouse_record did not finish'
            ros.spin_for(0.05)
            if started is None and any(line.startswith('recording') for line in lines):
                started = time.monotonic()
                targets.publish(point_message(moved, 'world', 0))
            if future is None and started is not None and time.monotonic() - started > 0.6:
                future = reset.call_async(Trigger.Request())
        reader.join(timeout=5.0)
        assert process.returncode == 0, ''.join(lines)
        assert future is not None and future.done() and future.result().success
    finally:
        ros.shutdown()
    rows = read_csv(tmp_path / 'reset.csv')
    target = [(row['target_x'], row['target_y'], row['target_z']) for row in rows]
    assert moved in target
    after = target.index(held)
    assert 0 < after < len(rows) - 10 and set(target[after:]) == {held}
    assert target[after - 1] == moved
    # Back at the initial pose, the body hangs from the held anchor: no 0.3 m error.
    assert rows[after]['anchor_error'] < 0.01
