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
The haptic loop's largest stable stiffness: predicted, measured in lockstep, and the passive one.

For each simulated device (handle mass m_d, damping b_d, held by a hand of 100 N/m and 1 N s/m),
coupling damping c and delay d: the largest stable coupling stiffness the loop's polynomial
predicts (``physics.coupling_stability``), the bracket a bisection of the node in lockstep finds
(``test_support.haptic_device.measure_largest_stable``, five halvings between 0.75 and 1.3
times the prediction), and the largest passive one for b = b_d + c_h
(``coupling_passivity_damping``: Colgate and Schenkel's condition on the body behind the
coupling). Deterministic: the same numbers on every run and machine load.

``python -m bench.haptic_stability`` (from the repository's root) prints the table; ``make
bench`` runs it as a section (``--quick``: the first device only).
"""

import math
import sys
import time

from mouse_constraint_ros.physics.coupling_stability import (Device, largest_stable_stiffness,
                                                             passive_stiffness)
from test_support.haptic_device import coupling, HAND, loop, measure_largest_stable

# (m_d kg, b_d N s/m, coupling damping N s/m, delay ticks): those of test_haptic_stability.py.
CASES = ((0.045, 0.05, 0.5, 0), (0.2, 0.02, 2.0, 0), (0.1, 0.5, 0.5, 1))
COLUMNS = [['mass', 'm_d (kg)', 'g'], ['damping', 'b_d (N s/m)', 'g'],
           ['coupling_damping', 'c (N s/m)', 'g'], ['delay', 'delay (ticks)', 'd'],
           ['predicted', 'predicted (N/m)', '.0f'], ['measured', 'measured (N/m)', ''],
           ['ratio', 'measured / predicted', '.3f'], ['passive', 'passive (N/m)', '.0f']]


def measure(mass: float, damping: float, coupling_damping: float, delay: int) -> dict:
    """Return one row: the predicted, measured and passive stiffness of one device."""
    device = Device(mass, damping, **HAND)
    predicted = largest_stable_stiffness(**loop(device, coupling_damping, delay))
    low, high, _ = measure_largest_stable(predicted, coupling_damping, device, delay)
    passive = passive_stiffness(device_damping=damping + device.hand_damping,
                                **coupling(coupling_damping, delay))
    return {'mass': mass, 'damping': damping, 'coupling_damping': coupling_damping,
            'delay': delay, 'predicted': predicted, 'low': low, 'high': high,
            'measured': f'{low:.0f} - {high:.0f}', 'ratio': math.sqrt(low * high) / predicted,
            'passive': passive}


def run(quick: bool = False) -> dict:
    """Return the section: one row per device of ``CASES``."""
    began = time.perf_counter()
    rows = [measure(*case) for case in CASES[:1 if quick else None]]
    return {
        'title': 'Haptic coupling: the largest stable stiffness, predicted and measured',
        'text': ('Command: `python -m bench.haptic_stability`. Body 0.2 kg at 1 kHz with 2 '
                 'substeps, anchor at the COM, gravity off; the device a handle of mass m_d and '
                 'damping b_d held by a hand of 100 N/m and 1 N s/m, in lockstep with the node '
                 "(docs/haptics.md). Predicted: the first root of the loop's polynomial to leave "
                 'the unit circle; measured: the bracket of five halvings of a bisection between '
                 "0.75 and 1.3 times the prediction; passive: Colgate and Schenkel's condition "
                 'for b = b_d + c_h.'),
        'columns': COLUMNS,
        'rows': rows,
        'notes': [
            'Deterministic: the same numbers on every run and machine load. '
            '`test/test_haptic_stability.py` holds each bracket within 2 % wide and its middle '
            'within 5 % of the prediction, and the passive stiffness stable.',
        ],
        'elapsed_s': time.perf_counter() - began,
    }


def main() -> None:
    """Print the table."""
    from bench.common import section_markdown
    print(section_markdown(run(quick='--quick' in sys.argv)))


if __name__ == '__main__':
    main()
