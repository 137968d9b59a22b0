"""
Part 2, node rate: the node as its own process, watched from another over DDS.

For each rate the node (``mouse_constraint_node``, default parameters but ``rate_hz``: the box
hanging from its held corner under gravity) is started, ``observer.py rate`` subscribes to
``pose`` in a third process, and after 1 s of warm-up records a window: the receive time and
the stamp of every pose. From those:

- achieved rate: poses received in the window / window length;
- grid error: each stamp against t0 + n / rate_hz, t0 the first stamp of the window, n the
  nearest tick (the node's stamps are t0 + floor(n dt) in integer ns, so <= 1 ns is exact);
- missing: grid ticks between the first and last stamp that never arrived (dropped ticks);
- delay: receive time - stamp, the tick's lateness plus the DDS hop; ``late``: poses received
  more than one period after their stamp; ``gaps``: receive gaps longer than two periods;
- CPU: utime + stime of the node process (all threads) over the window, % of one core; RSS at
  the window's end.

For scale, the same is measured at 1 kHz for ``bare_timer.py``: an rclpy timer that publishes
a PoseStamped (and with ``--twist`` a TwistStamped) per tick and does nothing else, under the
SingleThreadedExecutor and the EventsExecutor spun as the node spins (``spin_once`` in a loop),
with ``spin_until_future_complete`` in a loop, and with the EventsExecutor's own ``spin()``. Its
stamps are the clock at the callback, so its grid error is the timer's jitter. And
``node_variant.py``: the package's node class with its spin loop and tick grid origin as before
8dfbd58 and with each of that commit's two changes alone.
"""

import sys
import time

import numpy as np
import ros_process

RATES = (100.0, 500.0, 1000.0, 2000.0, 5000.0)
SECONDS = 10.0
# The rows for scale (bare timers) and the node_variant.py rows: shorter windows.
SCALE_SECONDS = 5.0
QUICK_SECONDS = 2.0
WARMUP = 1.0
SCALE_RATE = 1000.0
# (bare_timer.py arguments, spin described, first-message timeout): the floor of rclpy itself.
BARE = (
    (('--executor', 'single'), 'SingleThreadedExecutor, spin_once(0.1) loop; pose', 10.0),
    (('--executor', 'events'), 'EventsExecutor, spin_once(0.1) loop; pose', 10.0),
    (('--executor', 'events', '--twist'),
     'EventsExecutor, spin_once(0.1) loop; pose + twist', 10.0),
    (('--executor', 'events-until', '--twist'),
     'EventsExecutor, spin_until_future_complete(0.1) loop; pose + twist', 10.0),
    (('--executor', 'events-spin'), 'EventsExecutor, spin(); pose', 2.0),
)
# (node_variant.py arguments, what it runs): the node's spin loop and grid origin before and
# after 8dfbd58 (which took both from this benchmark), taken apart.
VARIANTS = (
    (('--loop', 'once', '--grid', 'first-call'),
     'as before 8dfbd58: spin_once loop, t0 at the first call'),
    (('--loop', 'until', '--grid', 'first-call'), 'spin_until_future_complete loop only'),
    (('--loop', 'once', '--grid', 'scheduled'), 'grid t0 phase-locked to the timer only'),
)
TARGET_RATE = 1000.0
TARGET_RATE_TOLERANCE = 0.001
TARGET_CPU = 15.0
SUSTAINED_RATE = 5000.0


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
    with ros_process.Started(command) as publisher:
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
    })
    return figures


def _report(row: dict) -> None:
    print(f'  {row["process"]} {row["rate_hz"]:g} Hz, {row["spin"]}: {row["achieved_hz"]:.1f} Hz,'
          f' CPU {row["cpu_pct"]:.1f} %', file=sys.stderr, flush=True)


def run(quick: bool = False) -> dict:
    start = time.perf_counter()
    seconds = QUICK_SECONDS if quick else SECONDS
    scale_seconds = QUICK_SECONDS if quick else SCALE_SECONDS
    rows = []
    for rate in (RATES if not quick else (1000.0, 5000.0)):
        row = measure(ros_process.node_command({'rate_hz': rate}), rate, seconds)
        row.update({'process': 'mouse_constraint_node', 'spin': 'as installed (node.main)'})
        rows.append(row)
        _report(row)
    for arguments, description, first_timeout in BARE:
        command = ros_process.python_command(ros_process.BARE_TIMER, '--rate', str(SCALE_RATE),
                                             *arguments)
        row = measure(command, SCALE_RATE, scale_seconds, first_timeout)
        row.update({'process': 'bare timer', 'spin': description})
        rows.append(row)
        _report(row)
    for arguments, description in VARIANTS:
        command = ros_process.python_command(ros_process.NODE_VARIANT, *arguments, '--ros-args',
                                             '-p', f'rate_hz:={SCALE_RATE!r}')
        row = measure(command, SCALE_RATE, scale_seconds)
        row.update({'process': 'node_variant.py', 'spin': description})
        rows.append(row)
        _report(row)
    notes = _verdicts(rows)
    notes += [
        'Rows: mouse_constraint_node as installed; bare timer: bare_timer.py, an rclpy timer '
        'that only stamps and publishes (pose, or pose + twist as the node does), the floor '
        "under any rclpy node at this rate; node_variant.py: the package's MouseConstraintNode "
        'with its spin loop and tick grid origin chosen by the bench (see node_variant.py). A '
        'single window per row: CPU differences of a few points between rows are within the '
        "machine's noise (node_cost repeats its A/B in interleaved rounds).",
        'achieved: poses received in the window / the window (measured in the bench process '
        "between the observer's start and end lines); stamp rate: (poses - 1) / (last stamp - "
        'first stamp).',
        'grid error: largest |stamp - (t0 + n / rate_hz)| (ns) with n the nearest tick; '
        'missing: ticks of the grid that never arrived; repeated: stamps seen twice.',
        'delay: receive time in the observer - stamp (us), i.e. how long after the tick was due '
        'the pose reached another process; late: poses with delay > 1 period; gaps: receive '
        'gaps > 2 periods (the pose stream stalled), max gap in ms.',
        'CPU: utime + stime of /proc/<pid>/stat over the window, all threads of the process '
        "(DDS included), % of one core; the observer's own use is in results.json "
        '(observer_cpu_pct). The machine has 2 shared cores: the node, the observer and the '
        'DDS threads of both share them with whatever else runs. wait: how long the main thread '
        'waited for a CPU while runnable (ms per s, /proc/<pid>/schedstat); load: the 1-minute '
        'load average at the end of the window. Both gauge the disturbance.',
        "The bare timer's stamps are the clock read in its callback, not a grid: its grid error "
        "and delay show the timer's jitter.",
        'EventsExecutor.spin() (rclpy 7.1.6): a full core busy in the main thread, and the '
        '1 kHz timer never fired: no pose at all; it does not return to Python, so Python signal '
        'handlers never run either. spin_until_future_complete(f, timeout_sec) with a future '
        'never done runs timers normally without busy-waiting, but keeps 32 bytes per call '
        '(see the memory section).',
    ]
    return {
        'title': '2. Node rate: the node as a process, observed over DDS from another process',
        'text': (f'Node rows: {seconds:g} s window ({scale_seconds:g} s for the other rows) after '
                 f'{WARMUP:g} s of warm-up, one observer process subscribed to pose (raw, '
                 'RELIABLE). Node: default parameters (box hanging from its held corner, gravity '
                 'on) but rate_hz.'),
        'columns': [['process', 'process', ''], ['spin', 'spin', ''],
                    ['rate_hz', 'rate (Hz)', '.0f'], ['achieved_hz', 'achieved (Hz)', '.1f'],
                    ['rate_error_pct', 'rate error (%)', '+.3f'],
                    ['grid_error_ns', 'grid error (ns)', '.0f'],
                    ['missing', 'missing', 'd'], ['delay_p50_us', 'delay p50 (us)', '.0f'],
                    ['delay_p99_us', 'delay p99 (us)', '.0f'], ['late', 'late', 'd'],
                    ['gaps', 'gaps', 'd'], ['max_gap_ms', 'max gap (ms)', '.1f'],
                    ['cpu_pct', 'CPU (% core)', '.1f'], ['wait_ms_per_s', 'wait (ms/s)', '.0f'],
                    ['load', 'load', '.1f'], ['rss_mib', 'RSS (MiB)', '.1f']],
        'rows': rows,
        'notes': notes,
        'elapsed_s': time.perf_counter() - start,
    }


def _verdicts(rows) -> list:
    notes = []
    node = {row['rate_hz']: row for row in rows if row['process'] == 'mouse_constraint_node'}
    if TARGET_RATE in node:
        row = node[TARGET_RATE]
        rate_ok = abs(row['rate_error_pct']) <= 100.0 * TARGET_RATE_TOLERANCE
        cpu_ok = row['cpu_pct'] <= TARGET_CPU
        notes.append(
            f'Target: {TARGET_RATE:g} Hz within {100 * TARGET_RATE_TOLERANCE:g} % using at most '
            f'{TARGET_CPU:g} % of one core. Rate {row["achieved_hz"]:.2f} Hz '
            f'({row["rate_error_pct"]:+.3f} %, {row["missing"]} missing): '
            f'{"met" if rate_ok else "missed"}; CPU {row["cpu_pct"]:.1f} %: '
            + ('met.' if cpu_ok else
               f'missed by {row["cpu_pct"] - TARGET_CPU:.1f} points '
               f'({row["cpu_pct"] / TARGET_CPU:.2f}x the budget).'))
    floor = [row for row in rows if row['process'] == 'bare timer' and 'twist' in row['spin']
             and 'until' in row['spin']]
    if floor and TARGET_RATE in node:
        notes.append(
            f'For scale: a bare rclpy timer publishing pose + twist at {SCALE_RATE:g} Hz with the '
            f'executor and loop the node uses took {floor[0]["cpu_pct"]:.1f} % of a core here, '
            f'the node {node[TARGET_RATE]["cpu_pct"]:.1f} %: the node adds '
            f'{node[TARGET_RATE]["cpu_pct"] - floor[0]["cpu_pct"]:.1f} points to what rclpy and '
            'Fast DDS cost for two reliable publishes per tick.')
    variants = [row for row in rows if row['process'] == 'node_variant.py']
    if variants:
        described = '; '.join(
            f'{row["spin"]}: CPU {row["cpu_pct"]:.1f} %, delay p50 {row["delay_p50_us"]:.0f} us,'
            f' p99 {row["delay_p99_us"]:.0f} us, {row["late"]} late' for row in variants)
        notes.append('The node class with its loop and grid origin as before 8dfbd58 and each '
                     'change alone (node_variant.py rows; the installed node has both): '
                     + described + '.')
    if SUSTAINED_RATE in node:
        row = node[SUSTAINED_RATE]
        sustained = (row['missing'] == 0
                     and abs(row['rate_error_pct']) <= 100.0 * TARGET_RATE_TOLERANCE)
        notes.append(
            f'Target: {SUSTAINED_RATE:g} Hz sustained (no tick dropped, rate within '
            f'{100 * TARGET_RATE_TOLERANCE:g} %). {row["achieved_hz"]:.1f} Hz, '
            f'{row["missing"]} missing, CPU {row["cpu_pct"]:.1f} %: '
            f'{"met" if sustained else "missed"}.')
    return notes


if __name__ == '__main__':
    import json
    print(json.dumps(run(quick='--quick' in sys.argv), indent=1, default=str))
