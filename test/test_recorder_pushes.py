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
``mouse_record`` and the pushes: each row carries the wrench the node applied, the figure marks it.

The recorder beside a body stepped in lockstep holds, on every row, the wrench the node applied
at that tick, bit for bit: a push stamped from its start to the zero wrench that ends it, a
push that ends at ``wrench_timeout``, a wrench the node refuses (nothing), a push a ``~/reset``
ends. The figure of a recording with a push draws its force on a row of its own and marks its
span on every time plot and its stretch of the anchor's path; the CSV has the wrench in columns
after the old ones, so that a reader of the old columns reads the same values. ``mouse_wrench
--subscribers 2`` pushes only once the recorder listens too.
"""

import csv
import math

from geometry_msgs.msg import PoseStamped
from geometry_msgs.msg import TwistStamped
from geometry_msgs.msg import WrenchStamped

from matplotlib.colors import to_rgb
import numpy as np
import pytest
from rclpy.node import Node
from rclpy.serialization import serialize_message

from mouse_constraint_ros.cli.wrench import build_parser
from mouse_constraint_ros.cli.wrench import Push
from mouse_constraint_ros.recording.applied_wrench import push_spans
from mouse_constraint_ros.recording.applied_wrench import PushSpan
from mouse_constraint_ros.recording.capture import fetch_start
from mouse_constraint_ros.recording.capture import Recorder
from mouse_constraint_ros.recording.csv_file import write_csv
from mouse_constraint_ros.recording.figure import draw_figure
from mouse_constraint_ros.recording.figure import PUSH_COLOR
from mouse_constraint_ros.recording.figure_rows import FigureRows
from mouse_constraint_ros.recording.received import Received
from mouse_constraint_ros.recording.rows import COLUMNS
from mouse_constraint_ros.recording.rows import Row
from mouse_constraint_ros.recording.rows import tick_rows
from mouse_constraint_ros.testing import InputRefused
from mouse_constraint_ros.timing.spin import StopRequest
from mouse_constraint_ros.wire.interface import WRENCH_TOPIC
from mouse_constraint_ros.wire.messages import set_stamp
from mouse_constraint_ros.wire.messages import wrench_message

# A node in this process: the ros tier, the pure test of the figure's rows with it.
pytestmark = pytest.mark.ros

RATE = 200.0
TICK_NS = 5_000_000
# The first push: straight up, from 0.02 s after it is sent to 0.07 s after (10 ticks).
UP = (0.0, 0.0, 30.0)
# The second push, never ended by a zero wrench: it ends at WRENCH_TIMEOUT.
SIDEWAYS, TWIST = (10.0, 0.0, 0.0), (0.0, 0.0, 0.5)
WRENCH_TIMEOUT = 0.1
MAX_WRENCH_FORCE = 100.0
ZERO = (0.0, 0.0, 0.0)


def wrench_of(row: Row) -> tuple:
    """Return the row's applied force and torque."""
    return row.wrench_force, row.wrench_torque


@pytest.fixture(scope='module')
def pushed_recording():
    """
    Record a body in lockstep through three pushes and a refused wrench; return what came.

    :returns: the rows, the wrench the node applied at each tick (as the rows pair them, from
        the first tick), the stamps (ns) of the first push's start and end, and the start.
    """
    from mouse_constraint_ros.testing import SimulatedBody

    with SimulatedBody(rate_hz=RATE, marker_rate_hz=0.0, diagnostics_rate_hz=0.0,
                       wrench_timeout=WRENCH_TIMEOUT, max_wrench_force=MAX_WRENCH_FORCE,
                       linear_damping=2.0, angular_damping=2.0) as body:
        recorder = body.add_node(Recorder(context=body.context))
        start = fetch_start(recorder, body.executor, StopRequest(),
                            target_node='mouse_constraint', timeout=5.0)
        applied = []
        body.add_tick_callback(lambda b: applied.append(tuple(
            tuple(map(float, part)) for part in b.node.simulation.wrench)))
        body.step(20)
        began, ended = round((body.time + 0.02) * 1e9), round((body.time + 0.07) * 1e9)
        body.wrench(UP, stamp=began * 1e-9)
        body.wrench(ZERO, stamp=ended * 1e-9)
        body.step(30)
        with pytest.raises(InputRefused):
            body.wrench((0.0, 0.0, 2 * MAX_WRENCH_FORCE))
        body.step(10)
        body.wrench(SIDEWAYS, TWIST)
        body.step(40)
        body.wrench((0.0, 5.0, 0.0))
        body.step(5)
        body.reset()
        body.step(10)
        rows = tick_rows(recorder.received, start)
        return {'rows': rows, 'applied': applied, 'began': began, 'ended': ended,
                'start': start}


def test_each_row_carries_the_wrench_the_node_applied_at_its_tick(pushed_recording):
    """Row by row, the force and torque are the node's at that tick, bit for bit."""
    rows, applied = pushed_recording['rows'], pushed_recording['applied']
    assert pushed_recording['start']['wrench_timeout'] == WRENCH_TIMEOUT
    assert pushed_recording['start']['max_wrench_force'] == MAX_WRENCH_FORCE
    assert len(rows) == len(applied) == 115
    assert [wrench_of(row) for row in rows] == applied
    # The node applied each push: up, sideways with its torque, and the one the reset ended.
    assert set(applied) == {(ZERO, ZERO), (UP, ZERO), (SIDEWAYS, TWIST), ((0.0, 5.0, 0.0), ZERO)}


def received(topic: str, message, stamp_ns: int) -> Received:
    """Return ``message`` stamped ``stamp_ns``, as received on ``topic``."""
    set_stamp(message.header.stamp, stamp_ns)
    return Received(topic, 0, serialize_message(message))


def test_a_wrench_applies_from_its_stamp_whatever_the_order_of_arrival():
    """
    The rows follow the node's policy, not the order in which the recorder got the messages.

    1 ms ticks in 'world'. A push stamped at tick 3 that reaches the recorder after tick 5's
    pose, and its zero wrench stamped at tick 8 after tick 9's: ticks 3 to 7 carry it. A wrench
    in 'map' (the node takes none but its own frame) changes nothing; an unstamped one, come
    after tick 12's pose, applies from tick 13; one over max_wrench_force changes nothing.
    """
    ms = 1_000_000

    def tick(k: int) -> list:
        pose, twist = PoseStamped(), TwistStamped()
        pose.header.frame_id = twist.header.frame_id = 'world'
        pose.pose.orientation.w = 1.0
        return [received('pose', pose, k * ms), received('twist', twist, k * ms)]

    def wrench(force, stamp_ns: int, frame: str = '') -> Received:
        return received('wrench', wrench_message(force, ZERO, frame), stamp_ns)
    messages = []
    for k in range(1, 21):
        messages += tick(k)
        messages += {5: [wrench(UP, 3 * ms)], 9: [wrench(ZERO, 8 * ms)],
                     10: [wrench(SIDEWAYS, 10 * ms, 'map')], 12: [wrench(SIDEWAYS, 0)],
                     15: [wrench((0.0, 0.0, 2 * MAX_WRENCH_FORCE), 0)]}.get(k, [])
    rows = tick_rows(messages, {'anchor': ZERO, 'max_wrench_force': MAX_WRENCH_FORCE})
    assert [row.stamp_ns // ms for row in rows] == list(range(1, 21))
    forces = [row.wrench_force for row in rows]
    assert forces == [ZERO] * 2 + [UP] * 5 + [ZERO] * 5 + [SIDEWAYS] * 8


def test_the_pushes_are_read_back_as_spans(pushed_recording):
    """
    Three pushes: the stamped one from its start to its end, to the tick.

    The second lasts from the tick after it came (it is as old as the tick it came after) while
    it is at most WRENCH_TIMEOUT old: the ticks of WRENCH_TIMEOUT.
    """
    rows = pushed_recording['rows']
    first = rows[0].stamp_ns
    spans = push_spans(rows)
    assert [span.peak_force for span in spans] == [30.0, 10.0, 5.0]
    assert spans[0] == PushSpan((pushed_recording['began'] - first) * 1e-9,
                                (pushed_recording['ended'] - first) * 1e-9, 30.0)
    ticks = [sum(1 for row in rows if span.start <= row.time < span.end) for span in spans]
    assert ticks[:2] == [10, round(WRENCH_TIMEOUT * RATE)]
    pushed = [row.time for row in rows if wrench_of(row) != (ZERO, ZERO)]
    assert pushed == [row.time for row in rows
                      if any(span.start <= row.time < span.end for span in spans)]


def test_the_figure_draws_the_pushes(pushed_recording):
    """
    A row for the applied force, a span per push on each time plot, the pushed path marked.

    The spans are those of ``push_spans``, each with a line at its start; the force lines are
    the rows' force components; the marked stretch of each path holds exactly the anchor
    positions of the pushed rows, with a triangle at each push's first.
    """
    rows = pushed_recording['rows']
    spans = push_spans(rows)
    figure = draw_figure(rows, anchor=pushed_recording['start']['anchor'], frame_id='world')
    top, side, error, speed, spin, wrench, torque = figure.axes
    assert figure.get_suptitle().endswith(', 3 pushes')
    for axes in (error, speed, wrench):
        assert [(patch.get_x(), patch.get_x() + patch.get_width()) for patch in axes.patches] \
            == [(span.start, span.end) for span in spans]
        assert all(patch.get_facecolor()[:3] == to_rgb(PUSH_COLOR) for patch in axes.patches)
        starts = [line.get_xdata() for line in axes.get_lines() if line.get_color() == PUSH_COLOR]
        assert [tuple(x) for x in starts] == [(span.start, span.start) for span in spans]
    assert 'push' in [text.get_text() for text in speed.get_legend().get_texts()]
    forces = np.array([row.wrench_force for row in rows])
    lines = {line.get_label(): line for line in wrench.get_lines()}
    for index, axis in enumerate('xyz'):
        np.testing.assert_array_equal(lines[f'force {axis} (N)'].get_ydata(), forces[:, index])
    [torque_line] = torque.get_lines()
    assert torque_line.get_ydata().max() == 0.5
    pushed = np.array([wrench_of(row) != (ZERO, ZERO) for row in rows])
    anchors = np.array([row.anchor for row in rows])
    first = [rows.index(next(row for row in rows if row.time == span.start)) for span in spans]
    for axes, (i, j) in ((top, (0, 1)), (side, (0, 2))):
        lines = {line.get_label(): line for line in axes.get_lines()}
        marked, starts = lines['anchor while pushed'], lines['push start']
        assert marked.get_color() == starts.get_color() == PUSH_COLOR
        x, y = marked.get_xdata(), marked.get_ydata()
        np.testing.assert_array_equal(~np.isnan(x), pushed)
        np.testing.assert_array_equal(x[pushed], anchors[pushed, i])
        np.testing.assert_array_equal(y[pushed], anchors[pushed, j])
        np.testing.assert_array_equal(starts.get_xdata(), anchors[first, i])
        np.testing.assert_array_equal(starts.get_ydata(), anchors[first, j])


def test_a_figure_without_a_push_is_drawn_as_before(pushed_recording):
    """No push: two rows of plots, no span, no marked path, no push in the title."""
    rows = [row for row in pushed_recording['rows'] if row.time < push_spans(
        pushed_recording['rows'])[0].start]
    figure = draw_figure(rows, anchor=pushed_recording['start']['anchor'], frame_id='world')
    assert len(figure.axes) == 5 and 'push' not in figure.get_suptitle()
    assert not any(axes.patches for axes in figure.axes)
    assert not any(line.get_label() in ('anchor while pushed', 'push start') or
                   line.get_color() == PUSH_COLOR
                   for axes in figure.axes for line in axes.get_lines())


def test_the_csv_adds_the_wrench_after_the_old_columns(pushed_recording, tmp_path):
    """The wrench's six columns come last: the old columns read the same values as before."""
    rows = pushed_recording['rows']
    old = COLUMNS[:COLUMNS.index('grab_taken') + 1]
    assert COLUMNS == old + ('wrench_fx', 'wrench_fy', 'wrench_fz', 'wrench_tx', 'wrench_ty',
                             'wrench_tz')
    write_csv(tmp_path / 'run.csv', rows, metadata=['mouse_record of /mouse_constraint'])
    with open(tmp_path / 'run.csv', newline='') as stream:
        read = list(csv.DictReader(line for line in stream if not line.startswith('#')))
    assert len(read) == len(rows)
    for line, row in zip(read, rows):
        assert [line[name] for name in old] == [str(v) for v in row.fields()[:len(old)]]
        force = tuple(float(line[f'wrench_f{axis}']) for axis in 'xyz')
        torque = tuple(float(line[f'wrench_t{axis}']) for axis in 'xyz')
        assert (force, torque) == wrench_of(row)


def test_a_short_push_in_a_long_thinned_recording_keeps_its_ticks():
    """
    The figure's rows keep a push's first tick and the tick after it, however thinned.

    A 3-tick push at tick 1001 of 5000 rows kept to 8 (every 1024th row and the marks): the
    span read back from the kept rows is the push's own.
    """
    def row(index: int, force) -> Row:
        return Row(time=index * 1e-3, stamp_ns=index * 1_000_000, position=(0.0, 0.0, 1.0),
                   orientation=(0.0, 0.0, 0.0, 1.0), linear_velocity=ZERO,
                   angular_velocity=ZERO, anchor=(0.0, 0.0, 1.0), target=None,
                   anchor_error=None, speed=0.0, angular_speed=0.0, body_anchor=ZERO,
                   wrench_force=force)
    every = [row(index, UP if 1001 <= index < 1004 else ZERO) for index in range(5000)]
    kept = FigureRows(limit=8)
    for each in every:
        kept.add(each)
    assert kept.stride > 256 and len(kept.rows()) < 16
    assert push_spans(kept.rows()) == push_spans(every) == [
        PushSpan(every[1001].time, every[1004].time, math.hypot(*UP))]


def test_the_wrench_cli_pushes_once_the_subscribers_asked_for_listen(ros):
    """
    --subscribers 2 waits for both the node and the recorder; with one it sends nothing.

    A subscriber that matches after the push was sent never gets it: the recorder would miss a
    short push. Here one subscription (the node's) is there at first: the push waits its
    --timeout and ends with exit status 1, nothing sent; with the second (the recorder's) it
    pushes, and both get the wrench and the zero wrench that ends it.
    """
    node_side = ros.collect(WrenchStamped, WRENCH_TOPIC)
    arguments = ['--force', '0', '0', '3', '--duration', '0.05', '--subscribers', '2',
                 '--timeout', '0.3']
    alone = Push(build_parser().parse_args(arguments))
    pusher = ros.add(Node('mouse_wrench', context=ros.context))
    assert alone.run(pusher, ros.executor, StopRequest()) == 1
    assert alone.started_ns is None and not node_side
    recorder_side = ros.collect(WrenchStamped, WRENCH_TOPIC)
    push = Push(build_parser().parse_args(arguments))
    assert push.run(pusher, ros.executor, StopRequest()) == 0

    def forces(received) -> list:
        return [(m.wrench.force.x, m.wrench.force.y, m.wrench.force.z) for m in received]

    assert ros.spin_until(lambda: all(
        forces(received)[-1:] == [ZERO] for received in (node_side, recorder_side)))
    for received in (node_side, recorder_side):
        assert forces(received)[0] == (0.0, 0.0, 3.0)
        assert set(forces(received)[:-1]) == {(0.0, 0.0, 3.0)}


@pytest.mark.parametrize('text', ['0', '-1', '1.5', 'two'])
def test_the_wrench_cli_refuses_fewer_than_one_subscriber(text, capsys):
    """--subscribers is a whole number >= 1, else a usage error (exit 2)."""
    assert build_parser().parse_args(['--subscribers', '3']).subscribers == 3
    with pytest.raises(SystemExit) as exit_info:
        build_parser().parse_args(['--subscribers', text])
    assert exit_info.value.code == 2
    assert '--subscribers must be a whole number >= 1' in capsys.readouterr().err
