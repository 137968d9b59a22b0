"""
The node under a target flood: 20 000 targets/s for 10 s at the node process running at 1 kHz.

The node is the installed ``mouse_constraint_node`` (its own process, no gravity, damping 2/s,
workspace_radius 100 m); the flooder is another process publishing pre-serialized
``PointStamped`` targets that go round a circle of 0.3 m in 2 s, its phase the system clock's;
the observer is this process. Cases: valid targets only; every other target hostile (NaN, inf,
1e300, beyond the workspace, foreign frames, absurd stamps); every target hostile.

Measured: the node's output rate counted by grid stamps (a dropped tick is a missing stamp) and
by DDS write time, the ticks missing, how late it wrote them (write time - stamp, p99 and max),
its RSS after start, after the first flood second and at the end, its CPU share and how long its
main thread waited for a CPU (a busy machine shows there), the anchor's lag behind the target's
phase (median over the flood: a backlog of old targets would grow it) and its distance from the
last valid target after the flood. Also the cost of one target callback in-process, valid and
rejected. ``test/test_hardening.py`` asserts the same for a 3 s flood. Nothing here asserts.

Standalone: ``python bench/flood.py [--quick] [--seconds S]``.
"""

import argparse
import math
import os
import sys
import time

import common

CASES = [('valid targets', 0), ('every 2nd hostile', 2), ('all hostile', 1)]
SECONDS = 10.0
QUICK_SECONDS = 2.0
RATE = 20000.0


def _tools():
    if str(common.TEST_DIR) not in sys.path:
        sys.path.insert(0, str(common.TEST_DIR))
    import hardening_tools
    import ros_helpers
    return hardening_tools, ros_helpers


def _isolate() -> None:
    # As test/conftest.py: a domain of our own, localhost only, so that the flood reaches no one
    # else's nodes (rclpy reads these at init; the child processes inherit them).
    os.environ['ROS_DOMAIN_ID'] = str(40 + os.getpid() % 60)
    os.environ['ROS_AUTOMATIC_DISCOVERY_RANGE'] = 'LOCALHOST'


def callback_cost_us(repeats: int) -> dict:
    """Return the microseconds per target callback of an in-process node, valid and rejected."""
    import rclpy

    from mouse_constraint_ros.messages import point_message
    from mouse_constraint_ros.node import MouseConstraintNode

    context = rclpy.Context()
    rclpy.init(context=context)
    node = MouseConstraintNode(context=context)
    try:
        [subscription] = [s for s in node.subscriptions if s.topic_name == '/target']
        costs = {}
        for label, message in [
                ('valid', point_message((0.1, 0.2, 1.0), 'world', 0)),
                ('NaN', point_message((math.nan, 0.2, 1.0), 'world', 0)),
                ('foreign frame', point_message((0.1, 0.2, 1.0), 'map', 0)),
                ('beyond workspace', point_message((1e300, 0.2, 1.0), 'world', 0))]:
            callback = subscription.callback
            began = time.perf_counter()
            for _ in range(repeats):
                callback(message)
            costs[label] = (time.perf_counter() - began) / repeats * 1e6
        return costs
    finally:
        node.destroy_node()
        rclpy.try_shutdown(context=context)


def run(quick: bool, seconds: float = None) -> dict:
    """Return the section: one row per flood case."""
    _isolate()
    tools, ros_helpers = _tools()
    seconds = seconds or (QUICK_SECONDS if quick else SECONDS)
    rows = []
    for label, hostile_every in CASES:
        harness = ros_helpers.RosHarness()
        try:
            result = tools.run_flood(harness, seconds, RATE, hostile_every)
        finally:
            harness.shutdown()
        lags = [lag for lag in result['lag_s'] if math.isfinite(lag)]
        rows.append({
            'case': label,
            'sent': result['flood']['rate'],
            'stamp_rate': result['stamp_rate_hz'],
            'publish_rate': result['publish_rate_hz'],
            'missing': result['missing_ticks'],
            'late_p99': result['late_ms_p99'],
            'late_max': result['late_ms_max'],
            'rss_start': result['rss_start_mb'],
            'rss_1s': result['rss_flood_1s_mb'],
            'rss_end': result['rss_end_mb'],
            'cpu': 100.0 * result['node_cpu_share'],
            'flooder_cpu': 100.0 * result['flooder_cpu_share'],
            'observer_cpu': 100.0 * result['observer_cpu_share'],
            'run_delay': result['node_run_delay_ms'],
            'lag': 1e3 * common.median(lags) if lags else None,
            'final_error': result['final_error_m'],
        })
    costs = callback_cost_us(500 if quick else 5000)
    return {
        'title': f'Target flood: {RATE:g} targets/s for {seconds:g} s at the 1 kHz node process',
        'text': __doc__.split('\n\n')[1].replace('\n', ' '),
        'columns': [
            ['case', 'case', ''],
            ['sent', 'sent /s', '.0f'],
            ['stamp_rate', 'output Hz (stamps)', '.1f'],
            ['publish_rate', 'output Hz (write time)', '.1f'],
            ['missing', 'ticks missing', ''],
            ['late_p99', 'late p99 ms', '.1f'],
            ['late_max', 'late max ms', '.1f'],
            ['rss_start', 'RSS start MB', '.1f'],
            ['rss_1s', 'RSS 1 s MB', '.1f'],
            ['rss_end', 'RSS end MB', '.1f'],
            ['cpu', 'node CPU %', '.0f'],
            ['flooder_cpu', 'flooder CPU %', '.0f'],
            ['observer_cpu', 'observer CPU %', '.0f'],
            ['run_delay', 'node waited for CPU ms', '.0f'],
            ['lag', 'anchor lag ms', '.1f'],
            ['final_error', 'last target error m', '.1e'],
        ],
        'rows': rows,
        'notes': [
            'Output rate by stamps counts the ticks published per second of the flood; by '
            'write time it also carries the lateness at the window edges. Ticks go missing '
            'only when the node is more than 100 ms late (its catch-up bound); "node waited '
            'for CPU" is its main thread\'s run-queue time over the flood (/proc schedstat): '
            'large values mean the machine, not the node, was short of CPU.',
            'In the hostile cases "last target error" is not the node\'s: the target '
            'subscription keeps only the newest message (depth 1), so a bad message published '
            'right after the last valid one can replace it before the node takes it.',
            'In-process cost of one target callback (us): ' + ', '.join(
                f'{label} {cost:.1f}' for label, cost in costs.items()) + '.',
        ],
        'callback_cost_us': costs,
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
