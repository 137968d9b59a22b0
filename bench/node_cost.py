"""
Part 2, where the node's CPU goes at 1 kHz: its tick taken apart, before and after 8dfbd58.

``node_variant.py --report`` runs the package's ``MouseConstraintNode`` in its own process with
the thread CPU time (``time.thread_time_ns``, so time spent descheduled does not count) of its
main thread measured around each part of the tick; an observer subscribes to pose as in
``node_rate``. Two configurations, in interleaved rounds (before, now, before, now, ...) so
that a slow spell of the shared machine hits both: the spin loop and tick grid origin as before
8dfbd58 (``spin_once`` loop, t0 at the first call) and as now (``spin_once`` loop, t0 where the
timer scheduled the first call; 8dfbd58's ``spin_until_future_complete`` loop was reverted for
the leak ``memory`` found). Figures are medians over the rounds of the
per-tick figure of each run; 1 us per tick at 1 kHz is 0.1 % of a core.
"""

import json
from pathlib import Path
import statistics
import tempfile
import time

import node_rate
import ros_process

RATE_HZ = 1000.0
SECONDS = 6.0
ROUNDS = 3
QUICK_SECONDS = 2.0
RUNS = (
    ('before', ('--loop', 'once', '--grid', 'first-call')),
    ('now', ('--loop', 'once', '--grid', 'scheduled')),
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
    rounds = 1 if quick else ROUNDS
    results = {name: [] for name, _ in RUNS}
    with tempfile.TemporaryDirectory(prefix='mouse_bench_') as directory:
        for round_index in range(rounds):
            for name, arguments in RUNS:
                path = Path(directory) / f'{name}-{round_index}.json'
                command = ros_process.python_command(
                    ros_process.NODE_VARIANT, *arguments, '--report', str(path), '--ros-args',
                    '-p', f'rate_hz:={RATE_HZ!r}')
                figures = node_rate.measure(command, RATE_HZ, seconds)
                report = json.loads(path.read_text())
                results[name].append({'figures': figures, 'report': report,
                                      'parts': breakdown(report)})

    def med(name: str, get) -> float:
        return statistics.median(get(result) for result in results[name])

    rows = []
    for key, meaning in PARTS:
        row = {'part': key, 'meaning': meaning}
        for name, _ in RUNS:
            row[name] = med(name, lambda result: result['parts'].get(key, 0.0))
        row['difference'] = row['now'] - row['before']
        rows.append(row)

    def listed(name: str, get, spec: str) -> str:
        return ', '.join(format(get(result), spec) for result in results[name])

    cpu = {name: listed(name, lambda r: r['figures']['cpu_pct'], '.1f') for name, _ in RUNS}
    late = {name: listed(name, lambda r: r['report']['late_ticks'], 'd') for name, _ in RUNS}
    delay = {name: med(name, lambda r: r['figures']['delay_p50_us']) for name, _ in RUNS}
    delay99 = {name: med(name, lambda r: r['figures']['delay_p99_us']) for name, _ in RUNS}
    ticks = med('before', lambda r: r['report']['ticks'])
    notes = [
        f'CPU per round over the observed window (/proc, as in node_rate): before {cpu["before"]}'
        f' %; now {cpu["now"]} %.',
        f'Late ticks per run (of about {ticks:.0f}; ticks a timer call ran after its first): '
        f'before {late["before"]}; now {late["now"]}. Pose delay (observer receive - stamp) '
        f'p50 {delay["before"]:.0f} us -> {delay["now"]:.0f} us, p99 {delay99["before"]:.0f} us'
        f' -> {delay99["now"]:.0f} us (medians over the rounds).',
        'The timing wrappers cost about 1 us per wrapped call (5 per tick), counted in the '
        'parts. Code run once a millisecond between sleeps runs with cold caches: the step takes '
        "about twice the us it takes in core_cost's tight loop.",
    ]
    return {
        'title': f'2b. Node CPU per tick at {RATE_HZ:g} Hz: where it goes, before and after '
                 '8dfbd58',
        'text': (f"Thread CPU time of the node process's main thread per tick, by part; median "
                 f'of {rounds} interleaved rounds of {seconds:g} s observed (plus start-up) per '
                 'configuration; us per tick (0.1 % of a core each).'),
        'columns': [['part', 'part', ''], ['meaning', 'what', ''],
                    ['before', 'before: spin_once, t0 first call (us/tick)', '.1f'],
                    ['now', 'now: spin_once, t0 scheduled (us/tick)', '.1f'],
                    ['difference', 'now - before', '+.1f']],
        'rows': rows,
        'notes': notes,
        'raw': {name: [result['report'] for result in runs] for name, runs in results.items()},
        'elapsed_s': time.perf_counter() - start,
    }
