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

"""Determinism, validation of every setting and input, and the core's independence of ROS."""

import dataclasses
import math
import subprocess
import sys

import pytest

from mouse_constraint_ros.physics import (BodyState, MouseConstraint, MouseSimulation, RigidBody,
                                          Settings)

BOX = RigidBody.solid_box(2.0, (0.4, 0.2, 0.1))
NAN, INF = math.nan, math.inf


def drive(sim: MouseSimulation) -> list:
    """Step through a target that appears, moves, jumps and disappears; return the states."""
    states = []
    for i in range(600):
        if i == 50:
            sim.target = (0.3, 0.1, 0.2)
        elif 50 < i < 300:
            sim.target = (0.3 + 0.001 * i, 0.1, 0.2 + 0.0005 * i)
        elif i == 300:
            sim.target = (-1.0, 2.0, 0.5)
        elif i == 450:
            sim.target = None
        states.append(sim.step(0.002))
    return states


def test_same_inputs_give_bit_identical_outputs():
    """Test 8: two simulations fed the same inputs agree to the last bit, stepped interleaved."""
    settings = Settings(BOX, MouseConstraint(anchor=(0.2, 0.1, 0.05), frequency_hz=4.0,
                                             damping_ratio=0.5, max_force=40.0),
                        linear_damping=0.1, angular_damping=0.2, substeps=3)
    initial = BodyState(angular_velocity=(0.5, -1.0, 2.0))
    first, second = MouseSimulation(settings, initial), MouseSimulation(settings, initial)
    assert drive(first) == drive(second)
    assert first.constraint_force == second.constraint_force


def test_reset_returns_to_the_initial_state_and_drops_the_target():
    """Reset restores the initial state exactly and leaves a free body."""
    initial = BodyState((1.0, 2.0, 3.0), (0.0, 0.0, math.sin(0.3), math.cos(0.3)))
    sim = MouseSimulation(Settings(BOX), initial)
    drive(sim)
    sim.target = (0.0, 0.0, 0.0)
    sim.reset()
    assert sim.state == initial
    assert sim.target is None
    assert sim.constraint_force == (0.0, 0.0, 0.0)
    assert drive(sim) == drive(MouseSimulation(Settings(BOX), initial))


@pytest.mark.parametrize('build, field, value', [
    (lambda: RigidBody(0.0, BOX.inertia), 'mass', '0.0'),
    (lambda: RigidBody(-1.0, BOX.inertia), 'mass', '-1.0'),
    (lambda: RigidBody(NAN, BOX.inertia), 'mass', 'nan'),
    (lambda: RigidBody(INF, BOX.inertia), 'mass', 'inf'),
    (lambda: RigidBody(1.0, (1.0, 0.0, 0.0, 1.0, 0.0)), 'inertia', '1.0, 0.0, 0.0, 1.0, 0.0'),
    (lambda: RigidBody(1.0, (1.0, 0.0, 0.0, 1.0, 0.0, NAN)), 'inertia', 'nan'),
    (lambda: RigidBody(1.0, (1.0, 0.0, 0.0, 1.0, 0.0, -1.0)), 'inertia', 'positive definite'),
    (lambda: RigidBody(1.0, (1.0, 2.0, 0.0, 1.0, 0.0, 1.0)), 'inertia', 'positive definite'),
    (lambda: RigidBody(1.0, (1.0, 0.0, 0.0, 1.0, 0.0, 3.0)), 'inertia', 'triangle'),
    (lambda: RigidBody(1.0, 'heavy'), 'inertia', "'heavy'"),
    (lambda: RigidBody.solid_box(1.0, (0.1, 0.0, 0.1)), 'extents', '0.0'),
    (lambda: MouseConstraint(anchor=(0.0, NAN, 0.0)), 'anchor', 'nan'),
    (lambda: MouseConstraint(anchor=(0.0, 0.0)), 'anchor', '(0.0, 0.0)'),
    (lambda: MouseConstraint(baumgarte=0.0), 'baumgarte', '0.0'),
    (lambda: MouseConstraint(baumgarte=1.5), 'baumgarte', '1.5'),
    (lambda: MouseConstraint(frequency_hz=-1.0), 'frequency_hz', '-1.0'),
    (lambda: MouseConstraint(frequency_hz=INF), 'frequency_hz', 'inf'),
    (lambda: MouseConstraint(damping_ratio=-0.1), 'damping_ratio', '-0.1'),
    (lambda: MouseConstraint(max_force=0.0), 'max_force', '0.0'),
    (lambda: MouseConstraint(max_force=-INF), 'max_force', '-inf'),
    (lambda: MouseConstraint(max_force=NAN), 'max_force', 'nan'),
    (lambda: Settings(BOX, gravity=(0.0, 0.0, INF)), 'gravity', 'inf'),
    (lambda: Settings(BOX, linear_damping=-1.0), 'linear_damping', '-1.0'),
    (lambda: Settings(BOX, angular_damping=NAN), 'angular_damping', 'nan'),
    (lambda: Settings(BOX, substeps=0), 'substeps', '0'),
    (lambda: Settings(BOX, substeps=2.5), 'substeps', '2.5'),
    (lambda: Settings(BOX, substeps=True), 'substeps', 'True'),
    (lambda: Settings('box'), 'body', "'box'"),
    (lambda: Settings(BOX, constraint=None), 'constraint', 'None'),
    (lambda: BodyState(orientation=(0.0, 0.0, 0.0, 2.0)).validated(), 'orientation', '2.0'),
    (lambda: BodyState(position=(NAN, 0.0, 0.0)).validated(), 'position', 'nan'),
    (lambda: BodyState(linear_velocity=(0.0, INF, 0.0)).validated(), 'linear_velocity', 'inf'),
    (lambda: BodyState(angular_velocity=(0.0, 0.0)).validated(), 'angular_velocity', '(0.0, 0.0)'),
    (lambda: RigidBody(1e-300, BOX.inertia), 'mass', '1e-300'),
    (lambda: RigidBody(1e300, BOX.inertia), 'mass', '1e+300'),
    (lambda: RigidBody(1.0, (1e-110, 0.0, 0.0, 1e-110, 0.0, 1e-110)), 'inertia', '1e-110'),
    (lambda: RigidBody(1.0, (1e100, 0.0, 0.0, 1e100, 0.0, 1e100)), 'inertia', '1e+100'),
    (lambda: RigidBody.solid_box(1.0, (1e200, 1.0, 1.0)), 'extents', '1e+200'),
    (lambda: RigidBody.solid_box(1.0, (1e-120, 1e-120, 1e-120)), 'extents', '1e-120'),
    (lambda: MouseConstraint(anchor=(0.0, 1e200, 0.0)), 'anchor', '1e+200'),
    (lambda: Settings(BOX, MouseConstraint(anchor=(1e8, 0.0, 0.0))), 'anchor', '1e+08'),
    (lambda: Settings(BOX, gravity=(1e308, 0.0, 0.0)), 'gravity', '1e+308'),
    (lambda: BodyState(position=(0.0, 0.0, 1e200)).validated(), 'position', '1e+200'),
])
def test_every_invalid_setting_raises_naming_field_and_value(build, field, value):
    """Test 8: ValueError whose message names the field and shows the value."""
    with pytest.raises(ValueError) as raised:
        build()
    assert field in str(raised.value)
    assert value in str(raised.value)


def test_messages_name_the_fields_with_a_prefix_and_show_plain_numbers():
    """A state names its fields with ``prefix``; arrays are shown as lists of numbers."""
    from array import array
    with pytest.raises(ValueError, match=r'^initial_orientation .*\(0\.0, 0\.0, 0\.0, 2\.0\)'):
        BodyState(orientation=array('d', [0.0, 0.0, 0.0, 2.0])).validated(prefix='initial_')
    with pytest.raises(ValueError, match=r'^initial_position .*\[1\.0, 2\.0\]'):
        BodyState(position=array('d', [1.0, 2.0])).validated(prefix='initial_')


def test_a_thin_plate_is_the_limit_of_realizable():
    """I3 = I1 + I2 exactly (a flat plate) is accepted; slightly beyond is not."""
    RigidBody(1.0, (1.0, 0.0, 0.0, 2.0, 0.0, 3.0))
    with pytest.raises(ValueError, match='triangle'):
        RigidBody(1.0, (1.0, 0.0, 0.0, 2.0, 0.0, 3.001))


@pytest.mark.parametrize('change', [
    lambda sim: setattr(sim, 'target', (0.0, NAN, 0.0)),
    lambda sim: setattr(sim, 'target', (0.0, 0.0, INF)),
    lambda sim: setattr(sim, 'target', (1.0, 2.0)),
    lambda sim: sim.step(0.0),
    lambda sim: sim.step(-0.001),
    lambda sim: sim.step(NAN),
    lambda sim: sim.step(INF),
    lambda sim: setattr(sim, 'settings', dataclasses.replace(sim.settings, substeps=-1)),
    lambda sim: setattr(sim, 'settings', 'fast'),
    lambda sim: sim.set_state(BodyState(orientation=(1.0, 1.0, 0.0, 0.0))),
])
def test_invalid_inputs_change_nothing(change):
    """Test 8: after a rejected input the simulation continues exactly as if it never came."""
    settings = Settings(BOX, MouseConstraint(anchor=(0.2, 0.1, 0.05), frequency_hz=3.0))
    touched, untouched = MouseSimulation(settings), MouseSimulation(settings)
    for sim in (touched, untouched):
        sim.target = (0.5, 0.0, 0.0)
        for _ in range(10):
            sim.step(0.001)
    with pytest.raises(ValueError):
        change(touched)
    assert touched.settings is untouched.settings or touched.settings == untouched.settings
    assert touched.target == untouched.target
    assert touched.state == untouched.state
    for _ in range(10):
        assert touched.step(0.001) == untouched.step(0.001)


def test_a_nearly_unit_orientation_is_normalized_exactly():
    """A quaternion within 1e-6 of unit norm is accepted and normalized."""
    sim = MouseSimulation(Settings(BOX), BodyState(orientation=(0.0, 0.0, 0.0, 1.0000005)))
    assert sim.state.orientation == (0.0, 0.0, 0.0, 1.0)


@pytest.mark.system
def test_the_core_imports_without_rclpy():
    """The physics package imports numpy and the standard library only."""
    code = ('import sys, mouse_constraint_ros.physics; '
            'print(sorted(m for m in sys.modules if m.split(".")[0] in '
            '("rclpy", "geometry_msgs", "std_msgs", "scipy")))')
    result = subprocess.run([sys.executable, '-c', code], capture_output=True, text=True,
                            check=True)
    assert result.stdout.strip() == '[]'
