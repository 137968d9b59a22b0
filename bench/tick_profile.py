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
Where a tick of the running node goes: py-spy samples of its main thread, sorted into parts.

``python -m bench.tick_profile [--py-spy PATH] [--seconds 15] [--rate 250] [--domain N]
[--raw FILE]`` (from the repository's root; ``make bench`` runs it as a section) starts
``mouse_constraint_node --ros-args --params-file config/params.yaml`` and, in another process, a
reader of ``pose`` and ``twist`` (ordinary, deserializing subscriptions), then runs ``py-spy
record --native -f raw`` on the node for the window. py-spy is not a dependency of the package:
``make bench-venv`` installs it into ``.venv`` (``requirements/bench/``); without it the section
says so.

Each sample of the main thread is put in the first part whose frame it holds, looked for from
the leaf up: the physics step, the grid and clock reads, the stamp and field filling, the
publish calls split into the Python -> C message conversion, rmw's CDR serialization in C, and
the DDS write, the marker and diagnostics callbacks, the rest of the timer callback, and the
executor turn (everything else in the spin loop). Samples of the executor waiting for its next
event (a condition variable or epoll wait) are not CPU time: they are counted apart and left
out. A part's microseconds per tick are its share of the samples on a CPU times the main
thread's CPU time per tick over the window (/proc), so they
assume py-spy's samples fall on the CPU time evenly: py-spy also samples a thread that is
runnable but waiting for a CPU, which on a busy machine weighs the parts after a wake-up (the
DDS write wakes the reader) more. The other threads' CPU per tick is shown beside it. For
CPU-only shares of the native parts (conversion, CDR serialization, DDS write), ``perf record
--call-graph dwarf -p <node pid>`` samples on-CPU time only, but shows no Python functions.
"""

import argparse
import collections
import json
import os
from pathlib import Path
import shutil
import signal
import subprocess
import sys
import tempfile
import time
from typing import Dict, List, Optional, Tuple

BENCH = Path(__file__).resolve().parent
ROOT = BENCH.parent
CLOCK_TICKS = os.sysconf('SC_CLK_TCK')
# The sampling window (s) and py-spy's samples per second.
SECONDS, QUICK_SECONDS, RATE = 15.0, 5.0, 250

# The executor waiting for its next event: py-spy samples the thread there although it is not
# on a CPU; these samples are counted apart and left out of the CPU shares.
WAITING = 'waiting for the next event (not CPU)'
# (part, frame markers): a sample goes to the first part, leaf first, one of whose markers is
# in a frame of its stack.
PARTS: List[Tuple[str, Tuple[str, ...]]] = [
    (WAITING, ('pthread_cond_timedwait', 'pthread_cond_wait', 'epoll_wait', 'futex_wait')),
    ('CDR serialization (C, in rmw)', ('TypeSupport::serialize', 'getEstimatedSerializedSize',
                                       'cdr_serialize')),
    ('DDS write (rcl_publish, Fast DDS)', ('rcl_publish',)),
    ('message conversion (Python -> C)', ('convert_from_py', '__create', '__destroy',
                                          '__init (', '__fini')),
    ('publish, rest (rclpy Python)', ('Publisher.publish',)),
    ('physics step', ('MouseSimulation.step', 'physics/')),
    ('stamp and field filling', ('set_stamp', 'fill_pose', 'fill_twist')),
    ('grid and clock reads', ('tick_grid.py', 'Clock.now', 'time_until_next_call',
                              '_release_if_timed_out', 'Time.nanoseconds')),
    ('markers and diagnostics (own timers)', ('publish_markers', 'publish_diagnostics')),
    ('timer callback, rest', ('_on_timer',)),
    ('executor turn and spin loop', ('spin_once', 'main (')),
]
UNSORTED = 'other (not under the spin loop)'
READER = """
import json, signal, sys
import rclpy
from rclpy.executors import SingleThreadedExecutor
from rclpy.node import Node
from rclpy.qos import HistoryPolicy, QoSProfile, ReliabilityPolicy
from rclpy.signals import SignalHandlerOptions
from geometry_msgs.msg import PoseStamped, TwistStamped
rclpy.init(signal_handler_options=SignalHandlerOptions.NO)
node = Node('tick_profile_reader')
qos = QoSProfile(history=HistoryPolicy.KEEP_LAST, depth=100,
                 reliability=ReliabilityPolicy.RELIABLE)
counts = {'pose': 0, 'twist': 0}
def counter(name):
    def count(_message):
        counts[name] += 1
    return count
node.create_subscription(PoseStamped, 'pose', counter('pose'), qos)
node.create_subscription(TwistStamped, 'twist', counter('twist'), qos)
stop = []
signal.signal(signal.SIGINT, lambda *_: stop.append(1))
signal.signal(signal.SIGUSR1, lambda *_: print(json.dumps(counts), flush=True))
executor = SingleThreadedExecutor(context=node.context)
executor.add_node(node)
while not stop:
    executor.spin_once(timeout_sec=0.1)
executor.shutdown()
node.destroy_node()
rclpy.try_shutdown()
"""


def thread_cpu(pid: int) -> Dict[int, Tuple[str, float]]:
    """Return, per thread id of ``pid``, its name and CPU seconds (utime + stime)."""
    threads = {}
    for task in Path(f'/proc/{pid}/task').iterdir():
        try:
            name = (task / 'comm').read_text().strip()
            fields = (task / 'stat').read_text().rsplit(')', 1)[1].split()
        except OSError:
            continue
        threads[int(task.name)] = (name, (int(fields[11]) + int(fields[12])) / CLOCK_TICKS)
    return threads


def categorize(raw: str) -> Dict[str, int]:
    """Return the main thread's samples per part from py-spy's raw output."""
    counts: Dict[str, int] = collections.Counter()
    for line in raw.splitlines():
        if not line.strip():
            continue
        stack, count = line.rsplit(' ', 1)
        frames = stack.split(';')
        if not any(frame.startswith('<module> (') for frame in frames[:3]):
            continue  # Not the main thread.
        part = UNSORTED
        for frame in reversed(frames):
            part = next((name for name, markers in PARTS
                         if any(marker in frame for marker in markers)), None)
            if part is not None:
                break
        counts[part or UNSORTED] += int(count)
    return counts


def reader_counts(reader: subprocess.Popen) -> Dict[str, int]:
    reader.send_signal(signal.SIGUSR1)
    return json.loads(reader.stdout.readline())


def profile(py_spy: str, seconds: float = SECONDS, rate: int = RATE,
            domain: Optional[int] = None, raw: Optional[Path] = None) -> dict:
    """
    Profile the node for ``seconds``; return its ticks, CPU per tick and samples per part.

    :param py_spy: the py-spy executable.
    :param seconds: the sampling window.
    :param rate: py-spy's samples per second.
    :param domain: the ROS domain of the node and its reader (default: 20-29 from the pid).
    :param raw: where to keep py-spy's raw output (default: nowhere).
    """
    domain = 20 + os.getpid() % 10 if domain is None else domain
    env = dict(os.environ, ROS_DOMAIN_ID=str(domain),
               ROS_AUTOMATIC_DISCOVERY_RANGE='LOCALHOST', PYTHONUNBUFFERED='1')
    node_bin = Path(sys.executable).parent / 'mouse_constraint_node'
    reader = subprocess.Popen([sys.executable, '-c', READER], env=env, stdout=subprocess.PIPE,
                              text=True)
    node = subprocess.Popen([str(node_bin), '--ros-args', '--params-file',
                             str(ROOT / 'config' / 'params.yaml')], env=env, cwd=ROOT,
                            stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    try:
        time.sleep(5.0)  # Discovery and warm-up.
        with tempfile.TemporaryDirectory(prefix='tick_profile_') as directory:
            out = raw or Path(directory) / 'profile.txt'
            before, start = thread_cpu(node.pid), reader_counts(reader)
            wall = time.monotonic()
            subprocess.run([py_spy, 'record', '--native', '-r', str(rate),
                            '-d', str(int(seconds)), '-f', 'raw', '-o', str(out),
                            '--pid', str(node.pid)], check=True, capture_output=True)
            wall = time.monotonic() - wall
            after, end = thread_cpu(node.pid), reader_counts(reader)
            samples = categorize(Path(out).read_text())
    finally:
        for process in (node, reader):
            process.send_signal(signal.SIGINT)
        for process in (node, reader):
            try:
                process.wait(timeout=10.0)
            except subprocess.TimeoutExpired:
                process.kill()
                process.wait()
    ticks = end['pose'] - start['pose']
    main_cpu = after[node.pid][1] - before[node.pid][1]
    other_cpu = sum(cpu - before[tid][1] for tid, (_, cpu) in after.items()
                    if tid != node.pid and tid in before)
    waiting = samples.pop(WAITING, 0)
    total = sum(samples.values())
    parts = []
    for name in [name for name, _ in PARTS if name != WAITING] + [UNSORTED]:
        share = samples.get(name, 0) / total if total else 0.0
        parts.append({'part': name, 'share_pct': 100.0 * share,
                      'us_per_tick': share * 1e6 * main_cpu / ticks})
    return {'ticks': ticks, 'wall_s': wall, 'main_us_per_tick': 1e6 * main_cpu / ticks,
            'other_us_per_tick': 1e6 * other_cpu / ticks, 'samples': total,
            'waiting': waiting, 'load': os.getloadavg()[0], 'parts': parts}


def find_py_spy() -> Optional[str]:
    """Return py-spy beside this interpreter (make bench-venv installs it), or on PATH."""
    beside = Path(sys.executable).parent / 'py-spy'
    return str(beside) if beside.is_file() else shutil.which('py-spy')


def run(quick: bool = False) -> dict:
    """Return the section: the parts of the main thread's samples, and the CPU per tick."""
    began = time.perf_counter()
    title = "Where a tick's time goes: py-spy samples of the node's main thread"
    py_spy = find_py_spy()
    if py_spy is None:
        return {'title': title, 'rows': [], 'elapsed_s': time.perf_counter() - began,
                'text': 'Not measured: no py-spy (requirements/bench/, make bench-venv).'}
    try:
        result = profile(py_spy, seconds=QUICK_SECONDS if quick else SECONDS)
    except subprocess.CalledProcessError as error:  # No ptrace here, say.
        return {'title': title, 'rows': [], 'elapsed_s': time.perf_counter() - began,
                'text': f'Not measured: py-spy failed: {error.stderr.decode().strip()[-300:]}'}
    return {
        'title': title,
        'text': ('Command: `python -m bench.tick_profile`. The node with config/params.yaml, '
                 'pose and twist read by another process; `py-spy record --native` on the '
                 'node, each sample of its main thread put in the first part whose frame it '
                 'holds (leaf first); the samples of the executor waiting for its next event '
                 'are not CPU and are left out. us per tick: the share times the main '
                 "thread's CPU per tick."),
        'columns': [['part', 'part', ''], ['share_pct', 'samples on a CPU (%)', '.1f'],
                    ['us_per_tick', 'us per tick', '.1f']],
        'rows': result['parts'],
        'notes': [
            f'{result["ticks"]} ticks in {result["wall_s"]:.1f} s; main thread '
            f'{result["main_us_per_tick"]:.1f} us of CPU per tick, the other threads (DDS, '
            f'rclpy) {result["other_us_per_tick"]:.1f} us; {result["samples"]} samples on a '
            f'CPU, {result["waiting"]} waiting; load {result["load"]:.2f}.',
            'py-spy also samples a thread that waits for a CPU: on a busy machine the parts '
            'after a wake-up (the DDS write wakes the reader) weigh more.',
        ],
        'figures': {'main_us_per_tick': result['main_us_per_tick'],
                    'other_us_per_tick': result['other_us_per_tick']},
        'elapsed_s': time.perf_counter() - began,
    }


def main(argv=None) -> int:
    """Print the profile as a table (see the module's docstring)."""
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[1])
    parser.add_argument('--py-spy', default=find_py_spy(),
                        help='path of the py-spy executable (default: %(default)s)')
    parser.add_argument('--seconds', type=float, default=SECONDS)
    parser.add_argument('--rate', type=int, default=RATE, help='py-spy samples per second')
    parser.add_argument('--domain', type=int, default=None)
    parser.add_argument('--raw', type=Path, help='keep py-spy raw output here')
    options = parser.parse_args(argv)
    if options.py_spy is None:
        parser.error('no py-spy: make bench-venv installs it, or pass --py-spy PATH')
    result = profile(options.py_spy, options.seconds, options.rate, options.domain, options.raw)
    print(f'{result["ticks"]} ticks (poses received) in {result["wall_s"]:.1f} s; main thread '
          f'{result["main_us_per_tick"]:.1f} us CPU per tick, other threads '
          f'{result["other_us_per_tick"]:.1f} us; {result["samples"]} samples on a CPU, '
          f'{result["waiting"]} waiting; load {result["load"]:.2f}')
    print('| part | samples % | us per tick |')
    print('| --- | ---: | ---: |')
    for part in result['parts']:
        print(f'| {part["part"]} | {part["share_pct"]:.1f} | {part["us_per_tick"]:.1f} |')
    return 0


if __name__ == '__main__':
    sys.exit(main())
