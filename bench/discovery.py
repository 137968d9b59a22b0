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
A command reaching the node: ``mouse_ctl release``, the node with and without the profile.

The profile is Fast DDS's ``config/fast_discovery.xml``, in the node's environment. The node
starts with config/params.yaml, 3 s pass (it is up and announced), then ``mouse_ctl release``
runs CALLS times one after the other, each timed from its start to its exit: Python's and
rclpy's start-up, discovery, the call and its answer. The command never has the profile: a new
participant whose first exchange with the node is lost waits for the node's next announcement,
every 3 s by default, every 0.25 s with the profile. The two cases alternate over ROUNDS rounds,
each round on a ROS domain of its own. Figures: per case the median and the largest call, and
how many took over 1 s.

Standalone: ``python -m bench.discovery [--quick]`` prints the section as JSON.
"""

import os
import subprocess
import sys
import time
from typing import Dict, List

from bench import common
from bench import ros_process

from test_support import processes

PROFILE = ros_process.ROOT / 'config' / 'fast_discovery.xml'
PROFILE_VARIABLE = 'FASTRTPS_DEFAULT_PROFILES_FILE'
CALLS, QUICK_CALLS = 15, 4
ROUNDS, QUICK_ROUNDS = 2, 1
STARTED = 3.0  # s between the node's start and the first call
SLOW = 1.0  # s: a call slower than this waited for an announcement
CASES = ('default', 'profile')


def _environment(domain_id: int, profile: bool) -> Dict[str, str]:
    environment = processes.private_environment(domain_id)
    environment.pop(PROFILE_VARIABLE, None)
    if profile:
        environment[PROFILE_VARIABLE] = str(PROFILE)
    return environment


def calls(*, domain_id: int, profile: bool, count: int) -> List[float]:
    """Return the seconds of ``count`` ``mouse_ctl release`` calls against a node just started."""
    command = processes.node_command('--params-file', str(ros_process.ROOT / 'config' /
                                                          'params.yaml'))
    client = _environment(domain_id, profile=False)
    seconds = []
    with processes.ChildProcess(command, environment=_environment(domain_id, profile)) as node:
        time.sleep(STARTED)
        for _ in range(count):
            start = time.perf_counter()
            result = subprocess.run([str(processes.BIN / 'mouse_ctl'), 'release'], env=client,
                                    capture_output=True, text=True, timeout=60)
            seconds.append(time.perf_counter() - start)
            if result.returncode != 0:
                raise RuntimeError(f'mouse_ctl release: {result.stderr.strip()}\n{node.log()}')
    return seconds


def run(quick: bool = False) -> dict:
    """Return the section: the calls' times against the node without and with the profile."""
    start = time.perf_counter()
    count, rounds = (QUICK_CALLS, QUICK_ROUNDS) if quick else (CALLS, ROUNDS)
    times: Dict[str, List[float]] = {case: [] for case in CASES}
    for round_ in range(rounds):
        for index, case in enumerate(CASES):
            domain_id = ros_process.DOMAIN_ID + 10 + 2 * round_ + index
            times[case] += calls(domain_id=domain_id, profile=case == 'profile', count=count)
    rows = [{'case': 'node without a profile' if case == 'default' else
             'node with config/fast_discovery.xml',
             'calls': len(seconds), 'median_s': common.median(seconds),
             'largest_s': max(seconds), 'slow': sum(s > SLOW for s in seconds)}
            for case, seconds in times.items()]
    return {
        'title': 'A command reaching the node: mouse_ctl release',
        'text': 'Command: `python -m bench.discovery`. Each call timed from its start to its '
                f'exit, {count} calls a round after the node had run {STARTED:g} s, the two '
                f'cases alternating over {rounds} round(s), each round on its own domain.',
        'columns': [['case', 'case', ''], ['calls', 'calls', 'd'],
                    ['median_s', 'median (s)', '.2f'], ['largest_s', 'largest (s)', '.2f'],
                    ['slow', f'over {SLOW:g} s', 'd']],
        'rows': rows,
        'notes': [f'{case}: ' + ' '.join(f'{s:.2f}' for s in seconds)
                  for case, seconds in times.items()],
        'figures': {f'{case}_largest_s': max(seconds) for case, seconds in times.items()},
        'elapsed_s': time.perf_counter() - start,
    }


if __name__ == '__main__':
    import json
    os.chdir(ros_process.ROOT)
    print(json.dumps(run(quick='--quick' in sys.argv), indent=1, default=str))
