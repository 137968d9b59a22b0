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
Force latency: a target pose published in another process -> the first force that reflects it.

The node runs at 1 kHz with config/haptic.yaml (the box hung by its corner on the soft
coupling, the force on ``force``). ``bench.observer latency --force`` publishes PoseStamped
targets on ``target_pose`` at random intervals (20-40 ms, a random phase against the tick
grid), 5-17 mm apart around the held corner, as a device's driver would, and records every
pose, twist and force.

The tick that first uses a target is found as ``bench.latency`` finds it, by replaying the
node's physics from its published states; the force of that tick (same stamp) is the first that
reflects it, and the replay's own force for that tick (minus its summed impulse over dt) must
equal the published one (to 1e-9 N), which checks both the match and the force.

Latency per target, in ticks of 1 ms: ``stamp - publish`` (the tick's due time, a lower bound)
and ``receive - publish``, when that force reached the observer (what a device driver sees).

Beside the executable, whose ticks come from its own spin loop, run the node with its ticks on
an rclpy timer (``bench.timer_node``) and the executable with ``tick_source: target_pose``
(each pose runs one tick at once, its force right after), the three alternating over ROUNDS
rounds of TRIALS / ROUNDS targets (as ``bench.latency``); each one's percentiles are over all
its targets. With device ticks each force carries its pose's stamp and is checked by replay
(``device_ticks``): from the state published before its tick, the tick with that pose as the
target must give it, as above (the node's own ticks are held back while poses come); its
tick's stamp is on the node's grid, one period after the tick before, no time of the pose, so
only ``receive - publish`` is reported for it. The node sits
idle between these sparse poses and each wakes it; a device at the node's rate, and its
one-tick target, is ``bench.device_stream``.

Standalone: ``python -m bench.force_latency [--quick]`` prints the section as JSON.
"""

from pathlib import Path
import time

from bench import ros_process
from bench.latency import _decode, alternating, GAP_S, MIN_JUMP_M, pooled
from bench.latency import QUICK_ROUNDS, QUICK_TRIALS, reflecting_ticks, resume, ROUNDS, SPREAD_M
from bench.latency import TRIALS
from geometry_msgs.msg import PoseStamped, TwistStamped, WrenchStamped
import numpy as np
import yaml

from mouse_constraint_ros.node.parameters import DEFAULTS, node_config
from mouse_constraint_ros.physics import MouseSimulation
from mouse_constraint_ros.wire.messages import felt_force, state_from_messages

PRESET = Path(__file__).resolve().parent.parent / 'config' / 'haptic.yaml'
TARGET_P99_TICKS = 2.0
# The node whose ticks the target poses run (``tick_source: target_pose``); its one-tick target
# is that of a device at the node's rate (``bench.device_stream``), not of this sparse stream.
DEVICE_RUN = 'mouse_constraint_node, tick_source target_pose'
FORCE_TOLERANCE = 1e-9


def preset() -> dict:
    """Return config/haptic.yaml's parameters."""
    return yaml.safe_load(PRESET.read_text())['/**']['ros__parameters']


def force_ticks(data: dict, parameters: dict) -> dict:
    """Return, per target found, the force's stamp and receive time, and the forces checked."""
    config = node_config(dict(DEFAULTS, **parameters))
    simulation = MouseSimulation(config.settings, config.initial_state)
    period = round(1e9 / config.rate_hz)
    replay = reflecting_ticks(data, parameters)
    poses = _decode(data['pose_raw'], data['pose_recv_ns'], PoseStamped)
    twists = _decode(data['twist_raw'], data['twist_recv_ns'], TwistStamped)
    forces = _decode(data['force_raw'], data['force_recv_ns'], WrenchStamped)
    targets = [tuple(float(c) for c in point) for point in data['targets']]
    found, mismatched = {}, 0
    for index, (stamp, _) in replay['first'].items():
        if stamp not in forces or stamp - period not in poses or stamp - period not in twists:
            continue
        resume(simulation, state_from_messages(poses[stamp - period][0],
                                               twists[stamp - period][0]))
        simulation.target = targets[index]
        simulation.step(1.0 / config.rate_hz)
        force, received = forces[stamp]
        published = force.wrench.force
        error = max(abs(a - b) for a, b in zip(
            felt_force(simulation.tick_impulse), (published.x, published.y, published.z)))
        if error > FORCE_TOLERANCE:
            mismatched += 1
            continue
        found[index] = (stamp, received)
    return {'found': found, 'mismatched': mismatched, 'replay': replay,
            'forces': len(forces), 'poses': len(poses)}


def device_ticks(data: dict, parameters: dict) -> dict:
    """
    Return, per pose the node ticked (``tick_source: target_pose``), its force, and the counts.

    A device tick's force carries its pose's stamp: the force of pose k is the one stamped
    with pose k's stamp, checked by replay: from the state the node published with the tick
    before its own, the tick with pose k as its target must give the published force to
    FORCE_TOLERANCE (the two streams go in step, one state and one force a tick, whatever order
    the observer took them in). A force of any other stamp is a tick of the node's own clock
    (``own``), checked with the target in force, or zero (the device silent, after its last
    pose); a force no replay gives is counted
    ``unexplained``. ``superseded``: poses no force answers (they never reached a tick).
    ``found``: pose index -> (None: the tick's stamp is the grid's, not a time of the pose,
    receive ns).
    """
    config = node_config(dict(DEFAULTS, **parameters))
    simulation = MouseSimulation(config.settings, config.initial_state)
    dt = 1.0 / config.rate_hz
    poses = _decode(data['pose_raw'], data['pose_recv_ns'], PoseStamped)
    twists = _decode(data['twist_raw'], data['twist_recv_ns'], TwistStamped)
    forces = _decode(data['force_raw'], data['force_recv_ns'], WrenchStamped)
    targets = [tuple(float(c) for c in point) for point in data['targets']]
    index = {int(stamp): k for k, stamp in enumerate(data.get('target_stamp_ns',
                                                              data['target_pub_ns']))}
    states = sorted(stamp for stamp in poses if stamp in twists)
    received_states = np.array([poses[stamp][1] for stamp in states])
    current = config.initial_anchor()
    found, unexplained, own = {}, 0, 0
    expected = None  # where in ``states`` the state before the next force should be
    for stamp, (force, received) in sorted(forces.items(), key=lambda item: item[1][1]):
        k = index.get(stamp)
        if k is None and received < data['target_pub_ns'][0]:
            continue
        target = current if k is None else targets[k]
        measured = (force.wrench.force.x, force.wrench.force.y, force.wrench.force.z)
        if k is None and not any(measured):  # the node's own tick, the device silent
            own += 1
            expected = None if expected is None else expected + 1
            continue
        if expected is None:  # the first: any state received within 0.2 s of it
            near = np.flatnonzero(np.abs(received_states - received) < 200_000_000)
            window = near.tolist()[::-1]
        else:  # the streams go in step: one state and one force a tick
            window = sorted(range(max(0, expected - 3), min(len(states), expected + 8)),
                            key=lambda j: abs(j - expected))
        match = None
        for before in window:
            resume(simulation, state_from_messages(poses[states[before]][0],
                                                   twists[states[before]][0]))
            simulation.target = target
            simulation.step(dt)
            if max(abs(a - b) for a, b in zip(felt_force(simulation.tick_impulse),
                                              measured)) <= FORCE_TOLERANCE:
                match = before
                break
        if match is None:
            unexplained += 1
            expected = None if expected is None else expected + 1
            continue
        expected = match + 1
        if k is None:
            own += 1
        else:
            found[k] = (None, received)
            current = target
    return {'found': found, 'superseded': len(index) - len(found), 'unexplained': unexplained,
            'own': own, 'forces': len(forces), 'poses': len(poses)}


def device_force_ticks(data: dict, parameters: dict) -> dict:
    """Return ``device_ticks``'s result in ``force_ticks``'s shape."""
    result = device_ticks(data, parameters)
    return {'found': result['found'], 'mismatched': result['unexplained'],
            'replay': {'superseded': [None] * result['superseded']},
            'forces': result['forces'], 'poses': result['poses']}


def measure(command, parameters: dict, trials: int, ticks=force_ticks) -> dict:
    """Run the node by ``command`` against the observer; return the latencies and counts."""
    config = node_config(dict(DEFAULTS, **parameters))
    with ros_process.start(command) as node:
        data, samples, _ = ros_process.observe(
            ['latency', '--force', '--trials', str(trials), '--gap-min', str(GAP_S[0]),
             '--gap-max', str(GAP_S[1]), '--center', *(repr(c) for c in config.initial_anchor()),
             '--spread', str(SPREAD_M), '--min-jump', str(MIN_JUMP_M)], [node.pid])
        cpu = ros_process.cpu_percent(samples['ready'], samples['end'], node.pid)
    result = ticks(data, parameters)
    period = 1e9 / config.rate_hz
    published = data['target_pub_ns']
    found = sorted(result['found'])
    return {'stamp': [(result['found'][k][0] - published[k]) / period for k in found
                      if result['found'][k][0] is not None],
            'receive': [(result['found'][k][1] - published[k]) / period for k in found],
            'published': len(published), 'found': len(found),
            'mismatched': result['mismatched'],
            'superseded': len(result['replay']['superseded']), 'forces': result['forces'],
            'poses': result['poses'], 'cpu': cpu, 'load': samples['end'].load}


def run(quick: bool = False) -> dict:
    start = time.perf_counter()
    trials = QUICK_TRIALS if quick else TRIALS
    rounds = QUICK_ROUNDS if quick else ROUNDS
    parameters = preset()
    config = node_config(dict(DEFAULTS, **parameters))
    device = {**parameters, 'tick_source': 'target_pose'}
    runs = (('mouse_constraint_node', ros_process.node_command(parameters)),
            ('the node, ticks on an rclpy timer', ros_process.timer_node_command(parameters)),
            (DEVICE_RUN, ros_process.node_command(device)))

    def measure_round(command) -> dict:
        if command is runs[2][1]:
            return measure(command, device, trials // rounds, device_force_ticks)
        return measure(command, parameters, trials // rounds)

    results = alternating(runs, rounds, measure_round)
    rows, notes = [], []
    for name, _ in runs:
        total = pooled(results[name])
        stamp, receive = total['stamp'], total['receive']
        rows += [{'node': name, 'measure': measure_name, 'trials': len(values),
                  'p50_ticks': float(np.percentile(values, 50)),
                  'p99_ticks': float(np.percentile(values, 99)),
                  'max_ticks': float(np.max(values))}
                 for measure_name, values in (('stamp - publish', stamp),
                                              ('receive - publish', receive))
                 if len(values)]
        counts = {key: sum(total[key]) for key in ('published', 'found', 'mismatched',
                                                   'superseded', 'forces', 'poses')}
        notes.append(
            f'{name}: {counts["published"]} targets published, {counts["found"]} found with '
            f'their force (replayed force equal to the published one within '
            f'{FORCE_TOLERANCE:g} N), {counts["mismatched"]} whose force did not match, '
            f'{counts["superseded"]} superseded before any tick used them; {counts["forces"]} '
            f'forces for {counts["poses"]} poses; node CPU {np.median(total["cpu"]):.1f} % '
            f'(median of the rounds), load {max(total["load"]):.1f} at most.')
        if len(receive):
            upper = float(np.percentile(receive, 99))
            verdict = 'met' if upper <= TARGET_P99_TICKS else 'missed'
            notes.append(f'{name}: target p99 <= {TARGET_P99_TICKS:g} ticks (receive - '
                         f'publish): {upper:.2f}, {verdict}.')
    return {
        'title': 'Force latency: target pose published in another process -> first force '
                 'reflecting it',
        'text': (f'Command: `python -m bench.force_latency`. Node at {config.rate_hz:g} Hz with '
                 f'config/haptic.yaml, {trials // rounds * rounds} target poses in {rounds} '
                 'alternating rounds at random '
                 f'{GAP_S[0] * 1e3:g}-{GAP_S[1] * 1e3:g} ms intervals; 1 tick = '
                 f'{1e3 / config.rate_hz:g} ms.'),
        'columns': [['node', 'node', ''], ['measure', 'measure', ''], ['trials', 'trials', 'd'],
                    ['p50_ticks', 'p50 (ticks)', '.2f'], ['p99_ticks', 'p99 (ticks)', '.2f'],
                    ['max_ticks', 'max (ticks)', '.2f']],
        'rows': rows,
        'notes': notes,
        'elapsed_s': time.perf_counter() - start,
    }


if __name__ == '__main__':
    import json
    import sys
    print(json.dumps(run(quick='--quick' in sys.argv), indent=1))
