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
Memory: the node's RSS at 1 kHz over a long run, every path exercised.

The node (``mouse_constraint_node``, defaults, 1 kHz) runs for ``--minutes`` while
``bench.observer exercise`` drives every path it has: targets round a 0.1 m circle at 500 Hz, every
50th of them a bad one (NaN, a foreign frame, beyond the workspace, inf: the
warning paths), ``~/reset`` every 7 s, ``~/release`` every 11 s, ``marker_rate_hz`` changed every
13 s (the parameter callback, timers destroyed and made), and subscribers on pose, twist,
markers and /diagnostics. VmRSS of the node is read every second.

Figures: RSS at 1 minute and at the end (each the median of the samples within 5 s of it), the
difference, the slope of a straight line fitted to RSS over minute 1 to the end (KiB/min and
bytes per tick), and the peak. A leak of even one byte per tick would add 0.5 MiB over the
9 minutes; the no-leak criterion is that both the growth from minute 1 and the slope projected
over minute 1 to minute 10 stay within ``TOLERANCE_KIB``. ``bench.spin_leak`` then measures the
RSS per call of the executor's spin calls (``spin_until_future_complete`` keeps memory per
call; ``node.main`` spins with ``spin_once``).

In the suite the run is ``SUITE_MINUTES`` long, to keep ``make bench`` well inside its budget
(15 min for everything); the 10-minute figure comes from ``python -m bench.memory --minutes 10``,
run on its own: it prints the section as JSON and saves its row in ``memory_long.json`` beside
this file, which the suite's section then shows as a second row, with its date and commit.
"""

import argparse
import json
from pathlib import Path
import subprocess
import sys
import time

from bench import common
from bench import ros_process
import numpy as np

from test_support import processes

RATE_HZ = 1000.0
MINUTES = 10.0
SUITE_MINUTES = 5.0
QUICK_MINUTES = 0.5
BENCH = Path(__file__).resolve().parent
LONG_RUN = BENCH / 'memory_long.json'
REFERENCE_S = 60.0
WINDOW_S = 5.0
# RSS moves in 4 KiB pages; once warm (after the first minute) a node without a leak stays
# within a few dozen pages. Judged on both the measured growth and the slope projected over the
# 9 minutes from minute 1 to minute 10, so that a 5-minute run can show a 10-minute leak.
TOLERANCE_KIB = 128
PROJECTED_MINUTES = 9.0
# The record of a standalone run the suite's section shows under its own row.
RECORDS = ('memory_long.json',)


def run(quick: bool = False, minutes: float = None) -> dict:
    start = time.perf_counter()
    minutes = minutes if minutes is not None else (QUICK_MINUTES if quick else SUITE_MINUTES)
    seconds = 60.0 * minutes
    reference = min(REFERENCE_S, seconds / 2.0)
    parameters = {'rate_hz': RATE_HZ}
    command = ros_process.node_command(parameters)
    times, rss = [], []
    with ros_process.start(command) as node:
        began = time.monotonic()

        def sample(line: str) -> None:
            if line.startswith(('ready', 'progress', 'end')):
                times.append(time.monotonic() - began)
                rss.append(processes.rss_bytes(node.pid) / 1024.0)

        data, samples, _ = ros_process.observe(
            ['exercise', '--seconds', str(seconds)], [node.pid], on_line=sample,
            timeout=seconds + 120.0)
        alive = node.alive()
        cpu = ros_process.cpu_percent(samples['ready'], samples['end'], node.pid)
    ready = times[0]
    t = np.array(times) - ready
    rss = np.array(rss, dtype=float)
    end = float(t[-1])

    def around(when: float) -> float:
        near = np.abs(t - when) <= WINDOW_S
        return float(np.median(rss[near]))

    at_reference, at_end = around(reference), around(end - WINDOW_S)
    late = t >= reference
    slope_kib_per_s = float(np.polyfit(t[late], rss[late], 1)[0]) if late.sum() > 2 else 0.0
    growth = at_end - at_reference
    row = {
        'run': 'this run',
        'minutes': end / 60.0,
        'rss_start_mib': float(rss[0]) / 1024.0,
        'rss_reference_mib': at_reference / 1024.0,
        'rss_end_mib': at_end / 1024.0,
        'growth_kib': growth,
        'slope_kib_per_min': 60.0 * slope_kib_per_s,
        'bytes_per_tick': 1024.0 * slope_kib_per_s / RATE_HZ,
        'rss_peak_mib': float(np.max(rss)) / 1024.0,
        'cpu_pct': cpu,
        'reference_min': reference / 60.0,
        'node_alive': alive,
    }
    sent = {k[len('sent_'):]: int(v) for k, v in data.items() if k.startswith('sent_')}
    received = {k[len('received_'):]: int(v) for k, v in data.items()
                if k.startswith('received_')}
    rows = [row]
    notes = [_verdict(row)]
    for record in RECORDS:
        path = BENCH / record
        if minutes < MINUTES and path.exists():
            rows.append(json.loads(path.read_text()))
            notes.append(f'Row {len(rows)}: {rows[-1]["run"]}. ' + _verdict(rows[-1]))
    if minutes < MINUTES and not LONG_RUN.exists():
        notes.append(f'No {MINUTES:g}-minute run on record ({LONG_RUN.name}): run '
                     f'`python -m bench.memory --minutes {MINUTES:g}`.')
    notes.append(_spin_leak())
    notes += [
        'Sent to the node: ' + ', '.join(f'{v} {k.replace("_", " ")}' for k, v in sent.items())
        + '. Received from it: ' + ', '.join(f'{v} {k}' for k, v in received.items()) + '.',
        'slope: least-squares line through the RSS samples (one per second) from the reference '
        'minute on; bytes per tick = slope / tick rate.',
    ]
    return {
        'title': f'Memory: node RSS at {RATE_HZ:g} Hz over {end / 60.0:.1f} min, every path '
                 'exercised',
        'text': ('The node as its own process at defaults (1 kHz); another process sends '
                 'targets at 500 Hz (every 50th bad), calls ~/reset, ~/release and '
                 'set_parameters, and subscribes to pose, twist, markers and /diagnostics. '
                 'VmRSS of the node read every second.'),
        'columns': [['run', 'run', ''], ['minutes', 'length (min)', '.1f'],
                    ['rss_start_mib', 'RSS at start (MiB)', '.2f'],
                    ['rss_reference_mib', 'RSS at 1 min (MiB)', '.2f'],
                    ['rss_end_mib', 'RSS at end (MiB)', '.2f'],
                    ['growth_kib', 'end - 1 min (KiB)', '+.0f'],
                    ['slope_kib_per_min', 'slope (KiB/min)', '+.1f'],
                    ['bytes_per_tick', 'slope (B/tick)', '+.3f'],
                    ['rss_peak_mib', 'peak (MiB)', '.2f'], ['cpu_pct', 'CPU (% core)', '.1f']],
        'rows': rows,
        'notes': notes,
        'raw': {'t_s': t.tolist(), 'rss_kib': rss.tolist(), 'sent': sent, 'received': received},
        'elapsed_s': time.perf_counter() - start,
    }


def _verdict(row: dict) -> str:
    projected = row['slope_kib_per_min'] * PROJECTED_MINUTES
    met = max(abs(row['growth_kib']), abs(projected)) <= TOLERANCE_KIB
    return (f'Target: RSS after 10 min equals RSS after {row["reference_min"]:g} min (within '
            f'{TOLERANCE_KIB} KiB, measured over {row["minutes"]:.1f} min and projected by the '
            f'slope over {PROJECTED_MINUTES:g} min). {row["rss_reference_mib"]:.2f} MiB -> '
            f'{row["rss_end_mib"]:.2f} MiB ({row["growth_kib"]:+.0f} KiB; slope '
            f'{row["slope_kib_per_min"]:+.1f} KiB/min, {projected:+.0f} KiB projected): '
            + ('met.' if met else 'missed.'))


def _spin_leak() -> str:
    """Run spin_leak.py; return what it found, as a note."""
    result = subprocess.run(ros_process.bench_command('spin_leak'), env=ros_process.environment(),
                            cwd=ros_process.ROOT, capture_output=True, text=True, timeout=300)
    if result.returncode != 0:
        return f'bench.spin_leak failed: {result.stderr[-500:]}'
    found = json.loads(result.stdout.strip().splitlines()[-1])
    per_call = found['bytes_per_call']
    return ('RSS growth per call of the EventsExecutor (bench.spin_leak, '
            f'{found["calls"]} calls each): ' + '; '.join(
                f'{name}: {value:.1f} B/call ({value * 10 * 60 / 1024:.1f} KiB/min at 10 calls '
                'a second)' for name, value in per_call.items()) + '.')


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[1])
    parser.add_argument('--minutes', type=float, default=MINUTES)
    parser.add_argument('--no-save', action='store_true',
                        help=f'do not write {LONG_RUN.name} (written for >= {MINUTES:g} min)')
    options = parser.parse_args(argv)
    machine = common.machine_info()  # At the start: the commit and load the run began with.
    section = run(minutes=options.minutes)
    section.pop('raw')
    print(json.dumps(section, indent=1))
    save = LONG_RUN if not options.no_save and options.minutes >= MINUTES else None
    if save is not None:
        row = dict(section['rows'][0])
        load = machine['load_average_at_start'][0]
        row['run'] = (f'standalone `python -m bench.memory --minutes {options.minutes:g}` started '
                      f'{machine["date"]}, commit {machine["commit"]}, load at start {load:.2f}')
        save.write_text(json.dumps(row, indent=1) + '\n')
    return 0


if __name__ == '__main__':
    sys.exit(main())
