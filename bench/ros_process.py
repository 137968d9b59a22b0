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
The node benchmarks' side of the processes: a bench-only ROS domain, the observer, /proc samples.

Every process started here gets the bench's ``ROS_DOMAIN_ID`` (``MOUSE_TEST_DOMAIN_ID`` when
set, else 20-29 from the bench's pid: away from the tests' 40-99 and from the default 0) and
localhost-only discovery, so that the benchmarks never see a developer's nodes, the tests, or
each other's leftovers. The processes themselves are ``test_support.processes.ChildProcess``;
``Sample`` reads their CPU time (also per kind of thread, ``thread_cpu``), run-queue wait and
RSS at one moment.
"""

import os
from pathlib import Path
import subprocess
import tempfile
import time
from typing import Callable, Dict, List, Mapping, Optional, Sequence

import numpy as np

from test_support import processes

ROOT = processes.ROOT
DOMAIN_ID = int(os.environ.get('MOUSE_TEST_DOMAIN_ID', 20 + os.getpid() % 10))


def environment() -> Dict[str, str]:
    """Return this process's environment with the bench-only ROS domain and discovery."""
    return processes.private_environment(DOMAIN_ID)


def node_command(parameters: Mapping[str, object]) -> List[str]:
    """Return the command that starts ``mouse_constraint_node`` with ``parameters`` set."""
    return processes.node_command(parameters=parameters)


def timer_node_command(parameters: Mapping[str, object]) -> List[str]:
    """Return the command of the node with its ticks on an rclpy timer (``bench.timer_node``)."""
    return [*bench_command('timer_node'), '--ros-args',
            *processes.parameter_arguments(parameters)]


def bench_command(module: str, *arguments: str) -> List[str]:
    """Return the command that runs ``python -m bench.<module> arguments``."""
    return processes.module_command(f'bench.{module}', *arguments)


def start(command: Sequence[str]) -> processes.ChildProcess:
    """Start ``command`` on the bench's domain; use it as a context manager."""
    return processes.ChildProcess(command, environment=environment())


# The kinds of thread ``thread_cpu`` sorts a process's CPU time into.
MAIN_THREAD = 'main'
DDS_THREADS = 'dds'
OTHER_THREADS = 'other'


def thread_cpu(pid: int) -> Dict[str, float]:
    """
    Return the CPU time (s) of ``pid``'s threads by kind: main, Fast DDS's (``dds.*``), other.

    In an rclpy process the other threads are rclpy's own: the EventsExecutor's timers thread,
    which waits for each timer and hands its call to the spinning thread. A thread that ended
    is not counted (``/proc`` no longer lists it).
    """
    kinds = {MAIN_THREAD: 0.0, DDS_THREADS: 0.0, OTHER_THREADS: 0.0}
    for task in Path(f'/proc/{pid}/task').iterdir():
        try:
            stat = (task / 'stat').read_text()
        except OSError:
            continue  # the thread ended meanwhile
        name = stat[stat.index('(') + 1:stat.rindex(')')]
        fields = stat[stat.rindex(')') + 2:].split()
        seconds = (int(fields[11]) + int(fields[12])) / processes.CLOCK_TICKS
        if int(task.name) == pid:
            kinds[MAIN_THREAD] += seconds
        elif name.startswith('dds.'):
            kinds[DDS_THREADS] += seconds
        else:
            kinds[OTHER_THREADS] += seconds
    return kinds


class Sample:
    """CPU time, run-queue wait and RSS of some processes at one moment, and the load."""

    def __init__(self, pids: Sequence[int]) -> None:
        self.wall = time.monotonic()
        self.cpu = {pid: processes.cpu_seconds(pid) for pid in pids}
        self.threads = {pid: thread_cpu(pid) for pid in pids}
        self.wait = {pid: processes.run_delay_ns(pid) / 1e9 for pid in pids}
        self.rss = {pid: processes.rss_bytes(pid) / 1024.0 for pid in pids}
        self.load = os.getloadavg()[0]


def cpu_percent(first: Sample, last: Sample, pid: int) -> float:
    """Return the CPU use of ``pid`` between two samples, in percent of one core."""
    return 100.0 * (last.cpu[pid] - first.cpu[pid]) / (last.wall - first.wall)


def wait_per_second(first: Sample, last: Sample, pid: int) -> float:
    """Return the run-queue wait of ``pid``'s main thread between two samples, in ms per s."""
    return 1e3 * (last.wait[pid] - first.wait[pid]) / (last.wall - first.wall)


def observe(arguments: Sequence[str], watched: Sequence[int],
            on_line: Optional[Callable[[str], None]] = None, timeout: float = 120.0):
    """
    Run ``bench.observer`` with ``arguments``; return (its results, samples, observer pid).

    ``samples`` maps each line the observer prints (``ready``, ``start``, ``end``) to a
    ``Sample`` of the ``watched`` processes and the observer, taken when the line arrives.
    """
    with tempfile.TemporaryDirectory(prefix='mouse_bench_') as directory:
        out = Path(directory) / 'observed.npz'
        observer = processes.ChildProcess(bench_command('observer', *arguments, '--out', str(out)),
                                          environment=environment(), stdout=subprocess.PIPE)
        samples = {}
        deadline = time.monotonic() + timeout
        try:
            for line in observer.process.stdout:
                word = line.split()[0] if line.split() else ''
                if word in ('ready', 'start', 'end'):
                    samples[word] = Sample([*watched, observer.pid])
                if on_line is not None:
                    on_line(line)
                if time.monotonic() > deadline:
                    raise RuntimeError(f'observer still running after {timeout:g} s')
            observer.process.wait(timeout=30.0)
            if observer.process.returncode != 0:
                raise RuntimeError(f'observer failed ({observer.process.returncode}): '
                                   + observer.log()[-2000:])
        finally:
            observer.close()
        with np.load(out) as data:
            return {name: data[name] for name in data.files}, samples, observer.pid
