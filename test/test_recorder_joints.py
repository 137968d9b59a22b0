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
``mouse_record`` of a whole robot: its joint_states in the CSV, the MCAP file and the figure.

The recorder beside a double pendulum released from 60 degrees, in lockstep, writes its files as
``mouse_record`` does (``RecordingFiles`` fed by the ``Recorder`` node); the CSV's joint columns
hold the values of the joint_states the node published, bit for bit. A single body's CSV keeps
its columns exactly, even with joint_states of another publisher on the topic. The installed
``mouse_record`` records a robot node spinning in this process on the wall clock likewise.
"""

import csv
import math
from pathlib import Path
import subprocess
import sys
import threading
import time

from mcap.reader import make_reader
import numpy as np
from PIL import Image
import pytest
from rclpy.node import Node
from rclpy.parameter import Parameter
from rclpy.serialization import deserialize_message
from rclpy.serialization import serialize_message
from sensor_msgs.msg import JointState

from mouse_constraint_ros.node.mouse_constraint_node import MouseConstraintNode
from mouse_constraint_ros.recording.capture import fetch_start
from mouse_constraint_ros.recording.capture import Recorder
from mouse_constraint_ros.recording.figure import draw_figure
from mouse_constraint_ros.recording.figure import FIGURE_DPI
from mouse_constraint_ros.recording.figure import FIGURE_INCHES
from mouse_constraint_ros.recording.figure import JOINTS_TITLE
from mouse_constraint_ros.recording.joints import joint_fields
from mouse_constraint_ros.recording.joints import JointValues
from mouse_constraint_ros.recording.received import Received
from mouse_constraint_ros.recording.recording_files import RecordingFiles
from mouse_constraint_ros.recording.rows import RowStream
from mouse_constraint_ros.recording.rows import tick_rows
from mouse_constraint_ros.timing.spin import StopRequest
from mouse_constraint_ros.wire.interface import JOINT_STATES_QOS
from mouse_constraint_ros.wire.interface import JOINT_STATES_TOPIC
from mouse_constraint_ros.wire.messages import set_stamp
from mouse_constraint_ros.wire.messages import stamp_nanoseconds
from test_support.robots import double_pendulum
from test_support.ros_harness import RosHarness

START = math.radians(60.0)
TICKS = 1000
# The single body's CSV columns, as its readers know them.
BODY_COLUMNS = (
    'time', 'stamp_ns', 'x', 'y', 'z', 'qx', 'qy', 'qz', 'qw', 'vx', 'vy', 'vz', 'wx', 'wy', 'wz',
    'anchor_x', 'anchor_y', 'anchor_z', 'target_x', 'target_y', 'target_z', 'anchor_error',
    'speed', 'angular_speed', 'body_anchor_x', 'body_anchor_y', 'body_anchor_z', 'grab_x',
    'grab_y', 'grab_z', 'grab_taken', 'wrench_fx', 'wrench_fy', 'wrench_fz', 'wrench_tx',
    'wrench_ty', 'wrench_tz')


def record(body, prefix: Path, ticks: int, each_tick=None) -> RecordingFiles:
    """Record ``ticks`` ticks of ``body`` into PREFIX.csv and PREFIX.mcap as mouse_record does."""
    files = RecordingFiles(prefix.with_suffix('.csv'), prefix.with_suffix('.mcap'))
    recorder = body.add_node(Recorder(context=body.context, sink=files.add, keep=False))
    start = fetch_start(recorder, body.executor, StopRequest(), target_node='mouse_constraint',
                        timeout=5.0)
    if each_tick is not None:
        each_tick(recorder)
    files.start(start, topic_names=recorder.topic_names(), offered_qos=recorder.offered_qos,
                metadata=['mouse_record of /mouse_constraint'])
    body.step(ticks)
    files.close()
    return files


def read_csv(path: Path):
    """Return the CSV's header and its rows as dicts of text."""
    with open(path, newline='') as stream:
        reader = csv.DictReader(line for line in stream if not line.startswith('#'))
        return tuple(reader.fieldnames), list(reader)


def mcap_messages(path: Path, topic: str):
    """Return the schema names of the MCAP file and the raw messages of ``topic``."""
    with open(path, 'rb') as stream:
        reader = make_reader(stream)
        schemas = {schema.name for schema in reader.get_summary().schemas.values()}
        raw = [message.data for _, channel, message in reader.iter_messages()
               if channel.topic == topic]
    return schemas, raw


def test_a_robot_recorded_has_the_joint_states_it_published_in_its_files(
        simulated_body_factory, tmp_path):
    """
    Each row's joint columns are the values of the joint_states of its tick, bit for bit.

    The columns follow the single body's, three a joint in the message's order, named by the
    joint; the MCAP file holds the messages as published; the figure's joint panel draws each
    joint's positions as the CSV holds them.
    """
    body = simulated_body_factory(robot_description=double_pendulum(), substeps=1,
                                  initial_joint_positions=[START, 0.0], marker_rate_hz=0.0,
                                  diagnostics_rate_hz=0.0)
    published = []
    body.add_tick_callback(lambda b: published.append(b.joints))
    files = record(body, tmp_path / 'robot', TICKS)
    header, rows = read_csv(tmp_path / 'robot.csv')
    names = list(published[0].name)
    quantities = ('position', 'velocity', 'effort')
    assert header == BODY_COLUMNS + tuple(
        f'joint.{name}.{quantity}' for name in names for quantity in quantities)
    assert files.joint_names == tuple(names) and len(names) == 2
    assert [int(row['stamp_ns']) for row in rows] == [
        stamp_nanoseconds(message.header.stamp) for message in published]
    for row, message in zip(rows, published):
        for index, name in enumerate(names):
            for quantity in quantities:
                assert float(row[f'joint.{name}.{quantity}']) == getattr(message, quantity)[index]
    # The pendulum swung, and the shoulder's effort is not the elbow's: nothing constant.
    shoulder = [float(row['joint.shoulder.position']) for row in rows]
    assert len(set(shoulder)) == len(rows) and max(shoulder) - min(shoulder) > 0.5
    schemas, raw = mcap_messages(tmp_path / 'robot.mcap', '/joint_states')
    assert 'sensor_msgs/msg/JointState' in schemas
    assert [deserialize_message(data, JointState) for data in raw] == published
    figure = draw_figure(files.rows(), anchor=(0.0, 0.0, 0.0), frame_id='world')
    [panel] = [axes for axes in figure.axes if axes.get_title() == JOINTS_TITLE]
    assert [line.get_label() for line in panel.get_lines()] == names
    for line, name in zip(panel.get_lines(), names):
        assert list(line.get_ydata()) == [float(row[f'joint.{name}.position']) for row in rows]


def test_a_single_body_csv_keeps_its_columns_beside_another_joint_states_publisher(
        simulated_body_factory, tmp_path):
    """
    A single body's CSV has exactly its columns; its MCAP file no JointState without one.

    Then with a publisher of joint_states beside it (a joint_state_publisher of another robot,
    stamped off the node's ticks): the recorder takes its messages (the MCAP file holds them)
    and still adds no column, since no tick of the node has joint_states.
    """
    plain = simulated_body_factory(marker_rate_hz=0.0, diagnostics_rate_hz=0.0)
    record(plain, tmp_path / 'plain', 100)
    header, rows = read_csv(tmp_path / 'plain.csv')
    assert header == BODY_COLUMNS and len(rows) == 100
    schemas, raw = mcap_messages(tmp_path / 'plain.mcap', '/joint_states')
    assert 'sensor_msgs/msg/JointState' not in schemas and raw == []

    body = simulated_body_factory(marker_rate_hz=0.0, diagnostics_rate_hz=0.0)
    other = body.add_node(Node('joint_state_publisher', context=body.context))
    publisher = other.create_publisher(JointState, JOINT_STATES_TOPIC, JOINT_STATES_QOS)
    stray = JointState(name=['wheel'], position=[1.0], velocity=[2.0], effort=[3.0])

    def publish_stray(b) -> None:
        set_stamp(stray.header.stamp, round(b.time * 1e9) + 500_000)
        publisher.publish(stray)
    body.add_tick_callback(publish_stray)

    def wait_for_the_publisher(recorder) -> None:
        subscription = recorder.subscriptions_by_topic[JOINT_STATES_TOPIC]
        assert body.step_until(lambda: subscription.get_publisher_count() > 0, 100) >= 0
    record(body, tmp_path / 'beside', 100, wait_for_the_publisher)
    header, rows = read_csv(tmp_path / 'beside.csv')
    assert header == BODY_COLUMNS and len(rows) >= 90
    _, raw = mcap_messages(tmp_path / 'beside.mcap', '/joint_states')
    assert len(raw) >= 90


def joint_states(stamp_ns: int, positions) -> Received:
    """Return a received joint_states of the double pendulum's two joints."""
    message = JointState(name=['shoulder', 'elbow'], position=list(positions),
                         velocity=[0.5, -0.5], effort=[0.0, 0.0])
    set_stamp(message.header.stamp, stamp_ns)
    return Received(JOINT_STATES_TOPIC, stamp_ns, serialize_message(message))


def test_rows_pair_joint_states_with_the_pose_of_their_stamp(pose_and_twist):
    """
    A row carries the joint_states of its stamp, whatever the order of arrival; none without.

    A message of a stamp no pose has is on no row; a stamp published twice pairs in order.
    """
    received = [*pose_and_twist(10), joint_states(10, (0.1, 0.2)),
                joint_states(20, (0.3, 0.4)), *pose_and_twist(20),
                joint_states(25, (9.0, 9.0)), *pose_and_twist(30),
                *pose_and_twist(40), joint_states(40, (0.5, 0.6)),
                *pose_and_twist(40)]
    rows = tick_rows(received, {'anchor': (0.0, 0.0, 0.0)})
    assert [row.stamp_ns for row in rows] == [10, 20, 30, 40, 40]
    assert [None if row.joints is None else row.joints.position for row in rows] == [
        (0.1, 0.2), (0.3, 0.4), None, (0.5, 0.6), None]
    assert rows[0].joints.names == ('shoulder', 'elbow')
    # The joints are named by the first message of a tick, not by one stamped off the ticks.
    stream = RowStream({'anchor': (0.0, 0.0, 0.0)})
    pose, twist = pose_and_twist(10)
    stray = JointState(name=['wheel'], position=[1.0])
    set_stamp(stray.header.stamp, 15)
    stream.add(pose)
    stream.add(Received(JOINT_STATES_TOPIC, 15, serialize_message(stray)))
    stream.add(joint_states(10, (0.1, 0.2)))
    assert stream.joint_names == ()  # no twist of stamp 10 yet
    stream.add(twist)
    assert stream.joint_names == ('shoulder', 'elbow')


@pytest.fixture
def pose_and_twist():
    """Return ``make(ns)``: a received pose (unturned, at the origin) and twist stamped ns."""
    from geometry_msgs.msg import PoseStamped, TwistStamped

    def make(ns: int):
        pose, twist = PoseStamped(), TwistStamped()
        pose.pose.orientation.w = 1.0
        set_stamp(pose.header.stamp, ns)
        set_stamp(twist.header.stamp, ns)
        return [Received('pose', ns, serialize_message(pose)),
                Received('twist', ns, serialize_message(twist))]
    return make


def test_the_figure_has_a_joint_panel_only_for_a_robot(pose_and_twist):
    """The joint positions panel: a line per joint, its positions; no panel for a single body."""
    received, positions = [], []
    for tick in range(1, 51):
        positions.append((math.sin(0.1 * tick), math.cos(0.1 * tick)))
        received += [joint_states(tick * 1000, positions[-1]), *pose_and_twist(tick * 1000)]
    robot = tick_rows(received, {'anchor': (0.0, 0.0, 0.0)})
    body = [row._replace(joints=None) for row in robot]
    with_joints = draw_figure(robot, anchor=(0.0, 0.0, 0.0), frame_id='world')
    without = draw_figure(body, anchor=(0.0, 0.0, 0.0), frame_id='world')
    assert len(with_joints.axes) == len(without.axes) + 1
    assert JOINTS_TITLE not in [axes.get_title() for axes in without.axes]
    [panel] = [axes for axes in with_joints.axes if axes.get_title() == JOINTS_TITLE]
    assert [line.get_label() for line in panel.get_lines()] == ['shoulder', 'elbow']
    for index, line in enumerate(panel.get_lines()):
        assert np.array_equal(line.get_ydata(), [p[index] for p in positions])
    assert panel.get_xlabel() == 'time (s)'
    # The panel lies below the others, across both columns.
    with_joints.canvas.draw()
    others = [axes.get_position() for axes in with_joints.axes if axes is not panel]
    box = panel.get_position()
    assert box.y1 < min(other.y0 for other in others)
    assert box.width > 1.5 * max(other.width for other in others)


@pytest.mark.system
@pytest.mark.alone
def test_mouse_record_of_a_robot_node_writes_its_joint_states(tmp_path):
    """
    The installed ``mouse_record`` against a swinging double pendulum at 200 Hz, for 1 s.

    Every row from the first with joint values on has those of the joint_states the node
    published at its stamp, bit for bit; the rows before it are the ticks before the recorder's
    joint_states subscription matched the node's publisher (after its pose subscription). The
    MCAP file holds those messages; the figure is drawn, without a warning about the robot's
    outline.
    """
    ros = RosHarness()
    try:
        ros.add(MouseConstraintNode(context=ros.context, parameter_overrides=[
            Parameter('robot_description', value=double_pendulum()),
            Parameter('initial_joint_positions', value=[START, 0.0]),
            Parameter('rate_hz', value=200.0), Parameter('marker_rate_hz', value=0.0),
            Parameter('diagnostics_rate_hz', value=0.0)]))
        published = ros.collect(JointState, JOINT_STATES_TOPIC, depth=100000)
        assert ros.spin_until(lambda: published)
        prefix = tmp_path / 'robot'
        process = subprocess.Popen(
            [str(Path(sys.executable).parent / 'mouse_record'), '-d', '1', '-o', str(prefix),
             '--mcap', '--timeout', '20'], stdout=subprocess.DEVNULL, stderr=subprocess.PIPE,
            text=True)
        lines = []
        reader = threading.Thread(target=lambda: lines.extend(process.stderr), daemon=True)
        reader.start()
        deadline = time.monotonic() + 60.0
        try:
            while process.poll() is None:
                assert time.monotonic() < deadline, 'mouse_record did not finish'
                ros.spin_for(0.05)
        finally:
            if process.poll() is None:
                process.kill()
            process.wait()
            reader.join(timeout=5.0)
    finally:
        ros.shutdown()
    stderr = ''.join(lines)
    assert process.returncode == 0, stderr
    assert 'Traceback' not in stderr and 'outline' not in stderr
    by_stamp = {stamp_nanoseconds(message.header.stamp): message for message in published}
    header, rows = read_csv(prefix.with_suffix('.csv'))
    names = list(published[0].name)
    assert header[:len(BODY_COLUMNS)] == BODY_COLUMNS and len(rows) >= 150
    first = next(index for index, row in enumerate(rows) if row['joint.shoulder.position'])
    assert first < 0.25 * len(rows)
    for row in rows[first:]:
        message = by_stamp[int(row['stamp_ns'])]
        for index, name in enumerate(names):
            for quantity in ('position', 'velocity', 'effort'):
                assert float(row[f'joint.{name}.{quantity}']) == getattr(message, quantity)[index]
    _, raw = mcap_messages(prefix.with_suffix('.mcap'), '/joint_states')
    recorded = [deserialize_message(data, JointState) for data in raw]
    assert len(recorded) >= len(rows) - first
    assert all(by_stamp[stamp_nanoseconds(m.header.stamp)] == m for m in recorded)
    with Image.open(prefix.with_suffix('.png')) as image:
        assert image.size == (FIGURE_INCHES[0] * FIGURE_DPI, FIGURE_INCHES[1] * FIGURE_DPI)


def test_joint_fields_follow_the_columns_and_leave_what_a_message_lacks_empty():
    """Values by the columns' joint names, whatever the message's order; '' where it has none."""
    columns = ('shoulder', 'elbow')
    whole = JointValues(columns, (0.1, 0.2), (0.3, 0.4), (0.5, 0.6))
    assert joint_fields(whole, columns) == [0.1, 0.3, 0.5, 0.2, 0.4, 0.6]
    # Another order, no velocities, and a joint the columns do not name.
    partial = JointValues(('wrist', 'elbow', 'shoulder'), (7.0, 0.2, 0.1), (), (1.0, 0.6, 0.5))
    assert joint_fields(partial, columns) == [0.1, '', 0.5, 0.2, '', 0.6]
    assert joint_fields(None, columns) == [''] * 6
