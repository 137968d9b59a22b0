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

"""The coupling in N/m and N s/m: mapped exactly onto the soft mode, nonsense refused."""

import math

import numpy as np
import pytest

from mouse_constraint_ros.node.parameters import DEFAULTS, node_config
from mouse_constraint_ros.node.startup import describe
from mouse_constraint_ros.physics.mouse_joint import coupling_gains, soft_gains
from mouse_constraint_ros.testing import SimulatedBody

MASS = 0.2
# A body held at its COM, weightless, the joint pulling at the target itself.
PLAIN = {'mass': MASS, 'anchor': [0.0, 0.0, 0.0], 'gravity': [0.0, 0.0, 0.0],
         'max_target_speed': math.inf, 'max_target_acceleration': math.inf,
         'target_feed_forward': False}


def modes(stiffness, damping, mass):
    """Return the roots s of m s^2 + c s + k."""
    return np.roots([mass, damping, stiffness])


@pytest.mark.parametrize('stiffness, damping', [(200.0, 2.0), (800.0, 0.5), (50.0, 10.0),
                                                (3000.0, 0.0)])
def test_the_soft_step_has_the_modes_of_the_spring_and_damper(stiffness, damping):
    """The anchor error's substep map has eigenvalues exp(s h), s the modes of m, c, k."""
    frequency, ratio = coupling_gains(stiffness, damping, MASS)
    assert 2.0 * math.pi * frequency == pytest.approx(math.sqrt(stiffness / MASS), rel=1e-15)
    h = 0.0005
    a, b = soft_gains(frequency, ratio, h)
    step = np.array([[1.0 - h * b, h * (1.0 - a)], [-b, 1.0 - a]])
    eigenvalues = np.sort_complex(np.linalg.eigvals(step))
    expected = np.sort_complex(np.exp(modes(stiffness, damping, MASS) * h))
    np.testing.assert_allclose(eigenvalues, expected, rtol=1e-9, atol=1e-12)


def values(**changes):
    """Return the default parameter values with ``changes``."""
    result = dict(DEFAULTS)
    result.update(changes)
    return result


def test_the_node_maps_the_gains_and_keeps_damping_ratio_without_a_damper():
    constraint = node_config(values(mass=MASS, coupling_stiffness=200.0,
                                    coupling_damping=2.0)).settings.constraint
    assert (constraint.frequency_hz, constraint.damping_ratio) == coupling_gains(200.0, 2.0, MASS)
    constraint = node_config(values(mass=MASS, coupling_stiffness=200.0,
                                    damping_ratio=0.3)).settings.constraint
    assert constraint.damping_ratio == 0.3
    assert constraint.frequency_hz == coupling_gains(200.0, 0.0, MASS)[0]
    constraint = node_config(values(frequency_hz=5.0)).settings.constraint
    assert (constraint.frequency_hz, constraint.damping_ratio) == (5.0, 1.0)


@pytest.mark.parametrize('changes, reason', [
    ({'coupling_stiffness': 200.0, 'frequency_hz': 5.0},
     'coupling_stiffness 200.0 N/m and frequency_hz 5.0 both set the soft spring: set one'),
    ({'coupling_damping': 2.0},
     'coupling_damping 2.0 N s/m needs coupling_stiffness > 0: a damper alone'),
    ({'coupling_damping': 2.0, 'frequency_hz': 5.0},
     'coupling_damping 2.0 N s/m needs coupling_stiffness > 0'),
    ({'coupling_stiffness': -1.0}, 'coupling_stiffness must be >= 0.0, got -1.0'),
    ({'coupling_damping': math.nan, 'coupling_stiffness': 1.0},
     'coupling_damping must be finite, got nan'),
    ({'coupling_stiffness': 1e30},
     'coupling_stiffness 1e+30 N/m on mass 2.0 kg gives frequency_hz 112539539519638.27, '
     'beyond 1e+06'),
    ({'coupling_stiffness': 1e-300, 'coupling_damping': 1.0, 'mass': 1e-30},
     'coupling_damping 1.0 N s/m with coupling_stiffness 1e-300 N/m on mass 1e-30 kg gives '
     'damping_ratio inf'),
])
def test_nonsense_is_refused_with_the_reason(changes, reason):
    with pytest.raises(ValueError, match='^' + reason.replace('(', r'\(').replace('+', r'\+')):
        node_config(values(**changes))


@pytest.mark.ros
def test_through_ros_the_anchor_rings_with_the_modes_of_the_coupling():
    """
    Through ROS: after a target jump, e[n+1] = (z1 + z2) e[n] - z1 z2 e[n-1] at every tick.

    z = exp(s dt) for the modes s of m s^2 + c s + k: the error of a body held at its COM moves
    exactly as the mass m on the spring k and damper c, sampled at the ticks.
    """
    stiffness, damping = 200.0, 0.8
    with SimulatedBody(coupling_stiffness=stiffness, coupling_damping=damping, **PLAIN) as body:
        body.step(2)
        start = body.pose.position.copy()
        target = start + (0.01, -0.02, 0.005)
        body.target(target)
        errors = []
        for _ in range(400):
            body.step()
            errors.append(body.pose.position - target)
        z1, z2 = np.exp(modes(stiffness, damping, MASS) * 0.001)
        errors = np.array(errors)
        residual = errors[2:] - (z1 + z2).real * errors[1:-1] + (z1 * z2).real * errors[:-2]
        assert np.abs(residual).max() < 1e-12
        assert np.abs(errors).max() > 0.01
        with pytest.raises(ValueError, match='both set the soft spring'):
            body.set_parameters(frequency_hz=3.0)


def test_the_start_line_names_the_coupling_in_newtons():
    line = describe(node_config(values(mass=MASS, coupling_stiffness=300.0,
                                       coupling_damping=3.0)))
    assert 'damping ratio 0.193649 (at the COM 300 N/m, 3 N s/m)' in line


@pytest.mark.ros
@pytest.mark.parametrize('frequency', [-1.0, math.nan, math.inf])
def test_a_frequency_no_configuration_takes_is_refused_for_itself_at_run_time_as_at_start(
        frequency):
    """
    frequency_hz -1, .nan or .inf with coupling_stiffness set: the run-time reason is start-up's.

    At start-up the value is refused for its range before the coupling is looked at; a change at
    run time, with the coupling set, says the same, not that both set the soft spring.
    """
    from mouse_constraint_ros.node.startup import StartupRefusal

    with pytest.raises(StartupRefusal) as start:
        SimulatedBody(coupling_stiffness=200.0, frequency_hz=frequency, **PLAIN)
    assert 'frequency_hz must be' in str(start.value)
    with SimulatedBody(coupling_stiffness=200.0, **PLAIN) as body:
        with pytest.raises(ValueError) as change:
            body.set_parameters(frequency_hz=frequency)
    assert str(change.value) == str(start.value)
