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
The node's rate and CPU against the bare rclpy floor, pose and twist read from another process.

Each row is a process (``mouse_constraint_node`` with its defaults but ``rate_hz``: the box
hanging from its held corner under gravity; or ``bench.bare_timer --executor events --twist``,
the floor: an rclpy timer under the node's executor and spin loop that only stamps and
publishes a PoseStamped and a TwistStamped per tick) watched by ``bench.observer rate``, which
reads both topics (a publisher with no reader sends nothing) and after 1 s of warm-up records a
window: the receive time and stamp of every pose. At each rate the node and the floor run one
after the other, so that each ratio node / floor is taken within minutes on the same machine;
the absolute figures are context (the machine's speed varies about 3x from day to day).

- achieved rate: poses received in the window / window length; rate error against rate_hz;
- missing: grid ticks between the first and last stamp that never arrived (dropped ticks);
- grid error: each stamp against t0 + n / rate_hz (the node's stamps are t0 + floor(n dt) in
  integer ns; the floor's are its clock readings, so its grid error is its timer's jitter);
- delay: receive time - stamp; late: poses received more than one period after their stamp;
- CPU: utime + stime of the process (all threads, DDS ones included) over the window, % of one
  core; RSS at the window's end.

Rates: 1 kHz (the figures the docs quote: CPU node / floor, rate within 0.1 %, ticks missing),
then up the ladder ``LADDER`` until the node no longer sustains the rate (within 0.1 %, no tick
missing) over a 10 s window: the highest sustained rate and the node / floor ratio there.

Standalone: ``python -m bench.node_rate [--quick]`` prints the section as JSON.
"""

import statistics
import sys
import time

from bench import ros_process
import numpy as np

BASE_RATE = 1000.0
LADDER = (2000.0, 3000.0, 4000.0, 5000.0)
SECONDS = 10.0
QUICK_SECONDS = 2.0
WARMUP = 1.0
RATE_TOLERANCE = 0.001
FLOOR = ('--executor', 'events', '--twist')


def stamp_figures(stamps: np.ndarray, received: np.ndarray, rate: float,
                  seconds: float) -> dict:
    """Return the rate, grid and delay figures of one window of (stamp, receive time) pairs."""
    period = 1e9 / rate
    if len(stamps) < 2:
        return {'received': len(stamps), 'achieved_hz': len(stamps) / seconds,
                'rate_error_pct': 100.0 * (len(stamps) / seconds - rate) / rate}
    offsets = (stamps - stamps[0]).astype(float)
    ticks = np.rint(offsets / period)
    grid_error = offsets - ticks * period
    span = int(ticks[-1]) + 1
    distinct = len(np.unique(ticks))
    delay = (received - stamps) / 1e3
    gaps = np.diff(received) / period
    return {
        'received': len(stamps),
        'achieved_hz': len(stamps) / seconds,
        'rate_error_pct': 100.0 * (len(stamps) / seconds - rate) / rate,
        'stamp_rate_hz': 1e9 * (len(stamps) - 1) / float(stamps[-1] - stamps[0]),
        'grid_error_ns': float(np.max(np.abs(grid_error))),
        'missing': span - distinct,
        'repeated': len(stamps) - distinct,
        'delay_p50_us': float(np.percentile(delay, 50)),
        'delay_p99_us': float(np.percentile(delay, 99)),
        'delay_max_us': float(np.max(delay)),
        'late': int(np.sum(delay > period / 1e3)),
        'gaps': int(np.sum(gaps > 2.0)),
        'max_gap_ms': float(np.max(gaps)) * period / 1e6,
    }


def measure(command, rate: float, seconds: float, first_timeout: float = 10.0,
            observer_arguments=()) -> dict:
    """Start ``command``, observe its ``pose`` for ``seconds``; return the figures."""
    with ros_process.start(command) as publisher:
        data, samples, observer = ros_process.observe(
            ['rate', '--seconds', str(seconds), '--warmup', str(WARMUP),
             '--first-timeout', str(first_timeout), *observer_arguments], [publisher.pid])
        if not publisher.alive():
            raise RuntimeError(f'{command} exited early ({publisher.process.returncode})')
    first, last = samples['start'], samples['end']
    figures = stamp_figures(data['stamp_ns'], data['recv_ns'], rate, last.wall - first.wall)
    figures.update({
        'rate_hz': rate,
        'window_s': last.wall - first.wall,
        'cpu_pct': ros_process.cpu_percent(first, last, publisher.pid),
        'wait_ms_per_s': ros_process.wait_per_second(first, last, publisher.pid),
        'load': last.load,
        'observer_cpu_pct': ros_process.cpu_percent(first, last, observer),
        'rss_mib': last.rss[publisher.pid] / 1024.0,
        'rss_start_mib': first.rss[publisher.pid] / 1024.0,
        'twists': int(data['also_received']),
        'threads_cpu_s': {kind: last.threads[publisher.pid][kind] - seconds
                          for kind, seconds in first.threads[publisher.pid].items()},
    })
    return figures


def alternating(processes: list, rate: float, rounds: int, seconds: float, *,
                floor_case: str, first_timeout: float = 10.0, observer_arguments=()) -> tuple:
    """
    Measure each (name, command) one window per round, the processes alternating.

    Return the rows, each with its case, CPU per tick (us) and RSS growth (MiB), and each
    case's median CPU per tick. ``floor_case`` names the rclpy floor: its stamps are clock
    readings, not a grid, so it has no missing ticks, and it is watched on pose and twist alone
    (``observer_arguments`` are the others').
    """
    rows, samples = [], {name: [] for name, _ in processes}
    for _ in range(rounds):
        for name, command in processes:
            row = measure(command, rate, seconds, first_timeout=first_timeout,
                          observer_arguments=() if name == floor_case else observer_arguments)
            row['case'] = name
            row['cpu_us_per_tick'] = 1e4 * row['cpu_pct'] / row['achieved_hz']
            row['rss_growth_mib'] = row['rss_mib'] - row['rss_start_mib']
            if name == floor_case:
                row['missing'] = None
            samples[name].append(row['cpu_us_per_tick'])
            rows.append(row)
            print(f'  {name}: CPU {row["cpu_pct"]:.1f} %, {row["achieved_hz"]:.1f} Hz, '
                  f'RSS {row["rss_start_mib"]:.1f} -> {row["rss_mib"]:.1f} MiB',
                  file=sys.stderr, flush=True)
    return rows, {name: statistics.median(values) for name, values in samples.items()}


def _report(row: dict) -> None:
    print(f'  {row["process"]} {row["rate_hz"]:g} Hz: {row["achieved_hz"]:.1f} Hz, '
          f'{row.get("missing", "-")} missing, CPU {row["cpu_pct"]:.1f} %',
          file=sys.stderr, flush=True)


def sustained(row: dict) -> bool:
    """Return whether a row kept its rate: within RATE_TOLERANCE and no tick missing."""
    return (row.get('missing', 1) == 0
            and abs(row['rate_error_pct']) <= 100.0 * RATE_TOLERANCE)


def pair(rate: float, seconds: float) -> tuple:
    """Return the node's row and the floor's row at ``rate``, measured one after the other."""
    node = measure(ros_process.node_command({'rate_hz': rate}), rate, seconds)
    node['process'] = 'mouse_constraint_node'
    _report(node)
    floor = measure(ros_process.bench_command('bare_timer', '--rate', repr(rate), *FLOOR), rate,
                    seconds)
    floor['process'] = 'floor: bench.bare_timer --twist'
    # Its stamps are clock readings, not a grid: no tick of it can be missing.
    floor['missing'] = floor['grid_error_ns'] = None
    _report(floor)
    node['cpu_ratio'] = node['cpu_pct'] / floor['cpu_pct']
    floor['cpu_ratio'] = 1.0
    return node, floor


def run(quick: bool = False) -> dict:
    """Return the section: the node and the floor at 1 kHz, then up the ladder."""
    start = time.perf_counter()
    seconds = QUICK_SECONDS if quick else SECONDS
    rows = []
    base, floor = pair(BASE_RATE, seconds)
    rows += [base, floor]
    highest = (base, floor) if sustained(base) else None
    for rate in (LADDER[:1] if quick else LADDER):
        node, floor = pair(rate, seconds)
        rows += [node, floor]
        if not sustained(node):
            break
        highest = (node, floor)
    figures = {
        'cpu_ratio_1khz': base['cpu_ratio'],
        'rate_error_pct_1khz': base['rate_error_pct'],
        'missing_1khz': base.get('missing'),
        'highest_sustained_hz': highest[0]['rate_hz'] if highest else None,
        'cpu_ratio_highest': highest[0]['cpu_ratio'] if highest else None,
    }
    notes = [
        f'At {BASE_RATE:g} Hz: node CPU / floor CPU {base["cpu_ratio"]:.2f} '
        f'({base["cpu_pct"]:.1f} % / {rows[1]["cpu_pct"]:.1f} % of a core); rate '
        f'{base["rate_error_pct"]:+.3f} % ('
        + ('within' if abs(base['rate_error_pct']) <= 100 * RATE_TOLERANCE else 'outside')
        + f' {100 * RATE_TOLERANCE:g} %), {base.get("missing")} ticks missing.',
        (f'Highest rate sustained for {seconds:g} s with pose and twist read (within '
         f'{100 * RATE_TOLERANCE:g} %, no tick missing): {highest[0]["rate_hz"]:g} Hz, node / '
         f'floor CPU there {highest[0]["cpu_ratio"]:.2f}.') if highest else
        f'No rate sustained for {seconds:g} s, not even {BASE_RATE:g} Hz.',
        'One window per row: a single spell of a busy machine moves a row; "wait" (ms per s '
        'the main thread waited for a CPU while runnable) and "load" (1-minute load average) '
        'show how busy it was.',
    ]
    return {
        'title': 'Node rate and CPU against the rclpy floor, pose and twist read from another '
                 'process',
        'text': (f'Command: `python -m bench.node_rate`. {seconds:g} s windows after {WARMUP:g} s '
                 'of warm-up; the node at its defaults but rate_hz; the floor is '
                 '`bench.bare_timer --executor events --twist` at the same rate, run next to it. '
                 'Ratios first: node / floor CPU.'),
        'columns': [['process', 'process', ''], ['rate_hz', 'rate (Hz)', '.0f'],
                    ['cpu_ratio', 'CPU / floor', '.2f'],
                    ['achieved_hz', 'achieved (Hz)', '.1f'],
                    ['rate_error_pct', 'rate error (%)', '+.3f'],
                    ['missing', 'missing', 'd'], ['grid_error_ns', 'grid error (ns)', '.0f'],
                    ['delay_p50_us', 'delay p50 (us)', '.0f'],
                    ['delay_p99_us', 'delay p99 (us)', '.0f'], ['late', 'late', 'd'],
                    ['twists', 'twists read', 'd'],
                    ['cpu_pct', 'CPU (% core)', '.1f'], ['wait_ms_per_s', 'wait (ms/s)', '.0f'],
                    ['load', 'load', '.1f'], ['rss_mib', 'RSS (MiB)', '.1f']],
        'rows': rows,
        'notes': notes,
        'figures': figures,
        'elapsed_s': time.perf_counter() - start,
    }


if __name__ == '__main__':
    import json
    print(json.dumps(run(quick='--quick' in sys.argv), indent=1, default=str))
