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
A device at the node's rate: each pose -> its force, the device-clocked node against a bare echo.

``bench.observer latency --force`` with a gap of one tick is the device's process: it publishes
a PoseStamped on ``target_pose`` every millisecond (the next one a millisecond after the last
publish call returned, so a little under 1 kHz), 5-17 mm apart around the held corner, and
records every pose, twist and force with its receive time. Three processes answer, alternating
over ROUNDS rounds:

- ``mouse_constraint_node`` with config/haptic.yaml and ``tick_source: target_pose``: each pose
  runs one tick at once, its force published right after;
- the same executable on its own clock (``tick_source: clock``, the default): each tick takes
  the newest pose that came before it; its force of a pose is the first that reflects it,
  found by replay as ``bench.force_latency`` finds it;
- ``bench.bare_timer --echo --twist --wrench``: a bare rclpy node on the node's executor that
  publishes the same three messages at once for each pose, with no physics: the floor of a
  pose -> force round trip through rclpy on this machine, same run.

For the device-clocked node the device stamps its k-th pose k periods after its first, as a
device at its rate does (``--nominal-stamps``), and the node's force of pose k carries that
stamp; it is checked by replay: from the state the node published with the tick before, the
tick with pose k as its target must give the published force to 1e-9 N (the poses are
millimetres apart, the forces then newtons). At the end the device's process reads the node's
own counts off /diagnostics: the poses that ran a tick (served) and those it counted lost from
the gaps in their stamps; served / sent is the figure, at the load the run had. For the node on
its own clock, poses a later one replaced before the node took them are counted as superseded;
a force no pose explains is counted. The echo's force carries its pose's stamp.

Latency per pose, in ticks of 1 ms: ``receive - publish``, the force back in the device's
process (the round trip a driver sees), and for the node on its own clock ``stamp - publish``,
the tick's start after the publish (the hop in, and the wait for the node's loop); a device
tick's stamp is on the node's grid, no time of the pose.

Standalone: ``python -m bench.device_stream [--quick]`` prints the section as JSON.
"""

from functools import partial
import time

from bench import ros_process
from bench.force_latency import device_ticks, force_ticks, FORCE_TOLERANCE, preset
from bench.latency import _decode, alternating, MIN_JUMP_M, pooled, SPREAD_M
from geometry_msgs.msg import WrenchStamped
import numpy as np

from mouse_constraint_ros.node.parameters import DEFAULTS, node_config

TRIALS = 8000
QUICK_TRIALS = 1000
ROUNDS = 4
QUICK_ROUNDS = 1
NODE = 'mouse_constraint_node, tick_source target_pose'
CLOCKED = 'mouse_constraint_node, its own clock'
ECHO = 'bare rclpy echo: bench.bare_timer --echo'
TARGET_P99_TICKS = 1.0


def clocked_answers(data: dict, parameters: dict) -> dict:
    """Return, per pose, the first force reflecting it (stamp, receive ns), and the counts."""
    result = force_ticks(data, parameters)
    replay = result['replay']
    return {'found': result['found'], 'superseded': len(replay['superseded']),
            'unexplained': replay['unexplained'] + result['mismatched'], 'own': 0,
            'forces': result['forces']}


def echo_answers(data: dict) -> dict:
    """Return, per pose the echo answered, its force's (stamp, receive ns), and the counts."""
    forces = _decode(data['force_raw'], data['force_recv_ns'], WrenchStamped)
    index = {int(sent): k for k, sent in enumerate(data.get('target_stamp_ns',
                                                            data['target_pub_ns']))}
    found = {index[stamp]: (stamp, received) for stamp, (_, received) in forces.items()
             if stamp in index}
    return {'found': found, 'superseded': len(index) - len(found), 'unexplained': 0, 'own': 0,
            'forces': len(forces)}


def measure(command, answers, trials: int, parameters: dict, nominal: bool = False) -> dict:
    """
    Run ``command`` against the device's process; return the latencies and counts.

    :param nominal: the device stamps its k-th pose k periods after its first (as a device at
        its rate does), not with the publish time.
    """
    config = node_config(dict(DEFAULTS, **parameters))
    period = 1e9 / config.rate_hz
    gap = repr(1.0 / config.rate_hz)
    with ros_process.start(command) as node:
        data, samples, observer = ros_process.observe(
            ['latency', '--force', '--trials', str(trials), '--gap-min', gap, '--gap-max', gap,
             '--center', *(repr(c) for c in config.initial_anchor()), '--spread', str(SPREAD_M),
             '--min-jump', str(MIN_JUMP_M), *(['--nominal-stamps'] if nominal else [])],
            [node.pid])
        cpu = ros_process.cpu_percent(samples['ready'], samples['end'], node.pid)
        observer_cpu = ros_process.cpu_percent(samples['ready'], samples['end'], observer)
    result = answers(data)
    published = data['target_pub_ns']
    found = sorted(result['found'])
    span = (published[-1] - published[0]) / 1e9
    return {'stamp': [(result['found'][k][0] - published[k]) / period for k in found
                      if result['found'][k][0] is not None],
            'receive': [(result['found'][k][1] - published[k]) / period for k in found],
            'published': len(published), 'found': len(found),
            'superseded': result['superseded'], 'unexplained': result['unexplained'],
            'own': result['own'], 'rate': (len(published) - 1) / span, 'cpu': cpu,
            'served': int(data['device_ticks']), 'lost': int(data['device_lost']),
            'observer_cpu': observer_cpu, 'load': samples['end'].load}


def run(quick: bool = False) -> dict:
    """Return the section: the device-clocked node and the bare echo, alternating."""
    start = time.perf_counter()
    trials = QUICK_TRIALS if quick else TRIALS
    rounds = QUICK_ROUNDS if quick else ROUNDS
    clocked = preset()
    parameters = {**clocked, 'tick_source': 'target_pose'}
    runs = ((NODE, ros_process.node_command(parameters)),
            (CLOCKED, ros_process.node_command(clocked)),
            (ECHO, ros_process.bench_command('bare_timer', '--echo', '--twist', '--wrench')))
    answers = {id(runs[0][1]): partial(device_ticks, parameters=parameters),
               id(runs[1][1]): partial(clocked_answers, parameters=clocked)}

    def measure_round(command) -> dict:
        return measure(command, answers.get(id(command), echo_answers), trials // rounds,
                       parameters, nominal=command is runs[0][1])

    results = alternating(runs, rounds, measure_round)
    rows, notes, figures = [], [], {}
    for name, _ in runs:
        total = pooled(results[name])
        for measure_name in ('stamp', 'receive'):
            values = total[measure_name]
            if not len(values) or (name == ECHO and measure_name == 'stamp'):
                continue  # a device tick's stamp is the grid's; the echo's, the pose's own
            rows.append({'process': name, 'measure': f'{measure_name} - publish',
                         'poses': len(values), 'p50_ticks': float(np.percentile(values, 50)),
                         'p99_ticks': float(np.percentile(values, 99)),
                         'max_ticks': float(np.max(values))})
        counts = {key: sum(total[key]) for key in ('published', 'found', 'superseded',
                                                   'unexplained', 'own', 'served', 'lost')}
        figures[name] = float(np.percentile(total['receive'], 99))
        how = {NODE: 'by their own force (the replay with that pose gives the published '
                     f'force within {FORCE_TOLERANCE:g} N)',
               CLOCKED: 'by the first force reflecting them (found by replay, its force '
                        f'within {FORCE_TOLERANCE:g} N)',
               ECHO: 'by their own force (its stamp)'}[name]
        if name == NODE:
            served, lost, sent = counts['served'], counts['lost'], counts['published']
            figures['served'] = served / sent
            figures['served_load'] = max(total['load'])
            fate = (f'{served} served (the node\'s count of the ticks they ran; {counts["found"]} '
                    f'found {how}), {lost} counted lost by the node (gaps in their stamps), '
                    f'{sent - served - lost} neither (lost before the first pose that came or '
                    'after the last), ')
        else:
            fate = (f'{counts["found"]} answered {how}, {counts["superseded"]} replaced '
                    'before taken, ')
        notes.append(
            f'{name}: {counts["published"]} poses published at {min(total["rate"]):.0f}-'
            f'{max(total["rate"]):.0f}/s, {fate}{counts["unexplained"]} forces no '
            'pose explains' + (f', {counts["own"]} tick(s) of the node\'s own clock'
                               if name == NODE else '') + '; CPU '
            f'{np.median(total["cpu"]):.1f} %, the device process '
            f'{np.median(total["observer_cpu"]):.1f} % (medians of the rounds), load '
            f'{max(total["load"]):.1f} at most.')
    node_p99, echo_p99 = figures[NODE], figures[ECHO]
    notes.append(f'Device-clocked node: {figures["served"]:.4f} of the poses sent served '
                 f'(ran their tick), at load {figures["served_load"]:.1f} at most.')
    notes.append(
        f'Round trip p99 (receive - publish): device-clocked node {node_p99:.2f} ticks, on its '
        f'own clock {figures[CLOCKED]:.2f}, bare echo {echo_p99:.2f} ticks; device-clocked '
        f'target p99 <= {TARGET_P99_TICKS:g} tick: '
        + ('met' if node_p99 <= TARGET_P99_TICKS else 'not met')
        + (f'; the echo, with no physics, {"meets" if echo_p99 <= TARGET_P99_TICKS else "misses"}'
           ' it on the same run.'))
    return {
        'title': "A device at the node's rate: each pose -> its force, device-clocked node "
                 'against its own clock and a bare rclpy echo',
        'text': (f'Command: `python -m bench.device_stream`. config/haptic.yaml, '
                 f'{trials // rounds * rounds} poses to each process in {rounds} alternating '
                 'rounds, one every tick; 1 tick = 1 ms.'),
        'columns': [['process', 'process', ''], ['measure', 'measure', ''],
                    ['poses', 'poses', 'd'], ['p50_ticks', 'p50 (ticks)', '.2f'],
                    ['p99_ticks', 'p99 (ticks)', '.2f'], ['max_ticks', 'max (ticks)', '.2f']],
        'rows': rows,
        'notes': notes,
        'figures': {'node_p99_ticks': node_p99, 'clocked_p99_ticks': figures[CLOCKED],
                    'echo_p99_ticks': echo_p99, 'node_served_per_sent': figures['served'],
                    'node_served_at_load': figures['served_load']},
        'elapsed_s': time.perf_counter() - start,
    }


if __name__ == '__main__':
    import json
    import sys
    print(json.dumps(run(quick='--quick' in sys.argv), indent=1))
