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
RSS per call of the EventsExecutor's spin calls, in a process of its own.

``python -m bench.spin_leak [--calls N]`` makes N calls of each with a zero timeout, after a
warm-up, and prints the RSS growth per call as JSON: ``spin_once``; ``spin_until_future_complete``
with one future that is never done; the same with a fresh
future per call. At 0.1 s per call a node makes 10 calls a second. ``node.main`` spins with
``spin_once``; this shows why not ``spin_until_future_complete`` (the rclpy version is in the
results' machine facts).
"""

import argparse
import gc
import json
import sys

import rclpy
from rclpy.experimental import EventsExecutor
from rclpy.node import Node
from rclpy.task import Future


def rss_kib() -> int:
    """Return this process's resident set size (KiB)."""
    for line in open('/proc/self/status'):
        if line.startswith('VmRSS:'):
            return int(line.split()[1])
    raise RuntimeError('no VmRSS')


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[1])
    parser.add_argument('--calls', type=int, default=50000)
    options = parser.parse_args(argv)
    rclpy.init()
    node = Node('bench_spin_leak')
    executor = EventsExecutor(context=node.context)
    executor.add_node(node)
    never = Future()
    calls = {
        'spin_once(timeout_sec=0)': lambda: executor.spin_once(timeout_sec=0.0),
        'spin_until_future_complete(never_done, timeout_sec=0)':
            lambda: executor.spin_until_future_complete(never, timeout_sec=0.0),
        'spin_until_future_complete(Future(), timeout_sec=0)':
            lambda: executor.spin_until_future_complete(Future(), timeout_sec=0.0),
    }
    result = {}
    try:
        for name, call in calls.items():
            for _ in range(options.calls // 10):
                call()
            gc.collect()
            before = rss_kib()
            for _ in range(options.calls):
                call()
            gc.collect()
            result[name] = 1024.0 * (rss_kib() - before) / options.calls
    finally:
        node.destroy_node()
        rclpy.try_shutdown()
    print(json.dumps({'calls': options.calls, 'bytes_per_call': result}))
    return 0


if __name__ == '__main__':
    sys.exit(main())
