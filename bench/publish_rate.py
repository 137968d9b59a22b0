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
Publishing below the physics rate: 100 Hz pose and twist from a node stepping at 1 kHz.

Only where the node has a ``publish_rate_hz`` parameter (looked up in its PARAMETERS table);
otherwise the section says so and measures nothing. The node runs with ``rate_hz`` 1000 and
``publish_rate_hz`` 100, watched by ``bench.observer rate`` (pose and twist read); the floor is
``bench.bare_timer --executor events --twist`` at 1 kHz, run next to it. Figures: the publish
rate against 100 Hz (within 1 %), and the node's CPU against 0.4 x the 1 kHz floor's: with
nine ticks in ten stepped but not published, the node should cost less than the floor of
publishing every tick.

Standalone: ``python -m bench.publish_rate [--quick]`` prints the section as JSON.
"""

import sys
import time

from bench import node_rate
from bench import ros_process

from mouse_constraint_ros.node.parameters import PARAMETERS

PHYSICS_HZ = 1000.0
PUBLISH_HZ = 100.0
RATE_TOLERANCE = 0.01
CPU_SHARE_OF_FLOOR = 0.4
PARAMETER = 'publish_rate_hz'


def has_parameter() -> bool:
    """Return whether the node declares ``publish_rate_hz``."""
    return any(parameter.name == PARAMETER for parameter in PARAMETERS)


def run(quick: bool = False) -> dict:
    """Return the section: the node publishing at 100 Hz, and the 1 kHz floor."""
    start = time.perf_counter()
    title = f'Publishing at {PUBLISH_HZ:g} Hz from {PHYSICS_HZ:g} Hz physics'
    if not has_parameter():
        return {'title': title,
                'text': f'Skipped: the node has no `{PARAMETER}` parameter (not in PARAMETERS).',
                'rows': [], 'columns': [], 'notes': [],
                'elapsed_s': time.perf_counter() - start}
    seconds = node_rate.QUICK_SECONDS if quick else node_rate.SECONDS
    node = node_rate.measure(ros_process.node_command(
        {'rate_hz': PHYSICS_HZ, PARAMETER: PUBLISH_HZ}), PUBLISH_HZ, seconds)
    node['process'] = f'mouse_constraint_node, {PARAMETER} {PUBLISH_HZ:g}'
    floor = node_rate.measure(ros_process.bench_command(
        'bare_timer', '--rate', repr(PHYSICS_HZ), *node_rate.FLOOR), PHYSICS_HZ, seconds)
    floor['process'] = f'floor: bench.bare_timer --twist at {PHYSICS_HZ:g} Hz'
    floor['missing'] = floor['grid_error_ns'] = None
    ratio = node['cpu_pct'] / floor['cpu_pct']
    node['cpu_ratio'], floor['cpu_ratio'] = ratio, 1.0
    held = abs(node['rate_error_pct']) <= 100.0 * RATE_TOLERANCE
    notes = [
        f'Publish rate {node["achieved_hz"]:.2f} Hz ({node["rate_error_pct"]:+.2f} %): '
        + ('within' if held else 'outside') + f' {100 * RATE_TOLERANCE:g} %. Node CPU / 1 kHz '
        f'floor {ratio:.2f} against {CPU_SHARE_OF_FLOOR:g}: '
        + ('below.' if ratio <= CPU_SHARE_OF_FLOOR else 'above.'),
    ]
    return {
        'title': title,
        'text': 'Command: `python -m bench.publish_rate`. Ratios first: node CPU / floor CPU.',
        'columns': [['process', 'process', ''], ['cpu_ratio', 'CPU / floor', '.2f'],
                    ['rate_hz', 'published rate asked (Hz)', '.0f'],
                    ['achieved_hz', 'achieved (Hz)', '.2f'],
                    ['rate_error_pct', 'rate error (%)', '+.3f'], ['missing', 'missing', 'd'],
                    ['cpu_pct', 'CPU (% core)', '.1f'], ['load', 'load', '.1f']],
        'rows': [node, floor],
        'notes': notes,
        'figures': {'publish_rate_error_pct': node['rate_error_pct'], 'cpu_ratio': ratio},
        'elapsed_s': time.perf_counter() - start,
    }


if __name__ == '__main__':
    import json
    print(json.dumps(run(quick='--quick' in sys.argv), indent=1, default=str))
