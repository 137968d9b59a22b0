"""
Part 2, where the node's CPU goes at 1 kHz: its tick taken apart, as is and as proposed.

``node_variant.py --report`` runs the package's ``MouseConstraintNode`` in its own process with
the thread CPU time (``time.thread_time_ns``, so time spent descheduled does not count) of its
main thread measured around each part of the tick; an observer subscribes to pose as in
``node_rate``. Two runs: the node as ``node.main`` spins it (``spin_once`` loop) and the node
with both changes the benchmarks propose (``spin_until_future_complete`` loop, tick grid
phase-locked to the timer). Figures are per tick, over the whole run; 1 us per tick at 1 kHz is
0.1 % of a core.
"""

import json
from pathlib import Path
import tempfile
import time

import node_rate
import ros_process

RATE_HZ = 1000.0
SECONDS = 10.0
QUICK_SECONDS = 2.0
RUNS = (
    ('as is', ('--loop', 'once')),
    ('proposed', ('--loop', 'until', '--phase-lock')),
)
PARTS = (
    ('step', 'MouseSimulation.step (physics, all substeps)'),
    ('publish pose', 'pose publisher.publish (message conversion + Fast DDS write)'),
    ('publish twist', 'twist publisher.publish'),
    ('grid due', 'TickGrid.due'),
    ('callback other', 'rest of the timer callback: clock, stamps, fill_pose/twist, loop'),
    ('markers and diagnostics', 'marker (30 Hz) and diagnostics (1 Hz) callbacks, per tick'),
    ('executor', 'main thread outside the callbacks: the executor and the spin loop'),
    ('main thread', 'main thread in all'),
    ('other threads', 'the process less its main thread: Fast DDS and executor threads'),
    ('process', 'the whole process (utime + stime of all threads)'),
)


def breakdown(report: dict) -> dict:
    """Return microseconds per tick of each part from a node_variant.py report."""
    ticks = report['ticks']
    parts = {name: ns / ticks / 1e3 for name, ns in report['parts_ns'].items()}
    callback = parts.get('timer callback', 0.0)
    inside = sum(parts.get(name, 0.0) for name in ('step', 'publish pose', 'publish twist',
                                                   'grid due'))
    main = report['main_thread_ns'] / ticks / 1e3
    process = report['process_ns'] / ticks / 1e3
    parts.update({
        'callback other': callback - inside,
        'executor': main - callback - parts.get('markers and diagnostics', 0.0),
        'main thread': main,
        'other threads': process - main,
        'process': process,
    })
    return parts


def run(quick: bool = False) -> dict:
    start = time.perf_counter()
    seconds = QUICK_SECONDS if quick else SECONDS
    results = {}
    with tempfile.TemporaryDirectory(prefix='mouse_bench_') as directory:
        for name, arguments in RUNS:
            path = Path(directory) / f'{name}.json'
            command = ros_process.python_command(
                ros_process.NODE_VARIANT, *arguments, '--report', str(path), '--ros-args', '-p',
                f'rate_hz:={RATE_HZ!r}')
            figures = node_rate.measure(command, RATE_HZ, seconds)
            report = json.loads(path.read_text())
            results[name] = {'figures': figures, 'report': report, 'parts': breakdown(report)}
    rows = []
    for key, meaning in PARTS:
        row = {'part': key, 'meaning': meaning}
        for name, _ in RUNS:
            row[name.replace(' ', '_')] = results[name]['parts'].get(key)
        rows.append(row)
    as_is, proposed = results['as is'], results['proposed']
    notes = [
        f'CPU over the observed window (/proc, as in node_rate): as is '
        f'{as_is["figures"]["cpu_pct"]:.1f} %, proposed {proposed["figures"]["cpu_pct"]:.1f} %; '
        f'over the whole run from the report: {as_is["parts"]["process"] / 10:.1f} % and '
        f'{proposed["parts"]["process"] / 10:.1f} %.',
        f'Late ticks (ticks run by a timer call after the first it ran): as is '
        f'{as_is["report"]["late_ticks"]} of {as_is["report"]["ticks"]}, proposed '
        f'{proposed["report"]["late_ticks"]} of {proposed["report"]["ticks"]}; pose delay p50 '
        f'{as_is["figures"]["delay_p50_us"]:.0f} us -> {proposed["figures"]["delay_p50_us"]:.0f}'
        f' us, p99 {as_is["figures"]["delay_p99_us"]:.0f} us -> '
        f'{proposed["figures"]["delay_p99_us"]:.0f} us.',
        'The timing wrappers cost about 1 us per wrapped call (5 per tick), counted in the '
        'parts. Code run once a millisecond between sleeps runs with cold caches: the step takes '
        "about twice the us it takes in core_cost's tight loop.",
    ]
    return {
        'title': f'2b. Node CPU per tick at {RATE_HZ:g} Hz: where it goes',
        'text': (f"Thread CPU time of the node process's main thread per tick, by part, over a "
                 f'{seconds:g} s observed run plus start-up; us per tick (0.1 % of a core '
                 'each).'),
        'columns': [['part', 'part', ''], ['meaning', 'what', ''],
                    ['as_is', 'as is (us/tick)', '.1f'],
                    ['proposed', 'proposed (us/tick)', '.1f']],
        'rows': rows,
        'notes': notes,
        'raw': {name: result['report'] for name, result in results.items()},
        'elapsed_s': time.perf_counter() - start,
    }
