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
The haptic parameters: the force out and the coupling in N/m and N s/m (no ROS here).

``parameters.PARAMETERS`` takes ``HAPTIC_PARAMETERS`` into the node's one table;
``soft_mode`` turns ``coupling_stiffness`` and ``coupling_damping`` into the soft mode's
``frequency_hz`` and ``damping_ratio`` (``physics.mouse_joint.coupling_gains``), or passes
those through when the coupling is unused (0), and refuses a combination that means nothing,
naming the parameters and why.
"""

from typing import Any, Mapping, Tuple

from .timer_limits import FINITE_MAX
from ..physics.mouse_joint import coupling_gains, MAX_DAMPING_RATIO, MAX_FREQUENCY_HZ
from ..physics.validation import scalar

# (name, default, description, bounds), as ``parameters.ParameterSpec`` takes them.
HAPTIC_PARAMETERS: Tuple[tuple, ...] = (
    ('publish_force', False,
     'Publish the force the pointer feels (geometry_msgs/WrenchStamped on force, N, in '
     'frame_id) with every pose, with its stamp: minus the constraint impulse of the tick over '
     'dt; zero torque. Off, it costs the tick nothing.', None),
    ('coupling_stiffness', 0.0,
     'Soft mode as a spring between target and anchor (N/m), instead of frequency_hz: '
     'frequency_hz = sqrt(k / mass) / (2 pi); exact at the COM. 0 = unused.', (0.0, FINITE_MAX)),
    ('coupling_damping', 0.0,
     'With coupling_stiffness: the damper beside the spring (N s/m): damping_ratio = '
     'c / (2 sqrt(k mass)). 0 = unused (damping_ratio applies).', (0.0, FINITE_MAX)),
)


def soft_mode(values: Mapping[str, Any]) -> Tuple[float, float]:
    """
    Return (frequency_hz, damping_ratio) of parameter ``values``; raise ValueError why not.

    A coupling stiffness replaces frequency_hz (both set is refused: which one holds would be
    a guess); a coupling damping needs a stiffness (a damper alone to the target is no soft
    mode of the joint), and replaces damping_ratio. frequency_hz and damping_ratio are checked
    against their own ranges first, in the joint's words: a value no configuration takes (-1,
    .nan, .inf) is refused for what it is, as at start-up, whatever the coupling is.
    """
    frequency = scalar('frequency_hz', values['frequency_hz'], at_least=0.0,
                       at_most=MAX_FREQUENCY_HZ)
    ratio = scalar('damping_ratio', values['damping_ratio'], at_least=0.0,
                   at_most=MAX_DAMPING_RATIO)
    stiffness = scalar('coupling_stiffness', values['coupling_stiffness'], at_least=0.0)
    damping = scalar('coupling_damping', values['coupling_damping'], at_least=0.0)
    if stiffness == 0.0:
        if damping > 0.0:
            raise ValueError(
                f'coupling_damping {damping!r} N s/m needs coupling_stiffness > 0: a damper '
                'alone does not hold the anchor (set frequency_hz and damping_ratio, or both '
                'coupling gains)')
        return frequency, ratio
    if frequency != 0.0:
        raise ValueError(
            f'coupling_stiffness {stiffness!r} N/m and frequency_hz {frequency!r} both set the '
            'soft spring: set one of them (the other 0.0)')
    mass = scalar('mass', values['mass'], above=0.0)
    coupled_frequency, coupled_ratio = coupling_gains(stiffness, damping, mass)
    if not coupled_frequency <= MAX_FREQUENCY_HZ:
        raise ValueError(
            f'coupling_stiffness {stiffness!r} N/m on mass {mass!r} kg gives frequency_hz '
            f'{coupled_frequency!r}, beyond {MAX_FREQUENCY_HZ:g}: a spring the step cannot hold')
    if damping > 0.0 and not coupled_ratio <= MAX_DAMPING_RATIO:
        raise ValueError(
            f'coupling_damping {damping!r} N s/m with coupling_stiffness {stiffness!r} N/m on '
            f'mass {mass!r} kg gives damping_ratio {coupled_ratio!r}, beyond '
            f'{MAX_DAMPING_RATIO:g}')
    return coupled_frequency, coupled_ratio if damping > 0.0 else ratio
