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
Which fit of stamped points: the core replay of a browser's stamped drag for each estimator.

The drags of ``bench.stream_timing`` (a 1 m/s circle of radius 0.25 m, at 20 and 60 Hz, with a
browser's irregular timing), stamped, replayed on the core through the node's timing path
(``test_support.stream_timing.replay``, no ROS), for estimators of the stamped stream's velocity
given as overrides of ``physics.target_stream``'s constants, each with exact stamps, with
stamps off by up to 0.5 ms (a coarse clock) and with positions on a 1.5 mm grid (screen
pixels). Pure core and seeded: the same numbers on every run. docs/dragging.md says why the
shipped estimator is the one it is.

``python -m bench.stream_estimators [--quick]`` (from the repository's root) prints the table;
``make bench`` runs it as a section (``--quick``: exact stamps only).
"""

import sys
import time

from test_support.stream_timing import RATES_HZ, replay, SECONDS

# Estimators for stamped streams, as overrides of physics.target_stream's constants.
ESTIMATORS = [
    ('parabola over 0.4 s', {'STAMPED_DEGREE': 2, 'BLEND_INTERVALS': 0.0}),
    ('cubic over 0.4 s', {'STAMPED_DEGREE': 3, 'BLEND_INTERVALS': 0.0}),
    ('quartic over 0.4 s', {'BLEND_INTERVALS': 0.0}),
    ('quartic over 0.3 s, blended over 1 interval', {'STAMPED_WINDOW': 0.3}),
    ('shipped: quartic over 0.4 s, blended over 1 interval', {}),
]
# (label, replay keywords): exact stamps, stamps off by up to 0.5 ms, 1.5 mm pixels.
CONDITIONS = [('exact', {}), ('stamps +-0.5 ms', {'stamp_noise': 0.0005}),
              ('1.5 mm pixels', {'pixel': 0.0015})]


def cells(overrides: dict, conditions, seconds: float = SECONDS) -> dict:
    """Return ``{column: 'error mm, speed deviation %'}`` of one estimator over the drags."""
    from mouse_constraint_ros.physics import target_stream
    saved = {key: getattr(target_stream, key) for key in overrides}
    row = {}
    try:
        for key, value in overrides.items():
            setattr(target_stream, key, value)
        for rate in RATES_HZ:
            for label, keywords in conditions:
                r = replay(rate, True, seconds, **keywords)
                row[f'{rate:g} Hz, {label}'] = (f'{r.error * 1e3:.2g} mm, '
                                                f'{r.speed_deviation * 100:.2g} %')
    finally:
        for key, value in saved.items():
            setattr(target_stream, key, value)
    return row


def run(quick: bool = False) -> dict:
    """Return the section: one row per estimator, a column per rate and condition."""
    began = time.perf_counter()
    conditions = CONDITIONS[:1] if quick else CONDITIONS
    rows = [{'estimator': name, **cells(overrides, conditions)}
            for name, overrides in ESTIMATORS]
    columns = [['estimator', 'stamped estimator', '']] + [
        [f'{rate:g} Hz, {label}', f'{rate:g} Hz, {label}', '']
        for rate in RATES_HZ for label, _ in conditions]
    return {
        'title': "Which fit of stamped points: a browser's drag replayed on the core",
        'text': ('Command: `python -m bench.stream_estimators`. The stamped drags of '
                 '`bench.stream_timing` replayed on the core (no ROS), for each estimator of '
                 'the stream; each cell: anchor RMS error, speed RMS deviation '
                 '(docs/dragging.md). Seeded: the same numbers on every run.'),
        'columns': columns,
        'rows': rows,
        'elapsed_s': time.perf_counter() - began,
    }


def main() -> None:
    """Print the table."""
    from bench.common import section_markdown
    print(section_markdown(run(quick='--quick' in sys.argv)))


if __name__ == '__main__':
    main()
