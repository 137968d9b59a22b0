#!/usr/bin/env python3
"""
The node's own class, run with a chosen spin loop and tick-grid origin, and optionally timed.

``node_variant.py --loop once|until --grid node|first-call|scheduled [--report FILE]
[--ros-args ...]`` runs ``MouseConstraintNode`` from the package, unchanged, in a main loop like
``node.main``'s, until SIGINT/SIGTERM, with the choices fixed here whatever ``node.py`` does, so
that an A/B comparison means the same before and after the node changes:

- ``--loop once``: ``EventsExecutor.spin_once(timeout_sec=0.1)`` in a loop (node.main before
  8dfbd58); ``--loop until``: ``spin_until_future_complete(never_done, timeout_sec=0.1)`` in a
  loop (since), which runs every event due within the 0.1 s in one call;
- ``--grid first-call``: the tick grid's t0 at the clock reading of the timer's first call
  (before 8dfbd58); ``--grid scheduled``: t0 at the time the timer scheduled that call
  (``now + time_until_next_call - period``, since), so that every later call finds exactly its
  own tick due however late it runs (up to a period); ``--grid node``: whatever the node does.

With ``--report FILE`` it writes, on exit, the thread CPU time of the main thread spent in each
part of the tick (``time.thread_time_ns`` around the step, each publish, the grid, the whole
timer callback, the marker and diagnostics callbacks) and in total, as JSON.
"""

import argparse
import collections
import json
import sys
import time

import rclpy
from rclpy.experimental import EventsExecutor
from rclpy.signals import SignalHandlerOptions
from rclpy.task import Future
from rclpy.utilities import remove_ros_args

from mouse_constraint_ros.node import MouseConstraintNode
from mouse_constraint_ros.spin import StopRequest


class PartTimer:
    """Thread CPU time (ns) and calls per named part, by wrapping callables."""

    def __init__(self) -> None:
        self.nanoseconds = collections.Counter()
        self.calls = collections.Counter()

    def wrap(self, function, name: str):
        clock = time.thread_time_ns
        nanoseconds, calls = self.nanoseconds, self.calls

        def timed(*args, **kwargs):
            start = clock()
            try:
                return function(*args, **kwargs)
            finally:
                nanoseconds[name] += clock() - start
                calls[name] += 1
        return timed


def grid_origin(node: MouseConstraintNode, callback, how: str):
    """Return ``callback`` that first starts the node's tick grid at t0 chosen by ``how``."""
    def started() -> None:
        grid = node._grid
        if not grid.started:
            now = node.get_clock().now().nanoseconds
            left = node._timer.time_until_next_call()
            if how == 'scheduled' and left is not None:
                grid.restart(now + left - node._timer.timer_period_ns)
            else:
                grid.restart(now)
        callback()
    return started


def main(argv=None) -> int:
    argv = sys.argv if argv is None else argv
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[1])
    parser.add_argument('--loop', choices=('once', 'until'), default='until')
    parser.add_argument('--grid', choices=('node', 'first-call', 'scheduled'), default='node')
    parser.add_argument('--report', help='write the per-part CPU times here on exit (JSON)')
    options = parser.parse_args(remove_ros_args(argv)[1:])
    rclpy.init(args=argv, signal_handler_options=SignalHandlerOptions.NO)
    node = MouseConstraintNode()
    parts = PartTimer()
    timer_callback = node._timer.callback
    if options.report:
        simulation = node._simulation
        simulation.step = parts.wrap(simulation.step, 'step')
        node._pose_publisher.publish = parts.wrap(node._pose_publisher.publish, 'publish pose')
        node._twist_publisher.publish = parts.wrap(node._twist_publisher.publish,
                                                   'publish twist')
        node._grid.due = parts.wrap(node._grid.due, 'grid due')
        timer_callback = parts.wrap(timer_callback, 'timer callback')
        for timer in getattr(node, '_monitor_timers', []):
            timer.callback = parts.wrap(timer.callback, 'markers and diagnostics')
    if options.grid != 'node':
        timer_callback = grid_origin(node, timer_callback, options.grid)
    node._timer.callback = timer_callback
    executor = EventsExecutor(context=node.context)
    executor.add_node(node)
    never = Future()
    context = node.context
    with StopRequest() as stop:
        thread_start, wall_start = time.thread_time_ns(), time.monotonic()
        process_start = time.process_time_ns()
        ticks_start = node.ticks_run
        while not stop and context.ok():
            if options.loop == 'once':
                executor.spin_once(timeout_sec=0.1)
            else:
                executor.spin_until_future_complete(never, timeout_sec=0.1)
        main_thread = time.thread_time_ns() - thread_start
        process = time.process_time_ns() - process_start
        wall = time.monotonic() - wall_start
    if options.report:
        with open(options.report, 'w') as report:
            json.dump({'wall_s': wall, 'ticks': node.ticks_run - ticks_start,
                       'late_ticks': node.late_ticks, 'dropped_ticks': node.dropped_ticks,
                       'process_ns': process, 'main_thread_ns': main_thread,
                       'parts_ns': dict(parts.nanoseconds), 'calls': dict(parts.calls)},
                      report)
    node.destroy_node()
    rclpy.try_shutdown()
    return 0


if __name__ == '__main__':
    sys.exit(main())
