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
Child processes of the tests and the benchmarks: the node and its peers on a private domain.

``ChildProcess`` starts a command (the installed ``mouse_constraint_node``, a flooder, an
observer) with its output in a temporary log file, and ``stop`` ends it the way a user would:
SIGINT, then SIGKILL if it has not exited in time. ``finish`` is the clean-up of a test or a
benchmark that ran a node with helpers beside it. ``cpu_seconds``, ``rss_bytes`` and
``run_delay_ns`` read /proc: utime + stime of all the process's threads (DDS ones included),
its resident set, and how long its main thread waited for a CPU while runnable (a busy machine,
not a slow process, shows there). ``short_lease_environment`` gives a child a DDS lease of 3 s, so
that its peers see it gone soon after it is killed.
"""

import math
import os
from pathlib import Path
import signal
import subprocess
import sys
import tempfile
from typing import Dict, List, Mapping, Optional, Sequence, Tuple

BIN = Path(sys.executable).parent
ROOT = Path(__file__).resolve().parent.parent
NODE_EXECUTABLE = BIN / 'mouse_constraint_node'
PAGE_SIZE = os.sysconf('SC_PAGE_SIZE')
CLOCK_TICKS = os.sysconf('SC_CLK_TCK')


def private_environment(domain_id: Optional[int] = None,
                        base: Optional[Mapping[str, str]] = None) -> Dict[str, str]:
    """
    Return ``base`` (this process's environment) with localhost-only discovery and a domain.

    :param domain_id: the ``ROS_DOMAIN_ID`` to set; None keeps the one in ``base``.
    """
    environment = dict(os.environ if base is None else base,
                       ROS_AUTOMATIC_DISCOVERY_RANGE='LOCALHOST', PYTHONUNBUFFERED='1')
    if domain_id is not None:
        environment['ROS_DOMAIN_ID'] = str(domain_id)
    return environment


# A Fast DDS participant that announces itself every 0.5 s and is given up 3 s after its last
# announcement (the default: every 3 s, given up after 20 s), so that its peers see a killed
# process gone within seconds. Fast DDS reads it from FASTRTPS_DEFAULT_PROFILES_FILE.
SHORT_LEASE_PROFILE = """<?xml version="1.0" encoding="UTF-8"?>
<dds xmlns="http://www.eprosima.com/XMLSchemas/fastRTPS_Profiles">
  <profiles>
    <participant profile_name="short_lease" is_default_profile="true">
      <rtps>
        <builtin>
          <discovery_config>
            <leaseDuration><sec>3</sec></leaseDuration>
            <leaseAnnouncement><sec>0</sec><nanosec>500000000</nanosec></leaseAnnouncement>
          </discovery_config>
        </builtin>
      </rtps>
    </participant>
  </profiles>
</dds>
"""


def short_lease_environment(folder: Path, base: Mapping[str, str]) -> Dict[str, str]:
    """
    Return ``base`` with Fast DDS's participant profile SHORT_LEASE_PROFILE, written in ``folder``.

    A process started with it that is killed (no goodbye to its peers) is seen gone by them
    3 s later instead of 20 s.
    """
    profile = Path(folder) / 'short_lease.xml'
    profile.write_text(SHORT_LEASE_PROFILE)
    return dict(base, FASTRTPS_DEFAULT_PROFILES_FILE=str(profile))


def yaml_float(value: float) -> str:
    """Return a float as YAML writes it: ``.inf``, ``-.inf`` and ``.nan`` for the non-finite."""
    if math.isnan(value):
        return '.nan'
    if math.isinf(value):
        return '.inf' if value > 0.0 else '-.inf'
    return repr(value)


def parameter_arguments(parameters: Mapping[str, object]) -> List[str]:
    """Return ``-p name:=value`` ROS arguments for ``parameters`` (doubles as float literals)."""
    arguments = []
    for name, value in parameters.items():
        if isinstance(value, bool):
            text = 'true' if value else 'false'
        elif isinstance(value, (list, tuple)):
            text = '[' + ', '.join(yaml_float(float(v)) for v in value) + ']'
        elif isinstance(value, float):
            text = yaml_float(value)
        else:
            text = repr(value)
        arguments += ['-p', f'{name}:={text}']
    return arguments


def node_command(*ros_arguments: str, parameters: Mapping[str, object] = None,
                 prefix: Sequence[str] = ()) -> List[str]:
    """Return the command of ``mouse_constraint_node`` with ``parameters`` and ROS arguments."""
    return [*prefix, str(NODE_EXECUTABLE), '--ros-args', *ros_arguments,
            *parameter_arguments(parameters or {})]


def module_command(module: str, *arguments: str, prefix: Sequence[str] = ()) -> List[str]:
    """Return the command that runs ``python -m module arguments`` with this interpreter."""
    return [*prefix, sys.executable, '-m', module, *arguments]


def stop(process: subprocess.Popen, timeout: float = 10.0) -> Optional[int]:
    """Send SIGINT, wait up to ``timeout`` seconds, then kill; return the exit code."""
    if process.poll() is None:
        process.send_signal(signal.SIGINT)
        try:
            process.wait(timeout=timeout)
        except subprocess.TimeoutExpired:
            process.kill()
            process.wait()
    return process.returncode


class ChildProcess:
    """
    A started command, its log (stderr, and stdout unless piped) in a temporary file.

    The log goes to a file, not a pipe: a pipe nobody reads fills and then blocks the child's
    logging (and with it the child). Started from the repository's root, so that ``python -m
    bench.x`` and ``python -m test_support.x`` find their packages. As a context manager it is
    closed (stopped, its log removed) when the block ends.
    """

    def __init__(self, command: Sequence[str], *, environment: Optional[Dict[str, str]] = None,
                 stdout: Optional[int] = None) -> None:
        """Start ``command``; ``stdout=subprocess.PIPE`` gives its stdout to the caller."""
        self.command = list(command)
        self.log_file = tempfile.NamedTemporaryFile(prefix='mouse_constraint_', suffix='.log')
        self.process = subprocess.Popen(
            self.command, cwd=ROOT, env=environment, text=True,
            stdout=self.log_file if stdout is None else stdout,
            stderr=subprocess.STDOUT if stdout is None else self.log_file)

    @property
    def pid(self) -> int:
        """Return the child's process id."""
        return self.process.pid

    def alive(self) -> bool:
        """Return whether the child is still running."""
        return self.process.poll() is None

    def log(self) -> str:
        """Return what the child logged so far."""
        return Path(self.log_file.name).read_text(errors='replace')

    def stop(self, timeout: float = 10.0) -> Optional[int]:
        """Send SIGINT, wait, kill if needed; return the exit code."""
        return stop(self.process, timeout)

    def close(self) -> None:
        """Stop the child and remove its log."""
        self.stop()
        if self.process.stdout is not None:
            self.process.stdout.close()
        self.log_file.close()

    def __enter__(self) -> 'ChildProcess':
        return self

    def __exit__(self, *_exception) -> None:
        self.close()


def finish(node: ChildProcess, *helpers: Optional[ChildProcess]) -> Tuple[Optional[int], str]:
    """
    Stop the ``helpers`` still running, then ``node``; return the node's exit code and log.

    Every process is closed (its log removed) afterwards; a helper of None (not started) is
    passed over.
    """
    for helper in helpers:
        if helper is not None:
            helper.close()
    exit_code = node.stop()
    log = node.log()
    node.close()
    return exit_code, log


def cpu_seconds(pid: int) -> float:
    """Return the user + system CPU time (all threads) that process ``pid`` has used (s)."""
    stat = Path(f'/proc/{pid}/stat').read_text()
    fields = stat[stat.rindex(')') + 2:].split()
    return (int(fields[11]) + int(fields[12])) / CLOCK_TICKS  # Fields 14, 15 of proc(5) stat.


def rss_bytes(pid: int) -> int:
    """Return the resident set size of process ``pid`` (bytes)."""
    fields = Path(f'/proc/{pid}/statm').read_text().split()
    return int(fields[1]) * PAGE_SIZE


def run_delay_ns(pid: int) -> int:
    """Return how long the main thread of ``pid`` has waited for a CPU while runnable (ns)."""
    return int(Path(f'/proc/{pid}/schedstat').read_text().split()[1])
