#!/usr/bin/env python3
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
What ``mouse_record`` spends per tick while it records: reading, rows, CSV, MCAP.

``python -m bench.recorder_cost [--quick]`` times, in this process and in interleaved rounds:
reading a serialized pose with ``deserialize_message`` against ``wire.cdr.stamped``'s raw
read, and a tick of a 1 kHz recording (a pose and a twist, serialized) taken by
``RecordingFiles`` as the recorder hands it over: rows made and written to the CSV, with and
without the MCAP file. Medians of the rounds, microseconds; 10000 ticks a round.
"""

import json
from pathlib import Path
import sys
import tempfile
import time

from bench.common import median, paired_ratio
from geometry_msgs.msg import PoseStamped, TwistStamped
from rclpy.serialization import deserialize_message, serialize_message

from mouse_constraint_ros.recording.received import MESSAGE_TYPES, Received
from mouse_constraint_ros.recording.recording_files import RecordingFiles
from mouse_constraint_ros.wire.cdr.stamped import decode_stamped, POSE
from mouse_constraint_ros.wire.interface import POSE_TOPIC, TWIST_TOPIC

TICKS = 10000


def _ticks(count: int) -> list:
    """Return ``count`` ticks of a body moving along x at 1 kHz: pose and twist, serialized."""
    received = []
    for n in range(count):
        stamp = 1_000_000_000 + n * 1_000_000
        pose, twist = PoseStamped(), TwistStamped()
        for message in (pose, twist):
            message.header.frame_id = 'world'
            message.header.stamp.sec, message.header.stamp.nanosec = divmod(stamp, 10 ** 9)
        pose.pose.position.x, pose.pose.orientation.w, twist.twist.linear.x = n * 1e-4, 1.0, 0.1
        received += [Received(POSE_TOPIC, stamp, serialize_message(pose)),
                     Received(TWIST_TOPIC, stamp, serialize_message(twist))]
    return received


def _record(received: list, folder: Path, mcap: bool) -> None:
    files = RecordingFiles(folder / 'run.csv', folder / 'run.mcap' if mcap else None)
    topic_names = {key: f'/{key}'.replace('//', '/') for key in MESSAGE_TYPES}
    files.start({'anchor': (0.2, 0.1, 0.05)}, topic_names=topic_names, offered_qos={})
    for message in received:
        files.add(message)
    files.close()


def run(quick: bool = False) -> dict:
    """Return the section: microseconds per read and per tick, and the ratios."""
    begun = time.perf_counter()
    ticks = 2000 if quick else TICKS
    received = _ticks(ticks)
    data = received[0].data
    reads = 2000

    def per_read(read):
        def timed() -> float:
            start = time.perf_counter()
            for _ in range(reads):
                read()
            return (time.perf_counter() - start) / reads * 1e6
        return timed

    with tempfile.TemporaryDirectory() as folder:
        def per_tick(mcap: bool):
            def timed() -> float:
                start = time.perf_counter()
                _record(received, Path(folder), mcap)
                return (time.perf_counter() - start) / ticks * 1e6
            return timed
        timed = {
            'deserialize': per_read(lambda: deserialize_message(data, MESSAGE_TYPES[POSE_TOPIC])),
            'raw': per_read(lambda: decode_stamped(data, POSE)),
            'csv': per_tick(False), 'csv_mcap': per_tick(True)}
        times = {name: [] for name in timed}
        for _ in range(3 if quick else 7):  # interleaved: a slow spell hits all alike
            for name, measure in timed.items():
                times[name].append(measure())
    rows = [
        {'case': 'a pose read: deserialize_message', 'us': median(times['deserialize'])},
        {'case': 'a pose read: wire.cdr.stamped (raw)', 'us': median(times['raw']),
         'ratio': paired_ratio(times['deserialize'], times['raw'])},
        {'case': 'a 1 kHz tick: rows and CSV', 'us': median(times['csv'])},
        {'case': 'a 1 kHz tick: rows, CSV and MCAP', 'us': median(times['csv_mcap'])},
    ]
    return {
        'title': 'The recorder per tick: reading, rows, CSV and MCAP',
        'text': ('`python -m bench.recorder_cost`. In this process, interleaved rounds: a '
                 'serialized PoseStamped read by rclpy and read raw; 10000 ticks of a 1 kHz '
                 'recording (a pose and a twist each) handed to `RecordingFiles` as the '
                 'recorder hands them, rows made and written, with and without the MCAP file. '
                 'Medians; the ratio is how many times cheaper the raw read is.'),
        'columns': [['case', 'case', ''], ['us', 'us', '.1f'], ['ratio', 'x cheaper', '.1f']],
        'rows': rows,
        'notes': [],
        'elapsed_s': time.perf_counter() - begun,
    }


if __name__ == '__main__':
    print(json.dumps(run(quick='--quick' in sys.argv), indent=1))
