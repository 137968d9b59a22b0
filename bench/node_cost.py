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
The node's CPU against the rclpy floor, as medians of alternating windows in one run.

Each case is a process watched by ``bench.observer rate``, which reads every topic the process
publishes (a publisher with no reader sends nothing), over a window after warm-up; its CPU is
utime + stime of all its threads over the window (``bench.node_rate.measure``):

- the floor: ``bench.bare_timer --executor events --twist`` at 1 kHz, a bare rclpy node: an
  rclpy timer under the node's executor and spin loop that only stamps and publishes a
  PoseStamped and a TwistStamped per tick;
- the node at 1 kHz publishing every tick (its defaults but ``rate_hz``: the box hanging from
  its held corner under gravity, markers and diagnostics on);
- the node at 1 kHz physics publishing at 100 Hz (``publish_rate_hz: 100.0``);
- the floor of three messages: the same timer publishing a WrenchStamped on ``force`` too
  (``--wrench``), and the node with the felt force on (``publish_force: true``), pose, twist
  and force read;
- beside them, with no target, the two halves of the executable's choice to run its ticks from
  its own spin loop: the node at 1 kHz with its ticks on an rclpy timer (``bench.timer_node``),
  and the floor with its ticks from its spin loop as the node's (``--executor events-loop``):
  the first says what the choice saves the node, the second what it saves a bare publisher.

The cases run one after the other, round after round, so that a busy spell of the machine hits
each. A ratio is the median CPU per tick of a case over the floor's: CPU per second over the
ticks the window held (poses received, times the ticks per pose of a node that publishes every
tenth tick). Per tick, because on a loaded machine the floor's rclpy timer skips periods it
was late for, while the node runs every tick of its grid: per second of CPU the node would be
charged for the ticks the floor left out. The ratio of CPU per second is reported beside it.
Targets: the node at 1 kHz <= 1.0 x the floor; publishing at 100 Hz <= 0.4 x the 1 kHz floor;
the node with the force <= 1.0 x the floor of three messages. Standalone:
``python -m bench.node_cost [--quick] [--rounds N] [--seconds S]`` prints the section as JSON.
"""

import argparse
import statistics
import sys
import time
from typing import Dict, List, Sequence, Tuple

from bench import node_rate, ros_process

RATE = 1000.0
PUBLISH_HZ = 100.0
ROUNDS = 5
SECONDS = 6.0
QUICK_ROUNDS = 2
QUICK_SECONDS = 2.0
FLOOR = 'floor'
FLOOR_3 = 'floor, three messages'
NODE_FORCE = 'node, every tick, force on'
# Beside them, no target: the node with its ticks on an rclpy timer (``bench.timer_node``), and
# the floor with its ticks from its spin loop, as the node's come.
NODE_TIMER = 'node, every tick, ticks on an rclpy timer'
FLOOR_LOOP = 'floor, ticks from its spin loop'
# Each case's floor, and the most CPU per tick it may take of it.
TARGETS = {'node, every tick': (FLOOR, 1.0),
           f'node, publishing at {PUBLISH_HZ:g} Hz': (FLOOR, 0.4),
           NODE_FORCE: (FLOOR_3, 1.0)}
# What the observer reads besides the pose.
TWO = ('--also', 'twist')
THREE = ('--also', 'twist', 'force')


def cases() -> List[Tuple[str, Sequence[str], float, Sequence[str]]]:
    """Return (name, command, rate its poses come at, observer arguments) of each case."""
    floor = ros_process.bench_command('bare_timer', '--rate', repr(RATE), *node_rate.FLOOR)
    return [
        (FLOOR, floor, RATE, TWO),
        ('node, every tick', ros_process.node_command({'rate_hz': RATE}), RATE, TWO),
        (f'node, publishing at {PUBLISH_HZ:g} Hz',
         ros_process.node_command({'rate_hz': RATE, 'publish_rate_hz': PUBLISH_HZ}),
         PUBLISH_HZ, TWO),
        (FLOOR_3, [*floor, '--wrench'], RATE, THREE),
        (NODE_FORCE, ros_process.node_command({'rate_hz': RATE, 'publish_force': True}), RATE,
         THREE),
        (NODE_TIMER, ros_process.timer_node_command({'rate_hz': RATE}), RATE, TWO),
        (FLOOR_LOOP, ros_process.bench_command('bare_timer', '--rate', repr(RATE), '--executor',
                                               'events-loop', '--twist'), RATE, TWO),
    ]


def cpu_per_tick(row: dict, rate: float) -> float:
    """Return the CPU (us) per physics tick of a window: per pose, over the ticks per pose."""
    return 1e4 * row['cpu_pct'] / (row['achieved_hz'] * RATE / rate)


def threads_per_tick(row: dict, rate: float) -> Dict[str, float]:
    """Return the CPU (us) per physics tick of each kind of thread (``ros_process``)."""
    ticks = row['achieved_hz'] * row['window_s'] * RATE / rate
    return {kind: 1e6 * seconds / ticks for kind, seconds in row['threads_cpu_s'].items()}


def run(quick: bool = False, rounds: int = 0, seconds: float = 0.0) -> dict:
    """Return the section: each case's CPU over alternating windows, and the ratios."""
    start = time.perf_counter()
    rounds = rounds or (QUICK_ROUNDS if quick else ROUNDS)
    seconds = seconds or (QUICK_SECONDS if quick else SECONDS)
    per_tick: Dict[str, List[float]] = {}
    per_second: Dict[str, List[float]] = {}
    per_thread: Dict[str, Dict[str, List[float]]] = {}
    rows = []
    for round_ in range(rounds):
        for name, command, rate, reads in cases():
            row = node_rate.measure(command, rate, seconds, observer_arguments=reads)
            row['case'], row['round'] = name, round_ + 1
            row['cpu_us_per_tick'] = cpu_per_tick(row, rate)
            for kind, us in threads_per_tick(row, rate).items():
                row[f'{kind}_us_per_tick'] = us
                per_thread.setdefault(name, {}).setdefault(kind, []).append(us)
            per_tick.setdefault(name, []).append(row['cpu_us_per_tick'])
            per_second.setdefault(name, []).append(row['cpu_pct'])
            rows.append(row)
            print(f'  {round_ + 1}/{rounds} {name}: CPU {row["cpu_pct"]:.1f} %, '
                  f'{row["cpu_us_per_tick"]:.0f} us a tick, {row["achieved_hz"]:.1f} Hz, '
                  f'load {row["load"]:.1f}', file=sys.stderr, flush=True)
    tick = {name: statistics.median(values) for name, values in per_tick.items()}
    second = {name: statistics.median(values) for name, values in per_second.items()}
    ratios = {name: tick[name] / tick[floor] for name, (floor, _) in TARGETS.items()}
    ratios[NODE_TIMER] = tick[NODE_TIMER] / tick[FLOOR]
    ratios[FLOOR_LOOP] = tick[FLOOR_LOOP] / tick[FLOOR]
    ratios['node, every tick / ' + FLOOR_LOOP] = tick['node, every tick'] / tick[FLOOR_LOOP]
    notes = [f'{floor}: median {tick[floor]:.0f} us a tick, {second[floor]:.1f} % of a core, '
             f'over {rounds} windows.' for floor in (FLOOR, FLOOR_3)]
    for name, kinds in per_thread.items():
        notes.append(f'{name}, per tick by thread (medians): ' + ', '.join(
            f'{kind} {statistics.median(values):.0f} us' for kind, values in kinds.items()))
    for name, (floor, target) in TARGETS.items():
        ratio = ratios[name]
        notes.append(f'{name}: median {tick[name]:.0f} us a tick, {ratio:.2f} x the {floor} '
                     f'(target <= {target:g}: ' + ('met' if ratio <= target else 'not met')
                     + f'); {second[name]:.1f} % of a core, {second[name] / second[floor]:.2f} '
                     'x per second.')
    notes.append(f'{NODE_TIMER} (bench.timer_node): median {tick[NODE_TIMER]:.0f} us a tick, '
                 f'{ratios[NODE_TIMER]:.2f} x the {FLOOR}.')
    notes.append(f'{FLOOR_LOOP}: median {tick[FLOOR_LOOP]:.0f} us a tick, '
                 f'{ratios[FLOOR_LOOP]:.2f} x the {FLOOR}; the node every tick is '
                 f'{tick["node, every tick"] / tick[FLOOR_LOOP]:.2f} x it.')
    return {
        'title': 'The node against the rclpy floor, alternating windows',
        'text': (f'Command: `python -m bench.node_cost`. {rounds} rounds of {seconds:g} s '
                 f'windows after {node_rate.WARMUP:g} s of warm-up, the cases alternating; every '
                 'topic read from another process. Ratios: median CPU per tick, node / floor.'),
        'columns': [['round', 'round', 'd'], ['case', 'case', ''],
                    ['cpu_us_per_tick', 'CPU per tick (us)', '.0f'],
                    ['main_us_per_tick', 'main thread (us)', '.0f'],
                    ['other_us_per_tick', 'rclpy timers thread (us)', '.0f'],
                    ['dds_us_per_tick', 'DDS threads (us)', '.0f'],
                    ['cpu_pct', 'CPU (% core)', '.1f'], ['achieved_hz', 'poses (Hz)', '.1f'],
                    ['missing', 'missing', 'd'], ['wait_ms_per_s', 'wait (ms/s)', '.0f'],
                    ['load', 'load', '.1f']],
        'rows': rows,
        'notes': notes,
        'figures': {'floor_cpu_us_per_tick': tick[FLOOR],
                    **{f'ratio: {name}': r for name, r in ratios.items()}},
        'elapsed_s': time.perf_counter() - start,
    }


def main(argv=None) -> int:
    """Run the section standalone and print it as JSON."""
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[1])
    parser.add_argument('--quick', action='store_true')
    parser.add_argument('--rounds', type=int, default=0)
    parser.add_argument('--seconds', type=float, default=0.0)
    options = parser.parse_args(argv)
    import json
    print(json.dumps(run(options.quick, options.rounds, options.seconds), indent=1,
                     default=str))
    return 0


if __name__ == '__main__':
    sys.exit(main())
