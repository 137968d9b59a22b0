"""
Helpers of the node benchmarks: ROS processes on a private domain, their CPU time and memory.

Every process started here gets a bench-only ``ROS_DOMAIN_ID`` and localhost-only discovery, so
that the benchmarks never see a developer's nodes, the tests, or each other's leftovers.
CPU time is utime + stime of /proc/<pid>/stat (all threads, DDS ones included), memory is
VmRSS of /proc/<pid>/status, and the time the main thread waited for a CPU while it was
runnable (the second field of /proc/<pid>/schedstat) shows how busy the machine was.
"""

import os
from pathlib import Path
import signal
import subprocess
import sys
import tempfile
import time
from typing import Callable, Dict, List, Optional, Sequence

import numpy as np

BENCH = Path(__file__).resolve().parent
ROOT = BENCH.parent
BIN = Path(sys.executable).parent
NODE = BIN / 'mouse_constraint_node'
OBSERVER = BENCH / 'observer.py'
BARE_TIMER = BENCH / 'bare_timer.py'
NODE_VARIANT = BENCH / 'node_variant.py'
# Away from the tests' domains (40-99, test/conftest.py) and from the default 0.
DOMAIN_ID = 20 + os.getpid() % 10
CLOCK_TICKS = os.sysconf('SC_CLK_TCK')


def environment() -> Dict[str, str]:
    """Return this process's environment with the bench-only ROS domain and discovery."""
    return dict(os.environ, ROS_DOMAIN_ID=str(DOMAIN_ID),
                ROS_AUTOMATIC_DISCOVERY_RANGE='LOCALHOST', PYTHONUNBUFFERED='1')


def node_command(parameters: Dict[str, object]) -> List[str]:
    """Return the command that starts ``mouse_constraint_node`` with ``parameters`` set."""
    command = [str(NODE), '--ros-args']
    for name, value in parameters.items():
        if isinstance(value, bool):
            text = 'true' if value else 'false'
        elif isinstance(value, (list, tuple)):
            text = '[' + ', '.join(repr(float(v)) for v in value) + ']'
        else:
            text = repr(value)
        command += ['-p', f'{name}:={text}']
    return command


def python_command(script: Path, *arguments: str) -> List[str]:
    """Return the command that runs a bench script with this interpreter."""
    return [sys.executable, str(script), *arguments]


def cpu_seconds(pid: int) -> float:
    """Return the CPU time (user + system, all threads) that process ``pid`` has used."""
    fields = Path(f'/proc/{pid}/stat').read_text().rsplit(')', 1)[1].split()
    return (int(fields[11]) + int(fields[12])) / CLOCK_TICKS  # Fields 14, 15 of stat(5).


def rss_kib(pid: int) -> int:
    """Return the resident set size of process ``pid`` (KiB)."""
    for line in Path(f'/proc/{pid}/status').read_text().splitlines():
        if line.startswith('VmRSS:'):
            return int(line.split()[1])
    raise RuntimeError(f'no VmRSS for pid {pid}')


def run_queue_wait_seconds(pid: int) -> float:
    """Return how long the main thread of ``pid`` has waited for a CPU while runnable (s)."""
    return int(Path(f'/proc/{pid}/schedstat').read_text().split()[1]) / 1e9


class Sample:
    """CPU time, run-queue wait and RSS of some processes at one moment, and the load."""

    def __init__(self, pids: Sequence[int]) -> None:
        self.wall = time.monotonic()
        self.cpu = {pid: cpu_seconds(pid) for pid in pids}
        self.wait = {pid: run_queue_wait_seconds(pid) for pid in pids}
        self.rss = {pid: rss_kib(pid) for pid in pids}
        self.load = os.getloadavg()[0]


def cpu_percent(first: Sample, last: Sample, pid: int) -> float:
    """Return the CPU use of ``pid`` between two samples, in percent of one core."""
    return 100.0 * (last.cpu[pid] - first.cpu[pid]) / (last.wall - first.wall)


def wait_per_second(first: Sample, last: Sample, pid: int) -> float:
    """Return the run-queue wait of ``pid``'s main thread between two samples, in ms per s."""
    return 1e3 * (last.wait[pid] - first.wait[pid]) / (last.wall - first.wall)


class Started:
    """A started process, stopped by SIGINT (then SIGKILL) when the ``with`` block ends."""

    def __init__(self, command: List[str], log: Optional[Path] = None, **popen) -> None:
        self.command = command
        self._log = open(log, 'w') if log is not None else subprocess.DEVNULL
        self.process = subprocess.Popen(command, env=environment(), cwd=ROOT,
                                        stderr=self._log, **popen)

    @property
    def pid(self) -> int:
        return self.process.pid

    def alive(self) -> bool:
        return self.process.poll() is None

    def stop(self, timeout: float = 5.0) -> int:
        """Send SIGINT, wait up to ``timeout`` seconds, then kill; return the exit code."""
        if self.alive():
            self.process.send_signal(signal.SIGINT)
            try:
                self.process.wait(timeout=timeout)
            except subprocess.TimeoutExpired:
                self.process.kill()
                self.process.wait()
        if self._log is not subprocess.DEVNULL:
            self._log.close()
        return self.process.returncode

    def __enter__(self) -> 'Started':
        return self

    def __exit__(self, *_exception) -> None:
        self.stop()


def observe(arguments: Sequence[str], watched: Sequence[int],
            on_line: Optional[Callable[[str], None]] = None, timeout: float = 120.0):
    """
    Run ``observer.py`` with ``arguments``; return (its results, samples, observer pid).

    ``samples`` maps each line the observer prints (``ready``, ``start``, ``end``) to a
    ``Sample`` of the ``watched`` processes and the observer, taken when the line arrives.
    """
    with tempfile.TemporaryDirectory(prefix='mouse_bench_') as directory:
        out = Path(directory) / 'observed.npz'
        command = python_command(OBSERVER, *arguments, '--out', str(out))
        process = subprocess.Popen(command, env=environment(), cwd=ROOT,
                                   stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
        samples = {}
        deadline = time.monotonic() + timeout
        try:
            for line in process.stdout:
                word = line.split()[0] if line.split() else ''
                if word in ('ready', 'start', 'end'):
                    samples[word] = Sample([*watched, process.pid])
                if on_line is not None:
                    on_line(line)
                if time.monotonic() > deadline:
                    raise RuntimeError(f'observer still running after {timeout:g} s')
            process.wait(timeout=30.0)
        finally:
            if process.poll() is None:
                process.kill()
                process.wait()
        if process.returncode != 0:
            raise RuntimeError(f'observer failed ({process.returncode}): '
                               + process.stderr.read()[-2000:])
        process.stderr.close()
        with np.load(out) as data:
            return {name: data[name] for name in data.files}, samples, process.pid
