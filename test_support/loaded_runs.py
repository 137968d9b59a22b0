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
Run a command several times while other processes keep cores busy: the loaded-machine check.

``python -m test_support.loaded_runs --runs 3 --hogs 1 -- make test`` starts ``--hogs``
processes that spin on the CPU for the whole time (a suite or a build sharing the machine),
runs the command ``--runs`` times in turn, and prints each run's exit status and wall time,
then how many passed. It exits 1 unless every run passed. ``make test-loaded`` runs it on
``make test``.
"""

import argparse
import multiprocessing
import subprocess
import sys
import time
from typing import List


def spin() -> None:
    """Keep one core busy until killed."""
    while True:
        pass


def minutes(seconds: float) -> str:
    """Return ``seconds`` as 'M min S s'."""
    whole = round(seconds)
    return f'{whole // 60} min {whole % 60:02d} s'


def main(argv: List[str] = None) -> int:
    """Run the command under load; return 0 when every run passed."""
    parser = argparse.ArgumentParser(description=__doc__.split('\n\n')[1])
    parser.add_argument('--runs', type=int, default=3, help='runs of the command (default 3)')
    parser.add_argument('--hogs', type=int, default=1,
                        help='processes keeping a core busy meanwhile (default 1)')
    parser.add_argument('command', nargs=argparse.REMAINDER, help='the command, after --')
    options = parser.parse_args(argv)
    command = options.command[1:] if options.command[:1] == ['--'] else options.command
    if not command:
        parser.error('no command given (after --)')
    hogs = [multiprocessing.Process(target=spin, daemon=True) for _ in range(options.hogs)]
    for hog in hogs:
        hog.start()
    results = []
    try:
        for run in range(1, options.runs + 1):
            started = time.monotonic()
            status = subprocess.run(command).returncode
            results.append((status, time.monotonic() - started))
            print(f'loaded run {run} of {options.runs} ({options.hogs} busy core(s)): '
                  f'{"passed" if status == 0 else f"FAILED (exit {status})"} in '
                  f'{minutes(results[-1][1])}', flush=True)
    finally:
        for hog in hogs:
            hog.kill()
    passed = sum(status == 0 for status, _ in results)
    mean = sum(seconds for _, seconds in results) / len(results)
    print(f'{passed} of {len(results)} runs passed with {options.hogs} busy core(s); mean '
          f'{minutes(mean)}: {" ".join(command)}')
    return 0 if passed == len(results) else 1


if __name__ == '__main__':
    sys.exit(main())
