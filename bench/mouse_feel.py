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
How a click and a drag move the body, for the joints users know and for the shipped defaults.

Prints the tables of docs/dragging.md: ``python -m bench.mouse_feel`` from the repository's
root (a few seconds per row; pure core, no ROS), and ``make bench`` runs it as a section. Each
row is config/params.yaml as shipped with the overrides named.
"""

import math
import time

from test_support.mouse_feel import circle, click, FAR_CLICK, far_click, seed_joint, SOFT

UNGUIDED = {'max_target_speed': math.inf, 'max_target_acceleration': math.inf}
NO_BOUNDS = {'max_force_per_weight': math.inf, 'angular_friction': 0.0}

CLICKS = [
    ('seed joint (rigid, unbounded)', seed_joint()),
    ('Box2D v3.2 sample: soft 7.5 Hz, zeta 1, 100 m g, friction 0.25',
     {**UNGUIDED, **SOFT, 'max_force_per_weight': 100.0, 'gravity_feed_forward': False}),
    ('Bounce: soft 6 Hz, zeta 0.8, 20 m g',
     {**UNGUIDED, **NO_BOUNDS, 'frequency_hz': 6.0, 'damping_ratio': 0.8,
      'max_force_per_weight': 20.0, 'gravity_feed_forward': False}),
    ('Jolt sample: soft 2 Hz, zeta 1',
     {**UNGUIDED, **NO_BOUNDS, 'frequency_hz': 2.0, 'gravity_feed_forward': False}),
    ('rigid, 20 m g, friction 0.25, no guide', UNGUIDED),
    ('soft 7.5 Hz + guide + gravity feed-forward', SOFT),
    ('shipped: rigid + guide 2 m/s, 20 m/s^2, 20 m g, friction 0.25', {}),
    ('shipped, 0.01 kg body', {'mass': 0.01}),
    ('shipped, 100 kg body', {'mass': 100.0}),
]

# Substeps of the far click on the floor (shipped: 2).
FAR_SUBSTEPS = (1, 2, 16)

DRAGS = [
    ('rigid, no guide', UNGUIDED, 0.0),
    ('soft 7.5 Hz, no guide', {**UNGUIDED, **SOFT}, 0.0),
    ('soft 7.5 Hz, no guide, arrivals up to 5 ms late', {**UNGUIDED, **SOFT}, 0.005),
    ('soft 7.5 Hz + guide', SOFT, 0.0),
    ('shipped (rigid + guide)', {}, 0.0),
]


def run(quick: bool = False) -> dict:
    """Return the section: both tables (``quick`` keeps the shipped rows only)."""
    start = time.perf_counter()
    rows = []
    clicks = [row for row in CLICKS if row[0].startswith('shipped')] if quick else CLICKS
    for label, overrides in clicks:
        r = click(overrides)
        rows.append({'case': f'0.5 m click: {label}',
                     'a': f'{r.peak_speed:.3g} m/s', 'b': f'{r.peak_angular_speed:.3g} rad/s',
                     'c': f'{r.error_at_settle * 1e3:.3g} mm',
                     'd': f'{r.error_after_settle * 1e3:.3g} mm'})
    for substeps in (2,) if quick else FAR_SUBSTEPS:
        speed, spin = far_click({'substeps': substeps})
        rows.append({'case': f'click 4 m away on the floor, box resting there: {substeps} '
                             'substeps', 'a': f'{speed:.3g} m/s', 'b': f'{spin:.3g} rad/s',
                     'c': '', 'd': ''})
    drags = [row for row in DRAGS if row[0].startswith('shipped')] if quick else DRAGS
    for label, overrides, jitter in drags:
        without = circle(overrides, jitter=jitter, target_feed_forward=False)
        with_ff = circle(overrides, jitter=jitter)
        rows.append({'case': f'1 m/s circle at 50 Hz: {label}',
                     'a': f'{without * 1e3:.3g} mm', 'b': f'{with_ff * 1e3:.3g} mm',
                     'c': f'{without / with_ff:.3g}x', 'd': ''})
    return {
        'title': 'Dragging: a click and a streamed drag (the core, no ROS)',
        'text': ('`python -m bench.mouse_feel`. Clicks: peak COM speed, peak angular speed, '
                 'anchor error 1.5 s after the click, worst error after that. Drags: RMS '
                 'tracking error without and with the velocity feed-forward, and the ratio.'),
        'columns': [['case', 'case', ''], ['a', 'speed / RMS without', ''],
                    ['b', 'angular speed / RMS with', ''], ['c', 'error at 1.5 s / ratio', ''],
                    ['d', 'worst after 1.5 s', '']],
        'rows': rows,
        'elapsed_s': time.perf_counter() - start,
    }


def main() -> None:
    """Print both tables as Markdown."""
    print('## A 0.5 m click (body hanging from its corner, config/params.yaml)\n')
    print('| joint | peak COM speed (m/s) | peak angular speed (rad/s) | anchor error at 1.5 s '
          '(mm) | max after 1.5 s (mm) | max in the last second (mm) |')
    print('| --- | --- | --- | --- | --- | --- |')
    for label, overrides in CLICKS:
        r = click(overrides)
        print(f'| {label} | {r.peak_speed:.3g} | {r.peak_angular_speed:.3g} | '
              f'{r.error_at_settle * 1e3:.3g} | {r.error_after_settle * 1e3:.3g} | '
              f'{r.error_last_second * 1e3:.3g} |')
    print(f'\n## A click on the floor {abs(FAR_CLICK[1]):g} m away, the box resting there\n')
    print('| substeps | peak COM speed (m/s) | peak angular speed (rad/s) |')
    print('| --- | --- | --- |')
    for substeps in FAR_SUBSTEPS:
        speed, spin = far_click({'substeps': substeps})
        print(f'| {substeps} | {speed:.3g} | {spin:.3g} |')
    print('\n## A drag: target circling at 1 m/s (radius 0.25 m), streamed at 50 Hz\n')
    print('| joint | RMS error without feed-forward (mm) | with (mm) | ratio |')
    print('| --- | --- | --- | --- |')
    for label, overrides, jitter in DRAGS:
        without = circle(overrides, jitter=jitter, target_feed_forward=False)
        with_ff = circle(overrides, jitter=jitter)
        print(f'| {label} | {without * 1e3:.3g} | {with_ff * 1e3:.3g} | '
              f'{without / with_ff:.3g} |')


if __name__ == '__main__':
    main()
