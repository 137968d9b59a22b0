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
Soak: 10 minutes of simulated time at 1 kHz, the core stepped directly.

No ROS and no clock: ``MouseSimulation.step(1 ms)`` 600 000 times per case, so it runs faster
than real time. The settings are the node's defaults (``node_config(DEFAULTS)``) unless a
case says otherwise. Cases:

- moving target: the target goes round a Lissajous figure that starts at the initial anchor
  (0.2 m, 0.15 m, 0.1 m amplitudes at 0.5, 0.3, 0.2 Hz, up to 0.7 m/s; its period is 10 s)
  with gravity on: the body is dragged, swings and spins the whole time;
- held, spinning: the target fixed at the initial anchor, the body started spinning at
  (1.5, -2, 6) rad/s: a spinning pendulum, no work is done on it;
- free spin: no target, no gravity, spinning at (0.05, 4, 0.05) rad/s, close to the
  intermediate axis, so that it tumbles over and over (Dzhanibekov).

Per tick: the quaternion's norm and the anchor error |C|; every 10 ticks the energy (kinetic +
gravitational, relative to the start) and, for the free body, |L|. Compared: the first minute
against the last.

Standalone: ``python -m bench.soak [--minutes M]`` prints the section as JSON.
"""

import argparse
from concurrent.futures import ProcessPoolExecutor
import json
import math
import os
import sys
import time

import numpy as np

from mouse_constraint_ros.node.parameters import DEFAULTS, node_config
from mouse_constraint_ros.physics import BodyState, MouseSimulation, Settings

RATE_HZ = 1000.0
MINUTES = 10.0
QUICK_MINUTES = 0.5
ENERGY_EVERY = 10
QUATERNION_TOLERANCE = 1e-12
# "Not growing": the last minute's figure at most this many times the first minute's.
GROWTH_TOLERANCE = 1.5
# (amplitude m, frequency Hz) per axis: the figure starts at its centre, the initial anchor.
LISSAJOUS = ((0.2, 0.5), (0.15, 0.3), (0.1, 0.2))
# Energy changes below this fraction of the starting kinetic energy are rounding.
ENERGY_ROUNDING = 1e-9


def lissajous(center, t: np.ndarray) -> np.ndarray:
    """Return the target at times ``t``: the Lissajous figure about ``center``."""
    return np.stack([c + a * np.sin(2.0 * math.pi * f * t)
                     for c, (a, f) in zip(center, LISSAJOUS)], axis=1)


CASES = ('moving target', 'held, spinning', 'free spin')


def case(name: str):
    """Return (settings text, settings, initial state, target path or None, fixed target)."""
    config = node_config(DEFAULTS)
    anchor = config.initial_anchor()
    state = config.initial_state
    if name == 'moving target':
        return ('node defaults, gravity on', config.settings, state,
                lambda t: lissajous(anchor, t), None)
    if name == 'held, spinning':
        spinning = BodyState(state.position, state.orientation, (0.0, 0.0, 0.0),
                             (1.5, -2.0, 6.0))
        return ('node defaults, target at the initial anchor', config.settings, spinning, None,
                anchor)
    free = Settings(config.settings.body, config.settings.constraint, gravity=(0.0, 0.0, 0.0),
                    substeps=config.settings.substeps)
    tumbling = BodyState(state.position, state.orientation, (0.0, 0.0, 0.0), (0.05, 4.0, 0.05))
    return ('no target, no gravity, near the intermediate axis', free, tumbling, None, None)


def soak_case(name: str, ticks: int) -> dict:
    """Run one case for ``ticks`` ticks; return its row (in a worker process)."""
    began = time.perf_counter()
    setup, settings, state, path, fixed = case(name)
    row = _figures(name, setup, soak(settings, state, path, fixed, ticks), ticks)
    row['run_s'] = time.perf_counter() - began
    return row


def soak(settings: Settings, state: BodyState, path, fixed, ticks: int) -> dict:
    """Step ``ticks`` ticks; return per-tick |q| - 1 and |C|, and the sampled energy and |L|."""
    simulation = MouseSimulation(settings, state)
    dt = 1.0 / RATE_HZ
    targets = path(dt * np.arange(1, ticks + 1)).tolist() if path is not None else None
    simulation.target = fixed
    mass = settings.body.mass
    gx, gy, gz = settings.gravity
    x0 = state.position
    q_error = np.empty(ticks)
    anchor_error = np.full(ticks, np.nan)
    samples = ticks // ENERGY_EVERY
    energy = np.empty(samples)
    momentum = np.empty(samples)
    potential0 = -mass * (gx * x0[0] + gy * x0[1] + gz * x0[2])
    energy0 = simulation.kinetic_energy()
    step, sqrt, hypot = simulation.step, math.sqrt, math.hypot
    for i in range(ticks):
        if targets is not None:
            simulation.target = targets[i]
        s = step(dt)
        qx, qy, qz, qw = s.orientation
        q_error[i] = sqrt(qx * qx + qy * qy + qz * qz + qw * qw) - 1.0
        if simulation.target is not None:
            anchor_error[i] = hypot(*simulation.anchor_error())
        if i % ENERGY_EVERY == 0:
            x = s.position
            potential = -mass * (gx * x[0] + gy * x[1] + gz * x[2]) - potential0
            energy[i // ENERGY_EVERY] = simulation.kinetic_energy() + potential - energy0
            momentum[i // ENERGY_EVERY] = math.hypot(*simulation.angular_momentum())
    return {'q_error': q_error, 'anchor_error': anchor_error, 'energy': energy,
            'momentum': momentum, 'energy0': energy0, 'final': simulation.state}


def _figures(name: str, setup: str, recorded: dict, ticks: int) -> dict:
    # The first and the last minute (a fifth of the run each in a run shorter than 5 min).
    minute = min(int(60 * RATE_HZ), ticks // 5)
    first, last = slice(0, minute), slice(ticks - minute, ticks)
    e_first = recorded['energy'][:minute // ENERGY_EVERY]
    e_last = recorded['energy'][-(minute // ENERGY_EVERY):]
    error = recorded['anchor_error']
    has_target = not np.all(np.isnan(error))
    momentum = recorded['momentum']
    finite = all(np.all(np.isfinite(v)) for v in recorded['final'])
    row = {
        'case': name, 'setup': setup, 'finite': 'yes' if finite else 'NO',
        'q_error_max': float(np.max(np.abs(recorded['q_error']))),
        'energy0_j': recorded['energy0'],
        'energy_first_j': [float(np.min(e_first)), float(np.max(e_first))],
        'energy_last_j': [float(np.min(e_last)), float(np.max(e_last))],
        'energy_peak_first_j': float(np.max(np.abs(e_first))),
        'energy_peak_last_j': float(np.max(np.abs(e_last))),
        'energy_max_abs_j': float(np.max(np.abs(recorded['energy']))),
        'energy_mean_drift_j': float(np.mean(e_last) - np.mean(e_first)),
    }
    row['energy_text'] = (f'[{row["energy_first_j"][0]:+.3g}, {row["energy_first_j"][1]:+.3g}]'
                          f' -> [{row["energy_last_j"][0]:+.3g}, {row["energy_last_j"][1]:+.3g}]')
    if has_target:
        row.update({
            'anchor_rms_first_mm': 1e3 * float(np.sqrt(np.mean(error[first] ** 2))),
            'anchor_rms_last_mm': 1e3 * float(np.sqrt(np.mean(error[last] ** 2))),
            'anchor_max_first_mm': 1e3 * float(np.max(error[first])),
            'anchor_max_last_mm': 1e3 * float(np.max(error[last])),
        })
        row['anchor_growth'] = row['anchor_rms_last_mm'] / row['anchor_rms_first_mm']
    else:
        m_first = momentum[:minute // ENERGY_EVERY]
        row['momentum_drift_rel'] = float(
            (np.mean(momentum[-(minute // ENERGY_EVERY):]) - np.mean(m_first))
            / np.mean(m_first))
    return row


def run(quick: bool = False, minutes: float = None) -> dict:
    start = time.perf_counter()
    minutes = minutes if minutes is not None else (QUICK_MINUTES if quick else MINUTES)
    ticks = int(round(60.0 * minutes * RATE_HZ))
    # The cases are independent: one worker process per core (the machine is otherwise idle
    # while the suite runs this; nothing here is timed but the run itself).
    with ProcessPoolExecutor(max_workers=min(len(CASES), os.cpu_count() or 1)) as pool:
        rows = list(pool.map(soak_case, CASES, [ticks] * len(CASES)))
    notes = _verdicts(rows, minutes)
    notes += [
        '|q| - 1: the largest deviation of the quaternion norm from 1 over every tick.',
        'energy: kinetic + gravitational - its value at the start (J), min and max over the '
        'first minute -> over the last; mean drift: mean over the last minute - mean over the '
        'first. With a moving target the target does work, so the energy follows the drag; '
        '"bounded" means it does not climb. The published '
        'velocities are half a substep behind the positions (leapfrog), so the energy has an '
        'O(h) ripple.',
        'anchor: RMS of |C| (distance of the anchor from the target after each tick) over the '
        'first and the last minute; growth = last / first.',
    ]
    if minutes < MINUTES:
        notes.append(f'Short run ({minutes:g} min of simulated time, quick mode or --minutes).')
    return {
        'title': f'Soak: {minutes:g} min simulated at {RATE_HZ:g} Hz, the core directly',
        'text': (f'{ticks} ticks of 1 ms per case, node default settings (rigid, baumgarte '
                 f'{node_config(DEFAULTS).settings.constraint.baumgarte:g}, '
                 f'{node_config(DEFAULTS).settings.substeps} substeps) unless stated; '
                 'first minute against last minute.'),
        'columns': [['case', 'case', ''], ['setup', 'setup', ''], ['finite', 'finite', ''],
                    ['q_error_max', 'max ||q| - 1|', '.1e'],
                    ['energy_text', 'energy (J): 1st min -> last min', ''],
                    ['energy_mean_drift_j', 'mean drift (J)', '+.2g'],
                    ['anchor_rms_first_mm', 'anchor RMS 1st min (mm)', '.3f'],
                    ['anchor_rms_last_mm', 'anchor RMS last min (mm)', '.3f'],
                    ['anchor_growth', 'anchor growth', '.2f'],
                    ['momentum_drift_rel', '|L| drift (rel)', '.1e'],
                    ['run_s', 'run time (s)', '.0f']],
        'rows': rows,
        'notes': notes,
        'elapsed_s': time.perf_counter() - start,
    }


def _verdicts(rows, minutes: float) -> list:
    notes = []
    q_worst = max(row['q_error_max'] for row in rows)
    notes.append(f'Target: quaternion norm within {QUATERNION_TOLERANCE:g} of 1. Worst '
                 f'{q_worst:.1e}: ' + ('met.' if q_worst <= QUATERNION_TOLERANCE else 'missed.'))
    gaining = [row['case'] for row in rows
               if row['energy_last_j'][1] > row['energy_first_j'][1]
               + ENERGY_ROUNDING * max(row['energy0_j'], row['energy_peak_first_j'])]
    notes.append('Target: energy bounded (the largest E - E0 of the last minute no higher than '
                 'that of the first, give or take rounding: '
                 f'{ENERGY_ROUNDING:g} of the starting energy scale). '
                 + ('Met by every case.' if not gaining else
                    f'Missed by: {", ".join(gaining)}.'))
    losing = [f'{row["case"]} ({row["energy_mean_drift_j"]:+.3g} J)' for row in rows
              if row['energy_mean_drift_j']
              < -0.01 * max(row['energy0_j'], row['energy_peak_first_j'])]
    if losing:
        notes.append('Energy lost between the first and the last minute (mean over each): '
                     + ', '.join(losing) + '. Bounded, but dissipated by the solver.')
    growing = [f'{row["case"]} ({row["anchor_growth"]:.2f}x)' for row in rows
               if row.get('anchor_growth', 0.0) > GROWTH_TOLERANCE]
    notes.append(f'Target: anchor error not growing (last-minute RMS at most '
                 f'{GROWTH_TOLERANCE:g}x the first). '
                 + ('Met.' if not growing else f'Missed by: {", ".join(growing)}.'))
    return notes


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[1])
    parser.add_argument('--minutes', type=float, default=MINUTES)
    options = parser.parse_args(argv)
    print(json.dumps(run(minutes=options.minutes), indent=1))
    return 0


if __name__ == '__main__':
    sys.exit(main())
