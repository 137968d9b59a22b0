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
Whole robots at 1 kHz: the node's cost per tick against the rclpy floor, joint_states read.

Two robots of the public robot-description collection (example-robot-data), as shipped: a UR5
(6 joints) and a Panda (9 joints: 7 and a mimic pair of fingers), each fixed at its base and
falling under gravity from its zero configuration onto its stops, so that the stops' rows (and
the Panda's mimic row) are solved every substep. Three
processes alternate, ``ROUNDS`` windows each, watched by ``bench.observer rate`` (pose
recorded; twist and joint_states read):

- the UR5 node and the Panda node (``mouse_constraint_node``, ``robot_description`` from the
  collection, its meshes through the ament index);
- the rclpy floor (``bench.bare_timer --executor events --twist``).

Figures: the median CPU per tick of each, the ratio robot / rclpy floor (target <=
``TARGET_RATIO``), and each node's RSS at its windows' start and end (flat: growth <=
``MAX_GROWTH_MIB``). Standalone: ``python -m bench.node_robot [--quick]``.
"""

import os
from pathlib import Path
import sys
import tempfile
import time

from bench import node_rate, ros_process

from mouse_constraint_ros.cli.urdf_params import params_text
from test_support.robots import collection_urdf, robot_collection

RATE = 1000.0
ROBOTS = (('UR5, 6 joints', 'ur_description/urdf/ur5_robot.urdf'),
          ('Panda, 9 joints', 'panda_description/urdf/panda.urdf'))
ROUNDS = 3
SECONDS = 10.0
QUICK_SECONDS = 2.0
TARGET_RATIO = 1.5
MAX_GROWTH_MIB = 1.0
FLOOR_CASE = 'rclpy floor: bench.bare_timer --twist'
OBSERVED = ('--also', 'twist', 'joint_states')


def cases(folder: Path) -> list:
    """Return (name, command) of the three processes, the robots' parameters in ``folder``."""
    rows = []
    for name, relative in ROBOTS:
        params = folder / (Path(relative).stem + '.yaml')
        params.write_text(params_text(collection_urdf(relative).read_text()))
        rows.append((name, ros_process.node_command(
            {'rate_hz': RATE, 'substeps': 1}) + ['--params-file', str(params)]))
    rows.append((FLOOR_CASE, ros_process.bench_command('bare_timer', '--rate', repr(RATE),
                                                       *node_rate.FLOOR)))
    return rows


def run(quick: bool = False) -> dict:
    """Return the section: the two robot nodes and the rclpy floor, alternating."""
    start = time.perf_counter()
    seconds = QUICK_SECONDS if quick else SECONDS
    prefix = str(robot_collection())
    os.environ['AMENT_PREFIX_PATH'] = prefix + (
        os.pathsep + os.environ['AMENT_PREFIX_PATH'] if os.environ.get('AMENT_PREFIX_PATH')
        else '')
    with tempfile.TemporaryDirectory() as folder:
        processes = cases(Path(folder))
        rows, medians = node_rate.alternating(
            processes, RATE, 1 if quick else ROUNDS, seconds, floor_case=FLOOR_CASE,
            first_timeout=30.0, observer_arguments=OBSERVED)
    floor = medians[FLOOR_CASE]
    ratios = {name: medians[name] / floor for name, _ in ROBOTS}
    growth = max(row['rss_growth_mib'] for row in rows if row['case'] != FLOOR_CASE)
    notes = [
        'Median CPU per tick: ' + ', '.join(
            f'{name} {medians[name]:.0f} us ({ratios[name]:.2f} x the floor)'
            for name, _ in ROBOTS) + f', rclpy floor {floor:.0f} us; target <= '
        f'{TARGET_RATIO:g} x: ' + ('met' if max(ratios.values()) <= TARGET_RATIO
                                   else 'not met') + '.',
        f'Largest RSS growth of a node over a window: {growth:.2f} MiB (flat: <= '
        f'{MAX_GROWTH_MIB:g} MiB: ' + ('met' if growth <= MAX_GROWTH_MIB else 'not met') + ').',
        'One window per row, the cases alternating; "load" is the 1-minute load average.',
    ]
    return {
        'title': 'Whole robots (a UR5, a Panda) at 1 kHz, joint_states read, against the rclpy '
                 'floor',
        'text': (f'Command: `python -m bench.node_robot`. {seconds:g} s windows after '
                 f'{node_rate.WARMUP:g} s of warm-up, the three processes alternating; pose '
                 'recorded, twist and joint_states read from another process.'),
        'columns': [['case', 'case', ''], ['cpu_us_per_tick', 'CPU per tick (us)', '.0f'],
                    ['cpu_pct', 'CPU (% core)', '.1f'],
                    ['achieved_hz', 'achieved (Hz)', '.1f'], ['missing', 'missing', 'd'],
                    ['rss_start_mib', 'RSS start (MiB)', '.1f'],
                    ['rss_mib', 'RSS end (MiB)', '.1f'], ['load', 'load', '.1f']],
        'rows': rows,
        'notes': notes,
        'figures': {'ur5_ratio': ratios[ROBOTS[0][0]], 'panda_ratio': ratios[ROBOTS[1][0]],
                    'floor_cpu_us_per_tick': floor, 'rss_growth_mib': growth},
        'elapsed_s': time.perf_counter() - start,
    }


if __name__ == '__main__':
    import json
    print(json.dumps(run(quick='--quick' in sys.argv), indent=1, default=str))
