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
A URDF mesh body on the floor at 1 kHz: the node's cost per tick against the rclpy floor.

The body is a closed convex mesh of ``VERTICES`` hull vertices (``test_support.meshes``'
``ellipsoid_hull``: Fibonacci points on an ellipsoid, every one a vertex), weighed at a density,
given to the node as ``robot_description`` and resting on the floor, where the contact test
reads every hull vertex each substep. Three processes alternate, ``ROUNDS`` windows each,
watched by ``bench.observer rate`` as in ``bench.node_rate`` (pose and twist read from another
process):

- the mesh on the floor (``mouse_constraint_node``, floor on, the mesh put down on it);
- the box on the floor (the node's default body, resting on four corners), for context;
- the rclpy floor (``bench.bare_timer --executor events --twist``): a timer that only stamps
  and publishes a pose and a twist per tick.

Figures: the median CPU per tick of each (CPU over the window / poses received), the ratio
mesh / rclpy floor (target <= ``TARGET_RATIO``), and the node's RSS at each window's start and
end (memory flat: it grows by at most ``MAX_GROWTH_MIB`` over a window). Standalone:
``python -m bench.node_hull [--quick]`` prints the section as JSON.
"""

from pathlib import Path
import sys
import tempfile
import time

from bench import node_rate, ros_process

from mouse_constraint_ros.cli.urdf_params import params_text
from test_support.meshes import ellipsoid_hull, geometry, urdf, write

RATE = 1000.0
VERTICES = 500
AXES = (0.1, 0.07, 0.05)
DENSITY = 1000.0
ROUNDS = 3
SECONDS = 10.0
QUICK_SECONDS = 2.0
TARGET_RATIO = 1.2
MAX_GROWTH_MIB = 1.0
FLOOR_CASE = 'rclpy floor: bench.bare_timer --twist'


def cases(folder: Path) -> list:
    """Return (name, command) of the three processes, the mesh written into ``folder``."""
    mesh = write(ellipsoid_hull(VERTICES, AXES), folder / 'hull.stl')
    params = folder / 'hull.yaml'
    params.write_text(params_text(urdf([geometry('mesh', filename=str(mesh))], link='hull')))
    resting = {'rate_hz': RATE, 'floor': True, 'hold_initial_anchor': False,
               'density': DENSITY}
    return [
        (f'mesh of {VERTICES} hull vertices on the floor', ros_process.node_command(
            dict(resting, initial_position=[0.0, 0.0, AXES[2] + 0.001])) + [
                '--params-file', str(params)]),
        ('box on the floor', ros_process.node_command(
            {'rate_hz': RATE, 'floor': True, 'hold_initial_anchor': False,
             'initial_position': [0.0, 0.0, 0.05]})),
        (FLOOR_CASE, ros_process.bench_command('bare_timer', '--rate', repr(RATE),
                                               *node_rate.FLOOR)),
    ]


def run(quick: bool = False) -> dict:
    """Return the section: the mesh node, the box node and the rclpy floor, alternating."""
    start = time.perf_counter()
    seconds = QUICK_SECONDS if quick else SECONDS
    with tempfile.TemporaryDirectory() as folder:
        processes = cases(Path(folder))
        rows, medians = node_rate.alternating(
            processes, RATE, 1 if quick else ROUNDS, seconds, floor_case=FLOOR_CASE)
    (mesh_name, _), (box_name, _), _ = processes
    ratio = medians[mesh_name] / medians[FLOOR_CASE]
    growth = max(row['rss_growth_mib'] for row in rows if row['case'] != FLOOR_CASE)
    notes = [
        f'Median CPU per tick: mesh {medians[mesh_name]:.0f} us, box {medians[box_name]:.0f} '
        f'us, rclpy floor {medians[FLOOR_CASE]:.0f} us. Mesh / rclpy floor {ratio:.2f} (target '
        f'<= {TARGET_RATIO:g}: ' + ('met' if ratio <= TARGET_RATIO else 'not met') + '); mesh '
        f'/ box {medians[mesh_name] / medians[box_name]:.2f}.',
        f'Largest RSS growth of a node over a window: {growth:.2f} MiB (flat: <= '
        f'{MAX_GROWTH_MIB:g} MiB: ' + ('met' if growth <= MAX_GROWTH_MIB else 'not met') + ').',
        'One window per row, the cases alternating; "load" is the 1-minute load average.',
    ]
    return {
        'title': f'A mesh body of {VERTICES} hull vertices on the floor at 1 kHz, against the '
                 'rclpy floor',
        'text': (f'Command: `python -m bench.node_hull`. {seconds:g} s windows after '
                 f'{node_rate.WARMUP:g} s of warm-up, the three processes alternating, pose and '
                 'twist read from another process.'),
        'columns': [['case', 'case', ''], ['cpu_us_per_tick', 'CPU per tick (us)', '.0f'],
                    ['cpu_pct', 'CPU (% core)', '.1f'],
                    ['achieved_hz', 'achieved (Hz)', '.1f'], ['missing', 'missing', 'd'],
                    ['rss_start_mib', 'RSS start (MiB)', '.1f'],
                    ['rss_mib', 'RSS end (MiB)', '.1f'], ['load', 'load', '.1f']],
        'rows': rows,
        'notes': notes,
        'figures': {'cpu_ratio': ratio, 'mesh_cpu_us_per_tick': medians[mesh_name],
                    'box_cpu_us_per_tick': medians[box_name],
                    'floor_cpu_us_per_tick': medians[FLOOR_CASE], 'rss_growth_mib': growth},
        'elapsed_s': time.perf_counter() - start,
    }


if __name__ == '__main__':
    import json
    print(json.dumps(run(quick='--quick' in sys.argv), indent=1, default=str))
