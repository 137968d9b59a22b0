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
The flood measurement of the hardening tests and ``bench/flood.py``: ``run_flood``.

A node process, a flooder process (``test_support.hardening_tools flood``) publishing targets
round a circle, and the observer in the test process recording pose and twist; what the node
kept up with, what it cost and how far behind the targets it ran.
"""

import json
import math
import subprocess
import time
from typing import Dict, Optional, Sequence

import numpy as np

from test_support.hardening_tools import CENTER
from test_support.hardening_tools import flood_command
from test_support.hardening_tools import NodeProcess
from test_support.hardening_tools import NS
from test_support.hardening_tools import PERIOD
from test_support.hardening_tools import PoseRecorder
from test_support.processes import ChildProcess
from test_support.processes import cpu_seconds
from test_support.processes import finish
from test_support.processes import rss_bytes
from test_support.processes import run_delay_ns


def run_flood(ros, seconds: float, rate: float = 20000.0, hostile_every: int = 0,
              node_rate: float = 1000.0, messages: bool = False,
              node_prefix: Sequence[str] = (),
              node_environment: Optional[Dict[str, str]] = None) -> dict:
    """
    Flood a node process with targets from a flooder process; return what was measured.

    ``ros`` is a ``RosHarness`` (the observer, subscribed to pose and twist). The node runs at
    ``node_rate`` without gravity, with some damping, and workspace_radius 100 m; the flooder
    publishes ``rate`` targets/s (0: as fast as it can), pre-serialized or, with ``messages``,
    as message objects. The result: the flooder's summary (``flood``); the node's output rate
    over the flood counted by grid stamp and by DDS source timestamp (when the node wrote the
    message), the ticks missing from the stamps, and how late the node wrote them
    (``late_ms_*``: source timestamp - stamp, which the observer's own delays do not enter);
    its RSS (after start, after the first second of the flood, at the end), CPU share and how
    long its main thread waited for a CPU (``node_run_delay_ms``, over the flood: a machine too
    busy to run it); how far behind the targets the anchor runs (``lag_s``: per flood second,
    the median lag of the anchor's angle on the circle behind the target's phase at the pose
    stamp) and how far it is from the last target after it; after the flood, when the last
    missing tick was due (``recovered_s``, from the flood's end; 0 when none was missing) and
    whether the node warned of the ticks it dropped (``drops_warned``).

    ``node_prefix`` runs the node under a command (``NodeProcess``), ``node_environment`` is its
    environment (None: this one's); ``bench.flood_rate`` runs another tree's node so.
    """
    from geometry_msgs.msg import TwistStamped
    node = NodeProcess('-p', f'rate_hz:={node_rate!r}', '-p', 'gravity:=[0.0, 0.0, 0.0]',
                       '-p', 'linear_damping:=2.0', '-p', 'angular_damping:=2.0',
                       '-p', 'workspace_radius:=100.0', prefix=node_prefix,
                       environment=node_environment)
    flooder = None
    try:
        poses = PoseRecorder(ros.probe)
        twists = ros.collect(TwistStamped, 'twist', depth=100000)
        if not ros.spin_until(lambda: len(poses) > 200 and twists, timeout=20.0):
            raise RuntimeError('no pose and twist from the node:\n' + node.log())
        ros.spin_for(0.5)
        rss_start = rss_bytes(node.pid)
        delay_start = run_delay_ns(node.pid)
        flooder = ChildProcess(
            flood_command('--rate', repr(rate), '--duration', repr(seconds),
                          '--hostile-every', str(hostile_every),
                          *(['--messages'] if messages else [])),
            stdout=subprocess.PIPE)
        samples = []  # (time ns, node rss, node cpu s, flooder cpu s, observer cpu s)

        def sample() -> None:
            try:
                flooder_cpu = cpu_seconds(flooder.pid)
            except (OSError, IndexError):  # It has just exited.
                flooder_cpu = samples[-1][3] if samples else 0.0
            samples.append((time.time_ns(), rss_bytes(node.pid), cpu_seconds(node.pid),
                            flooder_cpu, time.process_time()))

        next_sample = 0.0
        while flooder.alive():
            ros.spin_for(0.05)
            if time.monotonic() >= next_sample:
                sample()
                next_sample = time.monotonic() + 0.25
        sample()
        delay_end = run_delay_ns(node.pid)
        stdout, _ = flooder.process.communicate()
        lines = [line for line in stdout.splitlines() if line.startswith('{')]
        if flooder.process.returncode != 0 or not lines:
            raise RuntimeError(f'flooder failed ({flooder.process.returncode}): {stdout}\n'
                               + flooder.log())
        flood = json.loads(lines[-1])
        # Serving on after the flood: a second of ticks (by stamp, so that neither a late node
        # nor a late observer cuts it short), long enough for the anchor to settle.
        ros.spin_until(lambda: poses.stamps[-1] >= flood['end_ns'] + NS, timeout=10.0)
        alive = node.alive()
    finally:
        exit_code, log = finish(node, flooder)
    start_ns, end_ns = flood['start_ns'], flood['end_ns']
    stamps = np.array(poses.stamps, dtype=np.int64)
    published = np.array(poses.published, dtype=np.int64)
    received = np.array(poses.received, dtype=np.int64)
    span = (end_ns - start_ns) / NS
    in_flood = (stamps >= start_ns) & (stamps < end_ns)
    written = (published >= start_ns) & (published < end_ns)
    # Lag of the anchor behind the target: the anchor's angle on the circle against the
    # target's phase at the pose's stamp.
    anchors = poses.anchors()
    angle = np.arctan2(anchors[:, 1] - CENTER[1], anchors[:, 0] - CENTER[0])
    phase = 2.0 * np.pi * ((stamps % int(PERIOD * NS)) / (PERIOD * NS))
    lag = np.angle(np.exp(1j * (phase - angle))) / (2.0 * np.pi / PERIOD)
    lag_per_second = []
    for k in range(int(span)):
        window = (stamps >= start_ns + k * NS) & (stamps < start_ns + (k + 1) * NS)
        lag_per_second.append(float(np.median(lag[window])) if window.any() else math.nan)
    flood_samples = [s for s in samples if s[0] >= start_ns + NS]

    def cpu_share(column: int) -> float:
        return ((samples[-1][column] - samples[0][column])
                / ((samples[-1][0] - samples[0][0]) / NS))

    last_valid = np.array(flood['last_valid'])
    final_error = float(np.linalg.norm(anchors[-1] - last_valid))
    gaps = np.diff(stamps[in_flood])
    period_ns = NS / node_rate
    # After the flood: the stamp that ends the last gap of more than one tick.
    after = stamps[stamps >= end_ns - period_ns]
    late_gaps = np.flatnonzero(np.diff(after) > 1.5 * period_ns)
    recovered = (after[late_gaps[-1] + 1] - end_ns) / NS if len(late_gaps) else 0.0
    missing = int(np.sum(np.round(gaps / period_ns) - 1)) if len(gaps) else 0
    return {
        'flood': flood,
        'node_rate_hz': node_rate,
        'flood_seconds': span,
        'stamp_rate_hz': int(in_flood.sum()) / span,
        'publish_rate_hz': int(written.sum()) / span,
        'twists': len(twists),
        'missing_ticks': missing,
        'late_ms_p99': float(np.percentile((published - stamps)[in_flood], 99) / 1e6),
        'late_ms_max': float(np.max((published - stamps)[in_flood]) / 1e6),
        'observer_late_ms_p99': float(np.percentile((received - published)[in_flood], 99)
                                      / 1e6),
        'rss_start_mb': rss_start / 2 ** 20,
        'rss_flood_1s_mb': flood_samples[0][1] / 2 ** 20 if flood_samples else math.nan,
        'rss_end_mb': samples[-1][1] / 2 ** 20,
        'rss_max_mb': max(s[1] for s in samples) / 2 ** 20,
        'node_run_delay_ms': (delay_end - delay_start) / 1e6,
        'node_cpu_share': cpu_share(2),
        'flooder_cpu_share': cpu_share(3),
        'observer_cpu_share': cpu_share(4),
        'lag_s': lag_per_second,
        'final_error_m': final_error,
        'all_finite': bool(np.isfinite(np.array(poses.positions)).all()
                           and np.isfinite(np.array(poses.orientations)).all()),
        'served_after_flood_s': (poses.stamps[-1] - end_ns) / NS,
        'recovered_s': float(recovered),
        'drops_warned': 'dropped' in log,
        'node_alive': alive,
        'node_exit_code': exit_code,
        'node_log_tail': log[-2000:],
    }
