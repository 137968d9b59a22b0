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
``mouse_record`` keeps flat memory however long it records, and refuses a duration it cannot.

The recording's files are fed, in lockstep with a simulated node's clock, what the recorder
receives: a pose and a twist every tick, a stamped drag of 2 s every 10 s (a target a tick), a
grab and the node's anchor change every 30 s; the flushes come every 0.25 s of that clock, as
they come every 0.25 s of wall time while recording. An hour of a 10 Hz node makes an hour's
chunks of the MCAP file and 36000 rows, in seconds; what a row keeps does not depend on the
node's rate.
"""

import gc
import math
import os
from pathlib import Path
import random

from mcap.reader import make_reader
import pytest
from rcl_interfaces.msg import Parameter as ParameterMessage
from rcl_interfaces.msg import ParameterEvent
from rcl_interfaces.msg import ParameterType
from rclpy.serialization import serialize_message

from mouse_constraint_ros.cli.record import MAX_DURATION
from mouse_constraint_ros.cli.record import parse_arguments
from mouse_constraint_ros.recording.figure_rows import FigureRows
from mouse_constraint_ros.recording.missing_ticks import Grid
from mouse_constraint_ros.recording.missing_ticks import missing_ticks
from mouse_constraint_ros.recording.missing_ticks import TickCounter
from mouse_constraint_ros.recording.received import MESSAGE_TYPES
from mouse_constraint_ros.recording.received import PARAMETER_EVENTS_TOPIC
from mouse_constraint_ros.recording.received import Received
from mouse_constraint_ros.recording.recording_files import FLUSH_SECONDS
from mouse_constraint_ros.recording.recording_files import RecordingFiles
from mouse_constraint_ros.recording.rows import Row
from mouse_constraint_ros.wire.cdr.geometry import PoseStampedLayout
from mouse_constraint_ros.wire.cdr.geometry import TwistStampedLayout
from mouse_constraint_ros.wire.interface import GRAB_TOPIC
from mouse_constraint_ros.wire.interface import POSE_TOPIC
from mouse_constraint_ros.wire.interface import TARGET_TOPIC
from mouse_constraint_ros.wire.interface import TWIST_TOPIC
from mouse_constraint_ros.wire.messages import point_message
from mouse_constraint_ros.wire.messages import set_stamp

RATE_HZ = 10.0
TICK_NS = round(1e9 / RATE_HZ)
START_NS = 1_000_000_000
ANCHOR = (0.2, 0.1, 0.05)
# The run: an hour of the node's clock; memory is compared from minute 10 to its end.
TICKS = round(3600 * RATE_HZ)
WARM_TICK = round(600 * RATE_HZ)
# The figure's rows, filled and thinned within the first 10 minutes.
LIMIT = 2000
# Allowed growth of the resident memory from WARM_TICK to TICKS. Keeping every row grew it by
# 1 KB a row (30 MB here), the MCAP's chunk indexes by 700 bytes a flush (8 MB here).
TOLERANCE_BYTES = 2 ** 20


def resident_bytes() -> int:
    """Return this process's resident memory (bytes), after a full garbage collection."""
    gc.collect()
    with open('/proc/self/statm') as statm:
        return int(statm.read().split()[1]) * os.sysconf('SC_PAGE_SIZE')


def anchor_event(anchor, stamp_ns: int) -> bytes:
    """Return the node's ``/parameter_events`` message that sets its anchor, serialized."""
    event = ParameterEvent()
    event.node = '/mouse_constraint'
    set_stamp(event.stamp, stamp_ns)
    parameter = ParameterMessage(name='anchor')
    parameter.value.type = ParameterType.PARAMETER_DOUBLE_ARRAY
    parameter.value.double_array_value = [float(c) for c in anchor]
    event.changed_parameters = [parameter]
    return serialize_message(event)


def received(ticks: int):
    """Yield (tick, message) as a recorder in lockstep with a 1 kHz node receives them."""
    pose, twist = PoseStampedLayout('world'), TwistStampedLayout('world')
    for tick in range(ticks):
        stamp = START_NS + tick * TICK_NS
        t = tick / RATE_HZ
        second = tick // round(RATE_HZ)
        position = (0.3 * math.cos(t), 0.3 * math.sin(t), 1.0)
        yield tick, Received(POSE_TOPIC, stamp, pose.pack(stamp, position, (0.0, 0.0, 0.0, 1.0)))
        yield tick, Received(TWIST_TOPIC, stamp, twist.pack(
            stamp, (-0.3 * math.sin(t), 0.3 * math.cos(t), 0.0), (0.0, 0.0, 0.1)))
        if second % 10 < 2:  # a 2 s drag every 10 s
            yield tick, Received(TARGET_TOPIC, stamp, serialize_message(
                point_message((position[0], position[1], 1.05), 'world', stamp)))
        if tick % round(30 * RATE_HZ) == 0:  # a grab at the COM, and the node's anchor set to it
            yield tick, Received(GRAB_TOPIC, stamp, serialize_message(
                point_message(position, 'world', 0)))
            yield tick, Received(PARAMETER_EVENTS_TOPIC, stamp,
                                 anchor_event((0.0, 0.0, 0.0), stamp))


def test_the_recording_memory_stays_flat_however_long_it_records(tmp_path):
    """An hour of ticks into CSV and MCAP: no growth from minute 10 on beyond the tolerance."""
    now = [0.0]
    files = RecordingFiles(tmp_path / 'run.csv', tmp_path / 'run.mcap', clock=lambda: now[0],
                           figure_rows=FigureRows(limit=LIMIT))
    files.start({'anchor': ANCHOR, 'rate_hz': RATE_HZ},
                topic_names={key: '/' + key.lstrip('/') for key in MESSAGE_TYPES},
                offered_qos={})
    warm, count = None, 0
    for tick, message in received(TICKS):
        if tick == WARM_TICK and warm is None:
            warm = resident_bytes()
        now[0] = tick / RATE_HZ  # the flushes every FLUSH_SECONDS of the node's clock
        files.add(message)
        count += 1
    growth = resident_bytes() - warm
    files.close()
    print(f'resident memory grew {growth} bytes from tick {WARM_TICK} to {TICKS}')
    assert growth <= TOLERANCE_BYTES, f'{growth / 2 ** 20:.1f} MiB from tick {WARM_TICK} on'
    # What was recorded is all there: every row in the CSV, the figure's rows bounded.
    lines = (tmp_path / 'run.csv').read_text().splitlines()
    assert sum(1 for line in lines if line[:1].isdigit()) == files.figure_rows.count
    assert files.figure_rows.count >= TICKS - 10 and files.missing().missing == 0
    assert len(files.rows()) <= LIMIT
    with open(tmp_path / 'run.mcap', 'rb') as stream:
        summary = make_reader(stream).get_summary()
    assert len(summary.chunk_indexes) >= 3600 / (2 * FLUSH_SECONDS)
    assert summary.statistics.message_count == count


def row(index: int, grab=None) -> Row:
    """Return a row of tick ``index`` at 1 kHz, with a grab mark when given."""
    return Row(time=index * 1e-3, stamp_ns=index * TICK_NS, position=(0.0, 0.0, 1.0),
               orientation=(0.0, 0.0, 0.0, 1.0), linear_velocity=(0.0,) * 3,
               angular_velocity=(0.0,) * 3, anchor=ANCHOR, target=None, anchor_error=None,
               speed=0.0, angular_speed=0.0, body_anchor=ANCHOR, grab=grab,
               grab_taken=None if grab is None else True)


def test_the_figure_rows_are_bounded_and_evenly_spread():
    """All rows up to the limit; then every 2nd, 4th ...; grab rows and the last row kept."""
    rows = FigureRows(limit=16)
    for index in range(10):
        rows.add(row(index))
    assert [r.stamp_ns // TICK_NS for r in rows.rows()] == list(range(10))
    for index in range(10, 1001):
        rows.add(row(index, grab=(0.0, 0.0, 1.0) if index == 333 else None))
    kept = [r.stamp_ns // TICK_NS for r in rows.rows()]
    assert len(rows) == 1001 and len(kept) <= 16 and rows.stride == 128
    assert kept == sorted([*range(0, 1001, 128), 333, 1000])
    # A flood of grabs keeps a quarter of the limit as grab rows, the rest evenly thinned.
    flooded = FigureRows(limit=16)
    for index in range(1000):
        flooded.add(row(index, grab=(0.0, 0.0, 1.0)))
    kept = flooded.rows()
    assert len(kept) <= 16 and [r.stamp_ns // TICK_NS for r in kept][:4] == [0, 1, 2, 3]
    with pytest.raises(ValueError):
        FigureRows(limit=4)


@pytest.mark.parametrize('grid', [Grid(1000.0), Grid(1000.0, 300.0), None])
def test_the_ticks_counted_as_they_come_are_the_ticks_missing_of_all_rows(grid):
    """TickCounter, one stamp at a time, gives missing_ticks's report of the whole list."""
    random.seed(7)
    stamps, stamp = [], 0
    for _ in range(3000):
        stamp += random.choice([TICK_NS, TICK_NS, TICK_NS, 2 * TICK_NS, 0, 7 * TICK_NS,
                                -5 * TICK_NS, TICK_NS + 333])
        stamps.append(stamp)
    counter = TickCounter(grid)
    for stamp in stamps:
        counter.add(stamp)
    assert counter.result() == missing_ticks(stamps, grid)
    assert counter.result().missing > 0 and counter.result().restarts > 0


@pytest.mark.parametrize('duration', ['1e308', '3e9', str(MAX_DURATION * 1.0001)])
def test_a_duration_the_stamps_cannot_hold_is_a_usage_error(duration, capsys):
    """-d beyond the stamps' range is refused at parsing (exit 2), as -d inf is."""
    with pytest.raises(SystemExit) as exit_info:
        parse_arguments(['-d', duration])
    assert exit_info.value.code == 2
    error = capsys.readouterr().err
    assert 'usage: mouse_record' in error and f'<= {MAX_DURATION:.10g}' in error
    assert parse_arguments(['-d', str(MAX_DURATION)]).duration == MAX_DURATION


def test_the_recording_files_start_with_no_row(tmp_path):
    """Before start there is nothing to report; a recording without rows writes no trailer."""
    files = RecordingFiles(Path(tmp_path) / 'none.csv')
    assert files.missing() is None and files.rows() == []
    files.start({'anchor': ANCHOR}, topic_names={}, offered_qos={})
    files.close()
    assert not (tmp_path / 'none.csv').read_text().splitlines()[-1].startswith('# ')
