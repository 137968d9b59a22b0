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
coupling).
Deterministic: the same numbers on every run and machine load (about 1 min).

Standalone: ``python -m bench.haptic_stability`` prints a Markdown table.
"""

import math

from mouse_constraint_ros.physics.coupling_stability import (Device, largest_stable_stiffness,
                                                             passive_stiffness)
from test_support.haptic_device import coupling, HAND, loop, measure_largest_stable

# (m_d kg, b_d N s/m, coupling damping N s/m, delay ticks): those of test_haptic_stability.py.
CASES = ((0.045, 0.05, 0.5, 0), (0.2, 0.02, 2.0, 0), (0.1, 0.5, 0.5, 1))


def main() -> None:
    """Print the table."""
    print('| m_d (kg) | b_d (N s/m) | c (N s/m) | delay (ticks) | predicted (N/m) | measured '
          '(N/m) | measured / predicted | passive (N/m) |')
    print('| --- | --- | --- | --- | --- | --- | --- | --- |')
    for mass, damping, coupling_damping, delay in CASES:
        device = Device(mass, damping, **HAND)
        predicted = largest_stable_stiffness(**loop(device, coupling_damping, delay))
        low, high, _ = measure_largest_stable(predicted, coupling_damping, device, delay)
        passive = passive_stiffness(device_damping=damping + device.hand_damping,
                                    **coupling(coupling_damping, delay))
        print(f'| {mass} | {damping} | {coupling_damping} | {delay} | {predicted:.0f} | '
              f'{low:.0f} - {high:.0f} | {math.sqrt(low * high) / predicted:.3f} | '
              f'{passive:.0f} |')


if __name__ == '__main__':
    main()
