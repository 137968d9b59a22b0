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
The node under target floods: its rate held, its outputs finite, its drops warned and undone.

The node is the installed ``mouse_constraint_node`` at 1 kHz (its own process, no gravity,
damping 2/s, workspace_radius 100 m); the flooder is another process
(``test_support.hardening_tools flood``) publishing ``PointStamped`` targets that go round a
circle of 0.3 m in 2 s, its phase the system clock's; this process observes, reading pose and
twist. ``test_support.flood_run.run_flood`` makes the measurement; the hardening tests
assert on a shorter flood. Cases:

- 5 000 targets/s from a plain rclpy publisher (message objects, ``publish(msg)``): the rate
  the node holds (within 1 %);
- unbounded: a plain rclpy publisher as fast as it can publish (a core of its own): outputs
  finite, any dropped ticks warned in the node's log, and the time after the flood's end at
  which the last missing tick was due (back at full rate: within 1 s);
- 20 000 targets/s, every other one hostile (NaN, inf, 1e300, beyond the workspace, foreign
  frames, absurd stamps): the same figures while the node rejects half of what it gets.

Measured too: the output rate counted by DDS write time, how late the node wrote its ticks
(write time - stamp), its RSS after start and at the end, its CPU share and how long its main
thread waited for a CPU (a busy machine shows there), and the anchor's lag behind the target's
phase (median over the flood: a backlog of old targets would grow it). Nothing here asserts.

Standalone: ``python -m bench.flood [--quick] [--seconds S]``.
"""

import argparse
import math
import os
import sys
import time

from bench import common
from bench import ros_process

from test_support.ros_harness import RosHarness

# (case, targets/s (0: unbounded), every n-th hostile (0: none), message objects).
CASES = [('5 000/s, plain rclpy publisher', 5000.0, 0, True),
         ('unbounded, plain rclpy publisher', 0.0, 0, True),
         ('20 000/s, every 2nd hostile', 20000.0, 2, False)]
SECONDS = 10.0
QUICK_SECONDS = 2.0
NODE_RATE = 1000.0
RATE_TOLERANCE = 0.01
RECOVERY_S = 1.0


def _isolate() -> None:
    # rclpy reads these at init, and the child processes inherit them.
    os.environ.update(ros_process.environment())


def run(quick: bool, seconds: float = None) -> dict:
    """Return the section: one row per flood case."""
    start = time.perf_counter()
    _isolate()
    seconds = seconds or (QUICK_SECONDS if quick else SECONDS)
    from test_support.flood_run import run_flood
    rows = []
    for label, rate, hostile_every, messages in CASES:
        harness = RosHarness()
        try:
            result = run_flood(harness, seconds, rate, hostile_every, NODE_RATE, messages)
        finally:
            harness.shutdown()
        lags = [lag for lag in result['lag_s'] if math.isfinite(lag)]
        rows.append({
            'case': label,
            'rate_ratio': result['stamp_rate_hz'] / NODE_RATE,
            'sent': result['flood']['rate'],
            'stamp_rate': result['stamp_rate_hz'],
            'publish_rate': result['publish_rate_hz'],
            'missing': result['missing_ticks'],
            'warned': ('yes' if result['drops_warned'] else 'no') if result['missing_ticks']
            else '-',
            'recovered': result['recovered_s'],
            'finite': 'yes' if result['all_finite'] else 'NO',
            'late_p99': result['late_ms_p99'],
            'rss_start': result['rss_start_mb'],
            'rss_end': result['rss_end_mb'],
            'cpu': 100.0 * result['node_cpu_share'],
            'flooder_cpu': 100.0 * result['flooder_cpu_share'],
            'run_delay': result['node_run_delay_ms'],
            'lag': 1e3 * common.median(lags) if lags else None,
            'exit': result['node_exit_code'],
        })
    notes = []
    plain = rows[0]
    notes.append(
        f'{plain["case"]}: output {plain["stamp_rate"]:.1f} Hz, '
        f'{100 * (plain["rate_ratio"] - 1):+.2f} % of {NODE_RATE:g} Hz: '
        + ('held' if abs(plain['rate_ratio'] - 1) <= RATE_TOLERANCE else 'not held')
        + f' within {100 * RATE_TOLERANCE:g} %.')
    unbounded = rows[1]
    notes.append(
        f'{unbounded["case"]}: {unbounded["sent"]:.0f} targets/s sent; outputs finite: '
        f'{unbounded["finite"]}; {unbounded["missing"]} ticks missing, warned: '
        f'{unbounded["warned"]}; last missing tick {unbounded["recovered"]:.3f} s after the '
        f'flood (' + ('within' if unbounded['recovered'] <= RECOVERY_S else 'beyond')
        + f' {RECOVERY_S:g} s).')
    notes += [
        'output ratio: ticks published per second of the flood (by grid stamp) / rate_hz; '
        'missing: ticks absent from the stamps (the node drops ticks only when it is more than '
        'its catch-up bound late); warned: whether its log says it dropped them; back after: '
        "when the last missing tick was due, from the flood's end (0: none missing after it).",
        '"node waited for CPU" is its main thread\'s run-queue time over the flood (/proc '
        'schedstat): large values mean the machine, not the node, was short of CPU.',
    ]
    return {
        'title': f'Target floods at the {NODE_RATE:g} Hz node process, {seconds:g} s each',
        'text': 'Command: `python -m bench.flood`. ' + __doc__.split('\n\n')[1].replace('\n', ' '),
        'columns': [
            ['case', 'case', ''],
            ['rate_ratio', 'output / rate_hz', '.4f'],
            ['sent', 'sent /s', '.0f'],
            ['stamp_rate', 'output Hz (stamps)', '.1f'],
            ['publish_rate', 'output Hz (write time)', '.1f'],
            ['missing', 'ticks missing', ''],
            ['warned', 'drops warned', ''],
            ['recovered', 'back after (s)', '.3f'],
            ['finite', 'finite', ''],
            ['late_p99', 'late p99 ms', '.1f'],
            ['rss_start', 'RSS start MB', '.1f'],
            ['rss_end', 'RSS end MB', '.1f'],
            ['cpu', 'node CPU %', '.0f'],
            ['flooder_cpu', 'flooder CPU %', '.0f'],
            ['run_delay', 'node waited for CPU ms', '.0f'],
            ['lag', 'anchor lag ms', '.1f'],
            ['exit', 'node exit', ''],
        ],
        'rows': rows,
        'notes': notes,
        'elapsed_s': time.perf_counter() - start,
    }


def main(argv=None) -> int:
    """Run the flood benchmark on its own and print its table."""
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[1])
    parser.add_argument('--quick', action='store_true', help=f'{QUICK_SECONDS:g} s per case')
    parser.add_argument('--seconds', type=float, default=None, help='flood seconds per case')
    args = parser.parse_args(argv)
    print(common.section_markdown(run(args.quick, args.seconds)))
    return 0


if __name__ == '__main__':
    sys.exit(main())
