#!/usr/bin/env python3
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
Run the benchmark suite and write bench/results.md and bench/results.json.

Usage, from the repository's root: ``python -m bench.run_all [--quick] [--only NAME[,NAME...]]
[--output-dir DIR]`` (``make bench`` runs it).

Each entry of ``SUITE`` names a module of this package whose ``run(quick)`` returns a section
(see ``bench.common``). A new benchmark is one more module and one more entry. A section that
raises is reported as failed and the rest still run; the peers (PyBullet, MuJoCo) are optional
and their rows are skipped when they are not installed (``make bench`` installs them,
requirements/bench/; run directly, ``python -m bench.run_all`` says when they are missing). Each
section records the date, commit and peers of the run that measured it; one kept from an earlier
run (``--only``) is marked so in results.md.
"""

import argparse
import importlib
import json
from pathlib import Path
import sys
import time
import traceback

from bench import common

# (module name, what it measures), in the order of results.md.
SUITE = [
    ('physics_figures', 'the figures the docs quote, on the core: pendulum, gyroscopic, gains'),
    ('core_cost', 'us per substep, ours against the peers'),
    ('accuracy', 'the corner pendulum against the exact motion, energy'),
    ('drag', 'dragging at 1 kHz, tracking error'),
    ('mouse_feel', 'a click and a streamed drag: the shipped joint and the anchors recipes'),
    ('stream_timing', 'a browser drag through ROS, timed by stamps and by arrival'),
    ('stream_estimators', 'which fit of stamped points: the estimators on the core'),
    ('late_streams', 'late, mixed and jittering streams, the floor press: the node in lockstep'),
    ('haptic_stability', 'the haptic loop: largest stable stiffness, predicted and measured'),
    ('contact', 'the floor: rest, slide and drop, ours against PyBullet and MuJoCo'),
    ('node_rate', 'the node process against the rclpy floor at 1 kHz and up, pose and twist read'),
    ('node_cost', 'the node against the rclpy floor: medians of alternating windows, per tick'),
    ('tick_profile', "where a tick's time goes: py-spy samples of the node's main thread"),
    ('node_floor', 'the node at 1 kHz resting on the floor against no floor: CPU ratio'),
    ('node_hull', 'a 500-vertex mesh body on the floor at 1 kHz against the rclpy floor'),
    ('node_robot', 'a UR5 and a Panda at 1 kHz, joint_states read, against the rclpy floor'),
    ('publish_rate', 'publishing at 100 Hz from 1 kHz physics, if the node offers it'),
    ('latency', 'target published -> first pose reflecting it, at 1 kHz'),
    ('force_latency', 'target pose published -> first force reflecting it, config/haptic.yaml'),
    ('device_stream', "a device at the node's rate: each pose -> its force, against an echo"),
    ('device_load', 'a device at 1 kHz, two busy processes per core: poses served or counted'),
    ('discovery', 'mouse_ctl release against the node, with and without its Fast DDS profile'),
    ('help_time', "each console script's --help against a bare import of rclpy and messages"),
    ('first_output', 'from a start to the first output: a bare publisher, the node, the recorder'),
    ('soak', '10 min simulated at 1 kHz, the core directly'),
    ('flood', 'target floods at the 1 kHz node: 5 000/s plain, unbounded, hostile'),
    ('flood_rate', 'the 500 Hz node under a 5 000/s flood, run after run: the rate each held'),
    ('view_cost', 'mouse_view with one headless browser; the node with and without it'),
    ('recorder_cost', 'mouse_record per tick: raw reads, rows, CSV and MCAP'),
    # Last: the longest, and nothing else runs while it does.
    ('memory', 'node RSS over minutes at 1 kHz, every path exercised'),
]


def kept_sections(path: Path, fresh: dict) -> dict:
    """
    Return the sections of the results.json at ``path`` with ``fresh`` ones in their place.

    In SUITE's order; a kept section without its own date takes the date and commit of the run
    that wrote the file, and one of that run takes its peers and CPU (from the file's header).
    """
    try:
        previous = json.loads(path.read_text())
    except (OSError, ValueError):
        return fresh
    machine = previous.get('machine', {})
    when = {'date': machine.get('date', '?'), 'commit': machine.get('commit', '?')}
    merged = {}
    for name, _ in SUITE:
        if name in fresh:
            merged[name] = fresh[name]
        elif name in previous.get('sections', {}):
            merged[name] = dict(previous['sections'][name])
            measured = dict(merged[name].get('measured', when))
            if (measured['date'], measured['commit']) == (when['date'], when['commit']):
                # Measured by the run the old file's header describes: its peers and CPU.
                measured.setdefault('peers', machine.get('peers'))
                measured.setdefault('cpu', machine.get('cpu'))
            merged[name]['measured'] = {k: v for k, v in measured.items() if v is not None}
    return merged


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[1])
    parser.add_argument('--quick', action='store_true',
                        help='fewer repeats and cases: a smoke test of the suite, not results')
    parser.add_argument('--only', default='',
                        help='comma-separated module names to run (default: all); the other '
                             'sections of the existing results.json are kept, each with the '
                             'date and commit it was measured at')
    parser.add_argument('--output-dir', type=Path, default=Path(__file__).resolve().parent,
                        help='where to write results.md and results.json (default: bench/)')
    args = parser.parse_args(argv)
    names = [name for name, _ in SUITE]
    only = [name for name in args.only.split(',') if name]
    unknown = sorted(set(only) - set(names))
    if unknown:
        parser.error(f'unknown benchmark(s) {unknown}; choose from {names}')
    start = time.perf_counter()
    machine = common.machine_info()
    print(f'machine: {machine["cpu"]}, {machine["cores"]} cores, Python {machine["python"]}, '
          f'numpy {machine["numpy"]}, peers {machine["peers"]}', flush=True)
    missing = [name for name, version in machine['peers'].items() if 'not installed' in version]
    if missing:
        print(f'peers not installed here: {", ".join(missing)}; their rows are skipped '
              '(make bench installs requirements/bench/)', flush=True)
    sections = {}
    measured = {'date': machine['date'], 'commit': machine['commit'], 'peers': machine['peers'],
                'cpu': machine['cpu']}
    for name, description in SUITE:
        if only and name not in only:
            continue
        print(f'{name}: {description} ...', flush=True)
        began = time.perf_counter()
        try:
            sections[name] = importlib.import_module(f'bench.{name}').run(quick=args.quick)
        except Exception as error:  # One failed benchmark must not lose the others.
            traceback.print_exc()
            sections[name] = {'error': f'{type(error).__name__}: {error}'}
        sections[name]['measured'] = measured
        print(f'{name}: done in {time.perf_counter() - began:.0f} s', flush=True)
    if only:
        sections = kept_sections(args.output_dir / 'results.json', sections)
    results = {'machine': machine, 'quick': args.quick,
               'elapsed_s': time.perf_counter() - start, 'sections': sections}
    common.write_results(results, args.output_dir)
    print(common.results_markdown(results))
    print(f'wrote {args.output_dir / "results.md"} and results.json', flush=True)
    return 1 if any('error' in section for section in sections.values()) else 0


if __name__ == '__main__':
    sys.exit(main())
