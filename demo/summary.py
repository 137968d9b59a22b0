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
The numbers of a ``make demo`` run, phase by phase, from its recording's CSV.

``python demo/summary.py [demo/output]`` prints, for the phases of ``demo/run_demo.sh``: the
grab (the anchor error from the grab to the circle, the peak speed and spin, when the body came
to rest), the circle (the anchor error while the targets go round, median and largest, and
from ``SETTLED`` into it, and just after it), the jump (when the error fell below 5 cm and
0.1 mm, peak speed and spin) and the run's peak speed and spin. ``docs/recording.md`` quotes
them.

A row is on the circle when its target moves and lies within ``ON_CIRCLE`` of the circle of
``RADIUS`` through the grabbed point (the target path's chords between 50 Hz targets stay within
0.15 mm of it); the jump starts at the first row after it whose target is off the circle.
"""

import csv
import math
from pathlib import Path
import sys

import numpy as np

# The demo's circle (demo/run_demo.sh): its radius, centred RADIUS in -x of the grabbed point.
RADIUS = 0.3
ON_CIRCLE = 5e-4
# The body is at rest when its COM moves slower than this (m/s).
AT_REST = 1e-3
# The circle's start: the body takes this long (s) to come up to its speed.
SETTLED = 0.2


def read_rows(path: Path) -> dict:
    """Return the CSV's columns as arrays (NaN where empty)."""
    with open(path, newline='') as stream:
        rows = list(csv.DictReader(line for line in stream if not line.startswith('#')))
    return {key: np.array([float(row[key]) if row[key] else math.nan for row in rows])
            for key in rows[0]}


def summary(columns: dict) -> list:
    """Return the lines of the summary."""
    t, error = columns['time'], columns['anchor_error']
    speed, spin = columns['speed'], columns['angular_speed']
    [grab_row] = np.flatnonzero(columns['grab_taken'] == 1.0)
    grab = np.array([columns[f'grab_{c}'][grab_row] for c in 'xyz'])
    target = np.stack([columns[f'target_{c}'] for c in 'xyz'], axis=1)
    centre = grab - (RADIUS, 0.0, 0.0)
    radial = np.hypot(target[:, 0] - centre[0], target[:, 1] - centre[1])
    on_circle = ((np.abs(radial - RADIUS) < ON_CIRCLE)
                 & (np.abs(target[:, 2] - grab[2]) < ON_CIRCLE))
    held = np.all(np.isfinite(target), axis=1)
    moving = np.r_[False, held[1:] & held[:-1] & np.any(target[1:] != target[:-1], axis=1)]
    on = np.flatnonzero(on_circle & moving)
    first, last = on[0], on[-1]
    jump = last + 1 + np.flatnonzero(~on_circle[last + 1:])[0]
    swing = slice(grab_row, first)
    rest = grab_row + np.flatnonzero(speed[swing] >= AT_REST)[-1] + 1
    circle, after = error[first:last + 1], error[last + 1:jump]

    def below(limit: float) -> float:
        return t[jump + np.flatnonzero(error[jump:] < limit)[0]] - t[jump]
    return [
        f'grab at {t[grab_row]:.2f} s: anchor error at most {np.nanmax(error[swing]):.2g} m '
        f'until the circle; peak {speed[swing].max():.2f} m/s, {spin[swing].max():.2f} rad/s; '
        f'at rest {t[rest] - t[grab_row]:.2f} s after the grab',
        f'circle {t[first]:.2f} s to {t[last]:.2f} s: anchor error median '
        f'{np.median(circle) * 1e3:.3g} mm, largest {circle.max() * 1e3:.3g} mm at '
        f'{t[first + np.argmax(circle)] - t[first]:.2f} s into it, from {SETTLED:g} s into it '
        f'largest {circle[t[first:last + 1] - t[first] >= SETTLED].max() * 1e3:.3g} mm; '
        f'{np.median(speed[first:last + 1]):.2f} m/s median',
        f'after the circle, before the jump: largest {after.max() * 1e3:.3g} mm',
        f'jump at {t[jump]:.2f} s: error below 5 cm after {below(0.05):.2f} s, below 0.1 mm '
        f'after {below(1e-4):.2f} s; peak {speed[jump:].max():.2f} m/s, '
        f'{spin[jump:].max():.2f} rad/s',
        f'whole run: {t[-1]:.1f} s, {len(t)} ticks; peak {speed.max():.2f} m/s, '
        f'{spin.max():.2f} rad/s',
    ]


def main(argv: list) -> int:
    """Print the summary of the run in ``argv[1]`` (default demo/output)."""
    folder = Path(argv[1]) if len(argv) > 1 else Path(__file__).parent / 'output'
    print('\n'.join(summary(read_rows(folder / 'recording.csv'))))
    return 0


if __name__ == '__main__':
    sys.exit(main(sys.argv))
