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
Late and mixed streams through the node in lockstep: every row of docs/dragging.md's table.

``python -m bench.late_streams [--quick]`` runs ``test_support.late_streams``'s scenarios on
the node with config/params.yaml, stepped on simulated time (``mouse_constraint_ros.testing``):
a 0.5 m/s drag that stops at once or slows to rest, at 20 and 60 Hz, 0, 100 and 200 ms late;
the drag that stops at once as a browser sends it at 20 Hz, 200 ms late; a still pointer
jittering +-2 mm at 60 Hz, 0 to 240 ms late; a 1 m/s circle on time, mixed (every other point
unstamped), 100 ms late at 60 Hz and 200 ms late at 20 Hz; a corner pressed into the floor
and lifted (1 s pressed, lifted over the pressed point; 3 s pressed, lifted back); a flat
elastic drop. Each row is printed with its goal and whether it was met. The numbers are
simulated, the same on any machine and any run.
"""

import json
import sys
import time

from test_support import floor_scenarios, late_streams
from test_support.floor_press import floor_press


def _rows(quick: bool) -> list:
    rows = []
    delays = (0.0, 0.2) if quick else late_streams.DELAYS
    for slow_down in (True, False):
        for row in late_streams.stop_rows(delays=delays, slow_down=slow_down):
            limit = 10.0 if slow_down else row['gap_mm'] + 5.0
            ratio = 1.2 if slow_down else 2.0
            end = 'slows to rest over 0.2 s' if slow_down else 'stops at once'
            rows.append({
                'case': (f'0.5 m/s drag that {end}, {row["rate_hz"]:g} Hz, '
                         f'{1e3 * row["delay_s"]:g} ms late'),
                'value': (f'overshoot {row["overshoot_mm"]:.1f} mm, speed '
                          f'{row["speed_ratio"]:.2f}x'),
                'goal': f'<= {limit:.3g} mm, <= {ratio:g}x',
                'met': row['overshoot_mm'] <= limit and row['speed_ratio'] <= ratio})
    for row in late_streams.browser_stop_rows():
        limit = row['gap_mm'] + 5.0
        rows.append({
            'case': (f'the same as a browser sends it (seed {row["seed"]}), '
                     f'{row["rate_hz"]:g} Hz, {1e3 * row["delay_s"]:g} ms late'),
            'value': f'overshoot {row["overshoot_mm"]:.1f} mm, speed {row["speed_ratio"]:.2f}x',
            'goal': f'<= {limit:.3g} mm, <= 2x',
            'met': row['overshoot_mm'] <= limit and row['speed_ratio'] <= 2.0})
    for row in late_streams.still_rows(delays=(0.0, 0.24) if quick
                                       else late_streams.STILL_DELAYS):
        rows.append({'case': f'still pointer +-2 mm, 60 Hz, {1e3 * row["delay_s"]:g} ms late',
                     'value': (f'wander {row["wander_mm"]:.2f} mm RMS (pointer '
                               f'{row["pointer_mm"]:.2f})'),
                     'goal': '<= 3 mm RMS', 'met': row['wander_mm'] <= 3.0})
    for rate, delay, mixed, behind, error, wobble in (
            (60.0, 0.0, True, 0.0, 3.0, None), (20.0, 0.0, False, 0.0, 3.0, 3.0),
            (60.0, 0.0, False, 0.0, 1.0, 2.0), (60.0, 0.1, False, None, 3.0, 3.0),
            (20.0, 0.2, False, None, 3.0, 3.0)):
        row = late_streams.circle_row(rate, delay, mixed=mixed, behind=behind)
        kind = 'stamped and unstamped mixed' if mixed else (
            f'{1e3 * delay:g} ms late' if delay else 'on time')
        met = row['error_mm'] <= error and (wobble is None or row['wobble_pct'] <= wobble)
        rows.append({'case': f'1 m/s circle, {rate:g} Hz, {kind}',
                     'value': (f'{row["error_mm"]:.2f} mm RMS, wobble {row["wobble_pct"]:.2f} %'
                               + (f', {row["behind_ms"]:g} ms behind' if delay else '')),
                     'goal': f'<= {error:g} mm' + (f', <= {wobble:g} %' if wobble else ''),
                     'met': met})
    for case, press, back in (('for 1 s, then lifted', 1.0, False),
                              ('for 3 s, then lifted back above where it was', 3.0, True)):
        peaks = floor_press(press=press, back=back)
        rows.append({'case': f'corner pressed 0.5 m into the floor and 0.3 m aside {case}',
                     'value': f'COM {peaks.speed:.2f} m/s, {peaks.spin:.2f} rad/s',
                     'goal': '<= 2.5 m/s, <= 15 rad/s',
                     'met': peaks.speed <= 2.5 and peaks.spin <= 15.0})
    drift, _ = floor_scenarios.elastic_drift(floor_scenarios.world(), height=0.5, seconds=30.0)
    rows.append({'case': 'flat drop from 0.5 m, restitution 1, threshold 0, 30 s',
                 'value': f'lateral drift {1e3 * drift:.4f} mm', 'goal': '<= 1 mm',
                 'met': drift <= 1e-3})
    return rows


def _notes() -> list:
    on_time = late_streams.browser_stop_rows(delay=0.0)
    return [("A browser's 20 Hz drag that stops at once, on time, keeps no lag: it overshoots by "
             'the whole horizon a stream followed without lag needs, '
             + ' / '.join(f'{row["overshoot_mm"]:.1f} mm' for row in on_time) + ', speed '
             + ' / '.join(f'{row["speed_ratio"]:.2f}x' for row in on_time) + '.')]


def run(quick: bool = False) -> dict:
    """Return the section: every row with its goal."""
    begun = time.perf_counter()
    rows = _rows(quick)
    for row in rows:
        row['verdict'] = 'met' if row.pop('met') else 'missed'
    return {
        'title': 'Late and mixed streams: through the node in lockstep, shipped settings',
        'text': ('`python -m bench.late_streams`. The node with config/params.yaml stepped on '
                 'simulated time (`mouse_constraint_ros.testing`), each pointer event delivered '
                 'its delay after it, stamped with its time (test_support/late_streams.py, '
                 "docs/dragging.md); a browser's events irregular as stream_timing.schedule "
                 'makes them. Speeds after the first second; overshoot along the drag '
                 'past the last point; wander: RMS distance of the anchor from the still '
                 "pointer's place; circle error: RMS distance to the pointer at the tick's time "
                 '(late: at the delay that fits best).'),
        'columns': [['case', 'stream', ''], ['value', 'measured', ''], ['goal', 'goal', ''],
                    ['verdict', 'verdict', '']],
        'rows': rows,
        'notes': _notes(),
        'elapsed_s': time.perf_counter() - begun,
    }


if __name__ == '__main__':
    print(json.dumps(run(quick='--quick' in sys.argv), indent=1))
