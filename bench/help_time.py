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
Each console script's ``--help``, timed as a user typing it would, against the rclpy floor.

The floor is a Python that imports what any ROS command line of this package needs and does
nothing (``FLOOR_IMPORTS``: rclpy, argparse and the message packages). Each command runs
``ROUNDS`` times, in rounds that take the floor and every script in turn (a busy spell of the
machine hits them all alike), each timed from its start to its exit. Per command the best and
the median of its runs, and the ratio of its best to the floor's best of the same run; target:
every ratio <= 2. Standalone: ``python -m bench.help_time [--quick]`` prints the section as JSON.
"""

import subprocess
import sys
import time
from typing import Dict, List, Sequence

from bench import common
from bench import ros_process

from test_support import processes

FLOOR_IMPORTS = ('rclpy, argparse, geometry_msgs.msg, sensor_msgs.msg, rcl_interfaces.srv, '
                 'std_srvs.srv')
FLOOR = 'floor'
SCRIPTS = ('mouse_constraint_node', 'mouse_view', 'mouse_marker', 'mouse_record', 'mouse_target',
           'mouse_wrench', 'mouse_ctl')
ROUNDS, QUICK_ROUNDS = 7, 2
TARGET_RATIO = 2.0


def command(name: str) -> List[str]:
    """Return the command line of ``name``: the floor, or the console script with --help."""
    if name == FLOOR:
        return [sys.executable, '-c', f'import {FLOOR_IMPORTS}']
    return [str(processes.BIN / name), '--help']


def seconds(arguments: Sequence[str]) -> float:
    """Return the seconds ``arguments`` took from its start to its exit; raise if it failed."""
    start = time.perf_counter()
    result = subprocess.run(arguments, env=ros_process.environment(), capture_output=True,
                            text=True, timeout=60)
    elapsed = time.perf_counter() - start
    if result.returncode != 0:
        raise RuntimeError(f'{" ".join(arguments)} exited {result.returncode}: '
                           f'{result.stderr.strip()[-2000:]}')
    return elapsed


def run(quick: bool = False) -> dict:
    """Return the section: each script's --help against the floor, best and median."""
    start = time.perf_counter()
    names = (FLOOR, *SCRIPTS)
    times: Dict[str, List[float]] = {name: [] for name in names}
    seconds(command(FLOOR))  # the first start of all reads the files from disk
    for _ in range(QUICK_ROUNDS if quick else ROUNDS):
        for name in names:
            times[name].append(seconds(command(name)))
    floor = min(times[FLOOR])
    rows = [{'command': f'python -c "import {FLOOR_IMPORTS}"' if name == FLOOR
             else f'{name} --help', 'best_s': min(values), 'median_s': common.median(values),
             'ratio': min(values) / floor} for name, values in times.items()]
    worst = max(rows[1:], key=lambda row: row['ratio'])
    met = worst['ratio'] <= TARGET_RATIO
    return {
        'title': "Each console script's --help against the rclpy floor",
        'text': ('Command: `python -m bench.help_time`. Each command timed from its start to '
                 f'its exit, {len(times[FLOOR])} rounds, each round the floor and every script '
                 "in turn; ratio: its best over the floor's best of this run."),
        'columns': [['command', 'command', ''], ['best_s', 'best (s)', '.3f'],
                    ['median_s', 'median (s)', '.3f'], ['ratio', 'best / floor', '.2f']],
        'rows': rows,
        'notes': [f'Largest ratio {worst["ratio"]:.2f} ({worst["command"]}): target <= '
                  f'{TARGET_RATIO:g}, ' + ('met.' if met else 'not met.')],
        'figures': {'floor_s': floor, 'largest_ratio': worst['ratio'],
                    **{f'{row["command"].split()[0]}_ratio': row['ratio'] for row in rows[1:]}},
        'elapsed_s': time.perf_counter() - start,
    }


if __name__ == '__main__':
    import json
    print(json.dumps(run(quick='--quick' in sys.argv), indent=1, default=str))
