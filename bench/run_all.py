#!/usr/bin/env python3
"""
Run the benchmark suite and write bench/results.md and bench/results.json.

Usage: ``python bench/run_all.py [--quick] [--only NAME[,NAME...]] [--output-dir DIR]``.

Each entry of ``SUITE`` names a module of this folder whose ``run(quick)`` returns a section
(see ``common.py``). A new benchmark (e.g. the node's latency) is one more module and one more
entry. A section that raises is reported as failed and the rest still run; the peers (PyBullet,
MuJoCo) are optional and their rows are skipped when they are not installed.
"""

import argparse
import importlib
from pathlib import Path
import sys
import time
import traceback

import common

# (module name, what it measures), in the order of results.md.
SUITE = [
    ('core_cost', 'part 1: us per substep, ours against the peers'),
    ('accuracy', 'part 4: the corner pendulum against the exact motion, energy'),
    ('drag', 'part 5: dragging at 1 kHz, tracking error'),
    ('node_rate', 'part 2: the node process at 100 Hz to 5 kHz, observed over DDS; CPU, RSS'),
    ('node_cost', 'part 2: where the node spends its CPU per tick, before and after 8dfbd58'),
    ('latency', 'part 3: target published -> first pose reflecting it, at 1 kHz'),
    ('soak', 'hardening: 10 min simulated at 1 kHz, the core directly'),
    ('flood', 'hardening: 20 000 targets/s for 10 s at the node running 1 kHz'),
    # Last: the longest, and nothing else runs while it does.
    ('memory', 'part 6: node RSS over minutes at 1 kHz, every path exercised'),
]


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[1])
    parser.add_argument('--quick', action='store_true',
                        help='fewer repeats and cases: a smoke test of the suite, not results')
    parser.add_argument('--only', default='',
                        help='comma-separated module names to run (default: all)')
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
    sections = {}
    for name, description in SUITE:
        if only and name not in only:
            continue
        print(f'{name}: {description} ...', flush=True)
        began = time.perf_counter()
        try:
            sections[name] = importlib.import_module(name).run(quick=args.quick)
        except Exception as error:  # One failed benchmark must not lose the others.
            traceback.print_exc()
            sections[name] = {'error': f'{type(error).__name__}: {error}'}
        print(f'{name}: done in {time.perf_counter() - began:.0f} s', flush=True)
    results = {'machine': machine, 'quick': args.quick,
               'elapsed_s': time.perf_counter() - start, 'sections': sections}
    common.write_results(results, args.output_dir)
    print(common.results_markdown(results))
    print(f'wrote {args.output_dir / "results.md"} and results.json', flush=True)
    return 1 if any('error' in section for section in sections.values()) else 0


if __name__ == '__main__':
    sys.exit(main())
