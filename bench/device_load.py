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
A device at 1 kHz on a machine kept busy: every pose it sent served, or counted lost.

The device-clocked node (``tick_source: target_pose``, config/haptic.yaml) against the device's
process of ``bench.device_stream``, while ``HOGS_PER_CORE`` processes per core spin on the CPU
(a build or a test suite sharing the machine; the 1-minute load average they bring is in the
row). A pose the node serves runs its own tick; a pose the node never sees is one it must
count: the node reads the gaps in the device's stamps at the device's rate and reports them on
/diagnostics, which the device's process reads at the end. The figure: served / sent, and the
poses neither served nor counted (target 0, the first and last pose of a round aside: a gap
is seen only between two poses that came).

Standalone: ``python -m bench.device_load [--quick]`` prints the section as JSON.
"""

from functools import partial
import multiprocessing
import os
import time

from bench import ros_process
from bench.device_stream import measure
from bench.force_latency import device_ticks, preset

from test_support.loaded_runs import spin

HOGS_PER_CORE = 2
TRIALS = 8000
QUICK_TRIALS = 1000
ROUNDS = 2
QUICK_ROUNDS = 1
# Seconds the hogs spin before the first round, so that the 1-minute load average has risen
# to some 4 (1 - e^-2 of the five processes' 4.5 on two cores).
WARMUP = 120.0
QUICK_WARMUP = 5.0


def run(quick: bool = False) -> dict:
    """Return the section: the device-clocked node's poses served and lost, the machine busy."""
    start = time.perf_counter()
    trials = (QUICK_TRIALS if quick else TRIALS) // (QUICK_ROUNDS if quick else ROUNDS)
    rounds = QUICK_ROUNDS if quick else ROUNDS
    parameters = {**preset(), 'tick_source': 'target_pose'}
    command = ros_process.node_command(parameters)
    hogs = [multiprocessing.Process(target=spin, daemon=True)
            for _ in range(HOGS_PER_CORE * (os.cpu_count() or 1))]
    for hog in hogs:
        hog.start()
    rows = []
    try:
        time.sleep(QUICK_WARMUP if quick else WARMUP)
        for round_ in range(rounds):
            result = measure(command, partial(device_ticks, parameters=parameters), trials,
                             parameters, nominal=True)
            sent, served, lost = result['published'], result['served'], result['lost']
            rows.append({'round': round_ + 1, 'sent': sent, 'served': served, 'lost': lost,
                         'neither': sent - served - lost, 'served_pct': 100.0 * served / sent,
                         'hogs': len(hogs), 'load': result['load']})
    finally:
        for hog in hogs:
            hog.kill()
    sent = sum(row['sent'] for row in rows)
    served = sum(row['served'] for row in rows)
    neither = sum(row['neither'] for row in rows)
    edges = 2 * len(rows)
    notes = [f'{served} of {sent} poses served ({100.0 * served / sent:.2f} %), '
             f'{sum(row["lost"] for row in rows)} counted lost by the node, {neither} neither; '
             f'target: each pose served or counted, the first and last of a round aside '
             f'(at most {edges}): ' + ('met' if 0 <= neither <= edges else 'not met') + '.',
             f'{len(hogs)} processes spinning on {os.cpu_count()} cores; load is the 1-minute '
             'load average at the end of the round.']
    return {
        'title': 'A device at 1 kHz on a busy machine: poses served, or counted lost',
        'text': (f'Command: `python -m bench.device_load`. config/haptic.yaml, tick_source '
                 f'target_pose, {trials} poses a round one every tick, {HOGS_PER_CORE} '
                 'processes per core spinning meanwhile.'),
        'columns': [['round', 'round', 'd'], ['sent', 'sent', 'd'], ['served', 'served', 'd'],
                    ['lost', 'counted lost', 'd'], ['neither', 'neither', 'd'],
                    ['served_pct', 'served (%)', '.2f'], ['hogs', 'busy processes', 'd'],
                    ['load', 'load', '.1f']],
        'rows': rows,
        'notes': notes,
        'figures': {'served_per_sent': served / sent, 'neither': neither,
                    'load': max(row['load'] for row in rows)},
        'elapsed_s': time.perf_counter() - start,
    }


if __name__ == '__main__':
    import json
    import sys
    print(json.dumps(run(quick='--quick' in sys.argv), indent=1))
