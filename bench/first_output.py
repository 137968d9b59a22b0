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
From a process's start to its first output: a bare rclpy publisher, the node, the recorder.

Each round, on a ROS domain of its own, this process subscribes to ``pose`` and then starts, one
after the other, each timed from its start (``Popen``) to:

- bare publisher: ``bench.bare_timer --twist`` at the node's rate (Python, rclpy, a timer
  publishing pose and twist): its first pose received here;
- node: ``mouse_constraint_node`` with config/params.yaml: its first pose received here;
- recorder: ``mouse_record`` against that node, running: its log line that it has the node's
  parameters and the first pose (``START_LINE``), and the first row in its CSV, read from here;
  and, as the recorder's own share, from the moment this process sees the recorder's pose
  subscription in the graph (its pose stream is being discovered) to that row. That moment is
  this process's discovery of the recorder, not the node's: either may be the late one.

Discovery is Fast DDS's default (no profile), as a user's shell has it: a new participant
whose first exchange with the others is lost waits for their next announcement, up to 3 s, and
the bare publisher pays it as the node does. Figures: per case the median and the largest over
the rounds. Target: the recorder's first row within 1 s of its subscription seen.
Standalone: ``python -m bench.first_output [--quick]`` prints the section as JSON.
"""

import os
from pathlib import Path
import sys
import tempfile
import time
from typing import Callable, Dict, List, Optional

from bench import common
from bench import ros_process
from geometry_msgs.msg import PoseStamped
import rclpy
from rclpy.executors import SingleThreadedExecutor
from rclpy.node import Node

from mouse_constraint_ros.wire.interface import POSE_TOPIC, STATE_QOS
from test_support import processes

ROUNDS, QUICK_ROUNDS = 5, 2
RATE = 1000.0
TIMEOUT = 60.0
TARGET_ROW_S = 1.0
PROFILE_VARIABLE = 'FASTRTPS_DEFAULT_PROFILES_FILE'
CASES = ('bare publisher: first pose', 'node: first pose',
         "recorder: the node's parameters and first pose in (its start line)",
         'recorder: first row', 'recorder: first row after its start line',
         'recorder: first row after its subscription was seen')
# What the recorder logs once it has the node's parameters and the first pose.
START_LINE = ' m (body frame) from '


class Watcher:
    """This process's side: a pose subscription on the round's domain, and its executor."""

    def __init__(self, domain_id: int) -> None:
        self.context = rclpy.Context()
        rclpy.init(context=self.context, domain_id=domain_id)
        self.node = Node('first_output_watcher', context=self.context)
        self.executor = SingleThreadedExecutor(context=self.context)
        self.executor.add_node(self.node)
        self.first: Optional[float] = None
        self.subscription = None
        self.listen()

    def listen(self) -> None:
        """Subscribe anew: what an earlier publisher left queued is not taken for a first pose."""
        if self.subscription is not None:
            self.node.destroy_subscription(self.subscription)
        self.first = None
        self.subscription = self.node.create_subscription(PoseStamped, POSE_TOPIC, self._on_pose,
                                                          STATE_QOS)

    def _on_pose(self, _message: PoseStamped) -> None:
        if self.first is None:
            self.first = time.monotonic()

    def spin_until(self, condition: Callable[[], bool], what: str,
                   process: Optional[processes.ChildProcess] = None) -> float:
        """Spin until ``condition()``; return ``time.monotonic()`` then."""
        deadline = time.monotonic() + TIMEOUT
        while not condition():
            if (process is not None and not process.alive()) or time.monotonic() > deadline:
                log = '' if process is None else process.log()[-2000:]
                raise RuntimeError(f'{what}: not within {TIMEOUT:g} s\n{log}')
            self.executor.spin_once(timeout_sec=0.002)
        return time.monotonic()

    def close(self) -> None:
        self.executor.shutdown()
        self.node.destroy_node()
        rclpy.try_shutdown(context=self.context)


def _environment(domain_id: int) -> Dict[str, str]:
    environment = processes.private_environment(domain_id)
    environment.pop(PROFILE_VARIABLE, None)
    return environment


def _rows(path: Path) -> int:
    try:
        text = path.read_text()
    except FileNotFoundError:
        return 0
    lines = [line for line in text[:text.rfind('\n') + 1].splitlines()
             if not line.startswith('#')]
    return max(0, len(lines) - 1)


def one_round(domain_id: int, folder: Path) -> Dict[str, float]:
    """Return the seconds of each case of ``CASES`` in one round on ``domain_id``."""
    environment = _environment(domain_id)
    watcher = Watcher(domain_id)
    seconds = {}
    try:
        start = time.monotonic()
        with processes.ChildProcess(ros_process.bench_command(
                'bare_timer', '--rate', str(RATE), '--twist'), environment=environment) as bare:
            seconds[CASES[0]] = watcher.spin_until(lambda: watcher.first is not None,
                                                   'the bare publisher', bare) - start
        watcher.spin_until(lambda: not watcher.node.count_publishers(POSE_TOPIC),
                           'the bare publisher gone')
        watcher.listen()
        command = processes.node_command('--params-file',
                                         str(ros_process.ROOT / 'config' / 'params.yaml'))
        start = time.monotonic()
        with processes.ChildProcess(command, environment=environment) as node:
            seconds[CASES[1]] = watcher.spin_until(lambda: watcher.first is not None,
                                                   'the node', node) - start
            csv_path = folder / f'round_{domain_id}.csv'
            start = time.monotonic()
            with processes.ChildProcess(
                    [str(processes.BIN / 'mouse_record'), '-d', '60', '-o',
                     str(csv_path.with_suffix('')), '--timeout', str(TIMEOUT)],
                    environment=environment) as recorder:
                events: Dict[str, float] = {}

                def watch() -> bool:
                    now = time.monotonic()
                    if 'seen' not in events and watcher.node.count_subscribers(POSE_TOPIC) > 1:
                        events['seen'] = now
                    if 'line' not in events and START_LINE in recorder.log():
                        events['line'] = now
                    if 'row' not in events and _rows(csv_path) > 0:
                        events['row'] = now
                    return len(events) == 3
                watcher.spin_until(watch, 'the first row', recorder)
            seconds[CASES[2]] = events['line'] - start
            seconds[CASES[3]] = events['row'] - start
            seconds[CASES[4]] = events['row'] - events['line']
            seconds[CASES[5]] = events['row'] - events['seen']
    finally:
        watcher.close()
    return seconds


def run(quick: bool = False) -> dict:
    """Return the section: each case's seconds over the rounds."""
    began = time.perf_counter()
    os.environ.update(ros_process.environment())
    times: Dict[str, List[float]] = {case: [] for case in CASES}
    with tempfile.TemporaryDirectory(prefix='mouse_bench_first_') as folder:
        for round_ in range(QUICK_ROUNDS if quick else ROUNDS):
            for case, value in one_round(ros_process.DOMAIN_ID + 40 + round_,
                                         Path(folder)).items():
                times[case].append(value)
            print('  ' + ', '.join(f'{case} {values[-1]:.2f} s'
                                   for case, values in times.items()),
                  file=sys.stderr, flush=True)
    rows = [{'case': case, 'median_s': common.median(values), 'largest_s': max(values),
             'runs': ' '.join(f'{v:.2f}' for v in values)} for case, values in times.items()]
    largest_row = max(times[CASES[5]])
    return {
        'title': 'From a start to the first output: a bare rclpy publisher, node, recorder',
        'text': ("Command: `python -m bench.first_output`. Each timed from its process's start "
                 "to its first pose received in another process, the recorder's log line that "
                 "it has the node's parameters and first pose, or the first row in its CSV; the "
                 "last row from the recorder's pose subscription seen in the graph. "
                 f"{len(times[CASES[0]])} rounds, each on its own domain, Fast DDS's default "
                 'discovery.'),
        'columns': [['case', 'case', ''], ['median_s', 'median (s)', '.2f'],
                    ['largest_s', 'largest (s)', '.2f'], ['runs', 'each round (s)', '']],
        'rows': rows,
        'notes': [f"The recorder's first row after its subscription was seen: largest "
                  f'{largest_row:.2f} s, target <= {TARGET_ROW_S:g} s: '
                  + ('met.' if largest_row <= TARGET_ROW_S else 'not met.'),
                  "0 or less: this process saw the recorder's subscription only once the row was "
                  'there (its own discovery of the recorder was the late one); seconds: the '
                  "node's discovery of the recorder was (a lost first exchange waits for the next "
                  'announcement, up to 3 s). A row is written once poses stamped 0.5 s after it '
                  'have come (docs/recording.md).'],
        'figures': {'bare_first_pose_s': common.median(times[CASES[0]]),
                    'node_first_pose_s': common.median(times[CASES[1]]),
                    'recorder_start_line_s': common.median(times[CASES[2]]),
                    'recorder_first_row_s': common.median(times[CASES[3]]),
                    'recorder_row_after_start_line_largest_s': max(times[CASES[4]]),
                    'recorder_row_after_subscription_largest_s': largest_row},
        'elapsed_s': time.perf_counter() - began,
    }


if __name__ == '__main__':
    import json
    print(json.dumps(run(quick='--quick' in sys.argv), indent=1, default=str))
