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
The node's cost with the floor: at 1 kHz, the box resting on the floor against no floor.

Both processes are ``mouse_constraint_node`` with its defaults but these parameters, watched by
``bench.observer rate`` as in ``bench.node_rate`` (pose and twist read from another process,
CPU of the node over a window after warm-up):

- floor: ``floor: true`` at z = 0, the box put on it (``initial_position`` [0, 0, 0.05],
  ``hold_initial_anchor: false``), resting on four contacts for the whole window;
- no floor: the node's defaults, the box hanging from its held corner (the scene of
  ``bench.node_rate``).

The two alternate, ``ROUNDS`` windows each, so that a busy spell of the machine hits both; the
ratio is that of the median CPU time per tick stepped (CPU over the window / ticks received),
which a starved window that drops ticks does not bias. Target: floor / no floor <= 1.3. Standalone:
``python -m bench.node_floor [--quick]`` prints the section as JSON.
"""

import statistics
import sys
import time

from bench import node_rate, ros_process

RATE = 1000.0
ROUNDS = 3
SECONDS = 10.0
QUICK_SECONDS = 2.0
TARGET_RATIO = 1.3
CASES = (
    ('floor, box resting on it', {'rate_hz': RATE, 'floor': True,
                                  'initial_position': [0.0, 0.0, 0.05],
                                  'hold_initial_anchor': False}),
    ('no floor, box hanging from its corner', {'rate_hz': RATE}),
)


def run(quick: bool = False) -> dict:
    """Return the section: CPU of the node with and without the floor, alternating."""
    start = time.perf_counter()
    seconds = QUICK_SECONDS if quick else SECONDS
    samples = {name: [] for name, _ in CASES}
    rows = []
    for _ in range(1 if quick else ROUNDS):
        for name, parameters in CASES:
            row = node_rate.measure(ros_process.node_command(parameters), RATE, seconds)
            row['case'] = name
            row['cpu_us_per_tick'] = 1e4 * row['cpu_pct'] / row['achieved_hz']
            samples[name].append(row['cpu_us_per_tick'])
            rows.append(row)
            print(f'  {name}: CPU {row["cpu_pct"]:.1f} %, {row["achieved_hz"]:.1f} Hz, '
                  f'{row.get("missing")} missing', file=sys.stderr, flush=True)
    (floor_name, _), (bare_name, _) = CASES
    floor_cpu = statistics.median(samples[floor_name])
    bare_cpu = statistics.median(samples[bare_name])
    ratio = floor_cpu / bare_cpu
    notes = [
        f'Median CPU per tick with the floor {floor_cpu:.0f} us, without {bare_cpu:.0f} us: '
        f'ratio {ratio:.2f} (target <= {TARGET_RATIO:g}: '
        + ('met' if ratio <= TARGET_RATIO else 'not met') + ').',
        'One window per row, the cases alternating; "load" is the 1-minute load average.',
    ]
    return {
        'title': 'The node at 1 kHz with the box resting on the floor, against no floor',
        'text': (f'Command: `python -m bench.node_floor`. {seconds:g} s windows after '
                 f'{node_rate.WARMUP:g} s of warm-up, the two cases alternating, pose and '
                 'twist read from another process.'),
        'columns': [['case', 'case', ''], ['cpu_us_per_tick', 'CPU per tick (us)', '.0f'],
                    ['cpu_pct', 'CPU (% core)', '.1f'],
                    ['achieved_hz', 'achieved (Hz)', '.1f'], ['missing', 'missing', 'd'],
                    ['delay_p50_us', 'delay p50 (us)', '.0f'], ['load', 'load', '.1f']],
        'rows': rows,
        'notes': notes,
        'figures': {'cpu_ratio': ratio, 'floor_cpu_us_per_tick': floor_cpu,
                    'bare_cpu_us_per_tick': bare_cpu},
        'elapsed_s': time.perf_counter() - start,
    }


if __name__ == '__main__':
    import json
    print(json.dumps(run(quick='--quick' in sys.argv), indent=1, default=str))
