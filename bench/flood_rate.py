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
The 500 Hz node under a 5 000/s target flood, run after run: whether each holds the rate.

The node is the installed ``mouse_constraint_node`` at 500 Hz (its own process, no gravity,
damping 2/s, workspace_radius 100 m); the flooder another process publishing 5 000
``PointStamped`` targets a second as message objects (a plain rclpy publisher), round a circle;
this process observes pose and twist (``test_support.hardening_tools.run_flood``). A run holds
the rate when the poses published over the flood, counted by their grid stamps, are within 1 %
of 500 a second. ``bench.flood`` measures one run of each of its floods at 1 kHz; here the
same flood is run several times, since a node that falls behind in one run of several does
not show in one.

With ``--compare PATH``, each run is made twice, alternately: with the node of this tree and
with the node of the source tree at PATH (its ``mouse_constraint_ros``, run by this venv's
interpreter), so that two versions are measured in the same run of the machine.
``--hogs N`` keeps N more processes busy at a full core each meanwhile.

Standalone: ``python -m bench.flood_rate [--quick] [--runs N] [--seconds S] [--compare PATH]
[--hogs N]``.
"""

import argparse
import os
from pathlib import Path
import subprocess
import sys
import time
from typing import List, Optional

from bench import common
from bench import ros_process

from test_support.ros_harness import RosHarness

NODE_RATE = 500.0
FLOOD_RATE = 5000.0
RUNS = 6
QUICK_RUNS = 2
SECONDS = 5.0
QUICK_SECONDS = 2.0
RATE_TOLERANCE = 0.01
HOG = 'while True:\n    pass\n'


def _isolate() -> None:
    # rclpy reads these at init, and the child processes inherit them.
    os.environ.update(ros_process.environment())


def _one_run(seconds: float, tree: Optional[Path]) -> dict:
    """Return one flood run's figures, with the node of this tree or of ``tree``."""
    from test_support.flood_run import run_flood
    prefix, environment = (), None
    if tree is not None:
        prefix = (sys.executable,)
        environment = dict(os.environ, PYTHONPATH=str(tree))
    harness = RosHarness()
    try:
        result = run_flood(harness, seconds, FLOOD_RATE, 0, NODE_RATE, True,
                           node_prefix=prefix, node_environment=environment)
    finally:
        harness.shutdown()
    ratio = result['stamp_rate_hz'] / NODE_RATE
    return {
        'rate': result['stamp_rate_hz'],
        'ratio': ratio,
        'held': 'yes' if abs(ratio - 1.0) <= RATE_TOLERANCE else 'NO',
        'missing': result['missing_ticks'],
        'sent': result['flood']['rate'],
        'late_p99': result['late_ms_p99'],
        'cpu': 100.0 * result['node_cpu_share'],
        'run_delay': result['node_run_delay_ms'],
        'rss_growth': result['rss_end_mb'] - result['rss_start_mb'],
    }


def run(quick: bool, runs: Optional[int] = None, seconds: Optional[float] = None,
        compare: Optional[Path] = None, hogs: int = 0) -> dict:
    """Measure ``runs`` floods (each twice with ``compare``); return the section."""
    start = time.perf_counter()
    _isolate()
    runs = runs or (QUICK_RUNS if quick else RUNS)
    seconds = seconds or (QUICK_SECONDS if quick else SECONDS)
    trees = [('this tree', None)] + ([(f'{compare}', compare)] if compare is not None else [])
    busy: List[subprocess.Popen] = [subprocess.Popen([sys.executable, '-c', HOG])
                                    for _ in range(hogs)]
    rows = []
    try:
        for number in range(1, runs + 1):
            for label, tree in trees:
                row = _one_run(seconds, tree)
                row.update(run=number, node=label)
                rows.append(row)
                print(f'run {number} ({label}): {row["rate"]:.1f} poses/s, '
                      f'{row["missing"]} missing', flush=True)
    finally:
        for hog in busy:
            hog.kill()
            hog.wait()
    notes = []
    for label, _ in trees:
        mine = [row for row in rows if row['node'] == label]
        held = sum(row['held'] == 'yes' for row in mine)
        notes.append(f'{label}: held {NODE_RATE:g}/s within {100 * RATE_TOLERANCE:g} % in '
                     f'{held} of {len(mine)} runs; lowest {min(r["rate"] for r in mine):.1f} '
                     'poses/s.')
    notes += [
        'poses/s: poses published over the flood per second, counted by their grid stamps; '
        'missing: ticks absent from the stamps (dropped by the node).',
        '"node waited for CPU" is its main thread\'s run-queue time over the flood (/proc '
        'schedstat): large values mean the machine, not the node, was short of CPU.',
    ] + ([f'{hogs} more processes kept a core busy each meanwhile.'] if hogs else [])
    return {
        'title': f'The {NODE_RATE:g} Hz node under a {FLOOD_RATE:g}/s target flood, '
                 f'{runs} runs of {seconds:g} s',
        'text': 'Command: `python -m bench.flood_rate`. ' + ' '.join(
            __doc__.split('\n\n')[1].split()),
        'columns': [
            ['run', 'run', ''],
            ['node', 'node', ''],
            ['rate', 'poses/s', '.1f'],
            ['held', 'held', ''],
            ['missing', 'ticks missing', ''],
            ['sent', 'sent /s', '.0f'],
            ['late_p99', 'late p99 ms', '.1f'],
            ['cpu', 'node CPU %', '.0f'],
            ['run_delay', 'node waited for CPU ms', '.0f'],
            ['rss_growth', 'RSS growth MB', '.1f'],
        ],
        'rows': rows,
        'notes': notes,
        'elapsed_s': time.perf_counter() - start,
    }


def main(argv=None) -> int:
    """Run the benchmark on its own and print its table."""
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[1])
    parser.add_argument('--quick', action='store_true',
                        help=f'{QUICK_RUNS} runs of {QUICK_SECONDS:g} s')
    parser.add_argument('--runs', type=int, default=None, help=f'runs (default {RUNS})')
    parser.add_argument('--seconds', type=float, default=None,
                        help=f'flood seconds per run (default {SECONDS:g})')
    parser.add_argument('--compare', type=Path, default=None,
                        help="another source tree whose node runs alternately with this one's")
    parser.add_argument('--hogs', type=int, default=0,
                        help='processes kept busy at a full core each meanwhile')
    args = parser.parse_args(argv)
    print(common.section_markdown(run(args.quick, args.runs, args.seconds, args.compare,
                                      args.hogs)))
    return 0


if __name__ == '__main__':
    sys.exit(main())
