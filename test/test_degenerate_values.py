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
Degenerate parameter values: each is refused with its reason, or the step handles it.

The node validates with ``node_config`` at start-up and in its set-parameters callback,
so a ValueError there is a refusal with a reason; anything it accepts must step without raising
and stay finite, at the smallest and the largest step the core allows, for a target near the
anchor and one at the far end of the workspace, in rigid and in soft mode. Hypothesis draws the
values over the whole float exponent range, 1e-320 to 1e308, with a fixed seed.
"""

from array import array
import dataclasses
import math

from hypothesis import event, given, HealthCheck, settings, strategies as st
import numpy as np
import pytest

from mouse_constraint_ros.node.parameters import DEFAULTS, node_config, PARAMETERS
from mouse_constraint_ros.physics import BodyState, MouseSimulation, RigidBody, Settings
from mouse_constraint_ros.physics.gyroscopic import gyroscopic_step
from mouse_constraint_ros.physics.limits import (MAX_ACCELERATION, MAX_CONDITION, MAX_DISTANCE,
                                                 MAX_MASS, MAX_MOMENT, MIN_MASS, MIN_MOMENT)
from mouse_constraint_ros.physics.limits import MAX_STEP, MIN_STEP

REPRODUCIBLE = settings(derandomize=True, database=None, deadline=None,
                        suppress_health_check=[HealthCheck.too_slow])
# The far target: at the workspace's largest radius.
FAR = MAX_DISTANCE
STEPS = 6
# Released, the body is free: each step is the free step of the one before it (gravity adds at
# most MAX_ACCELERATION h to v, damping only slows it, the free rotation never gains energy and
# the orientation is normalized every step), and the ranges of physics.limits leave margins of
# 1e30 and more, a free fall taking 1e148 s to leave the float range. The release's own step and
# one free step from the state it left assert what more free steps would; at MAX_STEP each costs
# a thousand pieces of rotation.
RELEASED_STEPS = 2


def configured(**overrides):
    """Return the configuration of the defaults with ``overrides``, or the ValueError raised."""
    try:
        return node_config(dict(DEFAULTS, **overrides))
    except ValueError as error:
        return error


def refused(name: str, **overrides) -> str:
    """Return the message refusing ``overrides``; fail unless it is one line naming ``name``."""
    result = configured(**overrides)
    assert isinstance(result, ValueError), f'{overrides!r} accepted'
    message = str(result)
    assert name in message, message
    assert '\n' not in message and '\r' not in message, message
    assert 'array(' not in message, message
    return message


def problems(sim: MouseSimulation) -> str:
    """Return what is not finite or not unit in ``sim``'s state, force and energy, or ''."""
    state = sim.state
    values = [v for part in state for v in part] + list(sim.constraint_force)
    if not all(math.isfinite(v) for v in values + [sim.kinetic_energy()]):
        return f'non-finite: {state!r}, force {sim.constraint_force!r}'
    if abs(math.hypot(*state.orientation) - 1.0) > 1e-12:
        return f'|q| = {math.hypot(*state.orientation)!r}'
    return ''


def drive(config) -> None:
    """
    Step ``config`` through every case; fail on an exception or a problem.

    Step sizes MIN_STEP and MAX_STEP (the node's 1e-7 s and 1 s lie within), rigid and soft
    (the configured mode and the other one), each from the initial state: the initial anchor
    held, a target 1 mm from it, then one FAR away (STEPS each), then released
    (RELEASED_STEPS).
    """
    constraint = config.settings.constraint
    modes = [constraint, dataclasses.replace(
        constraint, frequency_hz=10.0 if constraint.rigid else 0.0)]
    direction = np.array([0.6, -0.8, 0.0])
    for h in (MIN_STEP, MAX_STEP):
        for mode in modes:
            settings = dataclasses.replace(config.settings, constraint=mode, substeps=1)
            sim = MouseSimulation(settings, config.initial_state)
            anchor = config.initial_anchor()
            far = tuple(FAR * direction)
            for target in (anchor, tuple(np.add(anchor, 1e-3 * direction)), far, None):
                sim.target = target
                for i in range(STEPS if target is not None else RELEASED_STEPS):
                    try:
                        sim.step(h)
                    except Exception as error:  # noqa: B902 (any exception is the failure)
                        pytest.fail(f'h {h!r}, {mode!r}, target {target!r}, step {i}: '
                                    f'{type(error).__name__}: {error}')
                    assert not problems(sim), \
                        f'h {h!r}, {mode!r}, target {target!r}, step {i}: {problems(sim)}'


def decades(low: int, high: int) -> st.SearchStrategy:
    """Return positive floats spread evenly over the decades 10^low .. 10^(high + 1)."""
    return st.builds(lambda e, m: m * 10.0 ** e, st.integers(low, high),
                     st.floats(1.0, 10.0, exclude_max=True)).filter(lambda v: 0.0 < v < math.inf)


# Magnitudes over the whole float range, subnormals included, or within the decades around the
# bounds (1e-100 .. 1e100) or around the defaults, where acceptance turns on their relations.
MAGNITUDES = st.one_of(decades(-320, 308), decades(-110, 110), decades(-15, 15))
SIGNED = st.one_of(st.just(0.0), MAGNITUDES, MAGNITUDES.map(lambda v: -v))
VECTORS = st.lists(SIGNED, min_size=3, max_size=3)
# Within a factor 10 or 1000 of each other: a box or moments that can be well conditioned.
FACTORS = st.lists(st.floats(-1.0, 1.0).map(lambda e: 10.0 ** e), min_size=3, max_size=3)
SPREAD = st.lists(st.floats(-3.0, 3.0).map(lambda e: 10.0 ** e), min_size=3, max_size=3)
# An orthonormal basis off the body axes.
AXES = np.linalg.qr(np.array([[1.0, 2.0, 0.5], [-0.3, 1.0, 2.0], [0.7, -1.0, 1.0]]))[0]


def sizes() -> st.SearchStrategy:
    """Return box sizes: any three numbers, or positive edges of one scale within 1:10."""
    return st.one_of(VECTORS, st.builds(lambda s, f: [s * c for c in f], MAGNITUDES, FACTORS))


@st.composite
def inertias(draw) -> list:
    """Return inertias: any six numbers, or moments of one scale (a box's), on or off the axes."""
    if draw(st.integers(0, 2)) == 0:
        return draw(st.lists(SIGNED, min_size=6, max_size=6))
    x, y, z = draw(st.one_of(FACTORS, SPREAD))
    scale = draw(MAGNITUDES)
    moments = [scale * (y * y + z * z), scale * (x * x + z * z), scale * (x * x + y * y)]
    if draw(st.booleans()):
        return [moments[0], 0.0, 0.0, moments[1], 0.0, moments[2]]
    m = AXES @ np.diag(moments) @ AXES.T
    return [m[0, 0], m[0, 1], m[0, 2], m[1, 1], m[1, 2], m[2, 2]]


VALUES = {
    'mass': SIGNED,
    'box_size': sizes(),
    'inertia': inertias(),
    'anchor': VECTORS,
    'initial_position': VECTORS,
    'gravity': VECTORS,
    'linear_damping': SIGNED,
    'angular_damping': SIGNED,
    'frequency_hz': SIGNED,
    'damping_ratio': SIGNED,
    'baumgarte': SIGNED,
    'max_force': SIGNED,
    'coupling_stiffness': SIGNED,
}


@pytest.mark.parametrize('name', list(VALUES))
def test_any_value_of_one_parameter_is_refused_naming_it_or_steps_finite(name):
    """
    One parameter drawn over the whole exponent range, the others at their defaults.

    Each value is refused with a one-line ValueError naming the parameter, or accepted and then
    every case of ``drive`` raises nothing and stays finite.
    """
    @settings(REPRODUCIBLE, max_examples=200)
    @given(VALUES[name])
    def check(value):
        result = configured(**{name: value})
        event('refused' if isinstance(result, ValueError) else 'accepted')
        if isinstance(result, ValueError):
            message = str(result)
            assert name in message and '\n' not in message, message
        else:
            drive(result)

    check()


def near(low: int, high: int, size: int = 3) -> st.SearchStrategy:
    """Return ``size`` signed values of one scale in 10^low .. 10^high, spread up to 1:1e6."""
    signs = st.lists(st.sampled_from([-1.0, 0.0, 1.0]), min_size=size, max_size=size)
    return st.builds(lambda s, f, g: [s * a * b for a, b in zip(f, g)], decades(low, high),
                     SPREAD, signs)


@settings(REPRODUCIBLE, max_examples=300)
@given(st.fixed_dictionaries({
    'mass': decades(-105, 105),
    'box_size': st.builds(lambda s, f: [s * c for c in f], decades(-60, 12), SPREAD),
    'inertia': st.one_of(st.just([0.0] * 6), inertias()),
    'anchor': near(-320, 12), 'initial_position': near(-320, 12), 'gravity': near(-320, 12),
    'frequency_hz': st.one_of(st.just(0.0), decades(-320, 6)),
    'damping_ratio': st.one_of(st.just(0.0), decades(-320, 6)),
    'linear_damping': decades(-320, 308), 'angular_damping': decades(-320, 308)}))
def test_any_combination_is_refused_or_steps_finite(values):
    """
    All of them drawn at once, near and beyond their bounds: whatever is accepted steps finite.

    The ranges of single parameters are not enough on their own (a far anchor on a light, thin
    body makes the effective mass singular); the refusal names one of the parameters drawn.
    """
    result = configured(**values)
    event('refused' if isinstance(result, ValueError) else 'accepted')
    if isinstance(result, ValueError):
        message = str(result)
        assert any(name in message for name in values) and '\n' not in message, message
    else:
        drive(result)


@pytest.mark.parametrize('name, value', [
    ('mass', 1e-300),
    ('mass', 1e-160),
    ('mass', 1e300),
    ('box_size', [1e-120, 1e-120, 1e-120]),
    ('box_size', [1e200, 1e200, 1e200]),
    ('box_size', [1.0, 1e-7, 1e-7]),
    ('inertia', [1e-110, 0.0, 0.0, 1e-110, 0.0, 1e-110]),
    ('inertia', [1e100, 0.0, 0.0, 1e100, 0.0, 1e100]),
    ('gravity', [1e308, 0.0, 0.0]),
    ('anchor', [1e200, 0.0, 0.0]),
    ('anchor', [1e8, 0.0, 0.0]),
    ('initial_position', [1e200, 0.0, 0.0]),
])
def test_the_values_users_saw_crash_the_node_are_refused(name, value):
    """Each of these once passed validation and then crashed or overflowed the step."""
    message = refused(name, **{name: value})
    assert 'math domain error' not in message


def test_the_bounds_are_where_the_float_arithmetic_needs_them():
    """The bounds themselves step finite (a heavy and a light box at the edges of the ranges)."""
    for mass in (MIN_MASS, MAX_MASS):
        # A cube whose moments are the smallest (largest) allowed, anchored at the farthest
        # point its effective mass allows.
        moment = MIN_MOMENT if mass == MIN_MASS else MAX_MOMENT
        reach = 0.999 * math.sqrt((MAX_CONDITION - 1.0) * moment / mass)
        anchor = [min(reach, 0.999 * MAX_DISTANCE), 0.0, 0.0]
        config = configured(mass=mass, inertia=[moment, 0.0, 0.0, moment, 0.0, moment],
                            anchor=anchor, gravity=[0.0, 0.0, -MAX_ACCELERATION])
        assert not isinstance(config, ValueError), config
        drive(config)


def test_a_mass_or_moment_just_outside_the_ranges_is_refused():
    """Just below MIN_MASS, above MAX_MASS, and moments just outside theirs."""
    cube = [1.0, 0.0, 0.0, 1.0, 0.0, 1.0]
    refused('mass', mass=MIN_MASS * 0.99, inertia=cube)
    refused('mass', mass=MAX_MASS * 1.01, inertia=cube)
    refused('inertia', inertia=[0.99 * MIN_MOMENT, 0.0, 0.0, MIN_MOMENT, 0.0, MIN_MOMENT])
    refused('inertia', inertia=[MAX_MOMENT, 0.0, 0.0, MAX_MOMENT, 0.0, 1.01 * MAX_MOMENT])
    refused('gravity', gravity=[0.0, 1.01 * MAX_ACCELERATION, 0.0])


def test_the_anchor_is_refused_where_the_effective_mass_is_ill_conditioned():
    """1 + m |r|^2 / I_min may reach MAX_CONDITION and not exceed it; the message says why."""
    config = node_config(DEFAULTS)
    body = config.settings.body
    reach = math.sqrt((MAX_CONDITION - 1.0) * body.principal_moments[0] / body.mass)
    assert not isinstance(configured(anchor=[0.0, 0.0, 0.999 * reach]), ValueError)
    message = refused('anchor', anchor=[0.0, 0.0, 1.001 * reach])
    assert 'box_size' in message and 'mass' in message and 'condition number' in message
    # The core refuses it too, naming the anchor.
    with pytest.raises(ValueError, match='anchor'):
        Settings(body, dataclasses.replace(config.settings.constraint,
                                           anchor=(0.0, 0.0, 1.001 * reach)))


def test_a_box_whose_inertia_is_invalid_is_refused_naming_box_size_and_mass():
    """A needle too thin for the conditioning, or a box too light: box_size and mass named."""
    for box, mass in (([1.0, 1e-7, 1e-7], 2.0), ([1e-40, 1e-40, 1e-40], 2.0),
                      ([0.4, 0.2, 0.1], 1e-95)):
        message = refused('box_size', box_size=box, mass=mass)
        assert 'mass' in message, message


def test_double_arrays_from_rclpy_are_shown_as_plain_lists():
    """Double arrays come from rclpy as array.array: messages show the numbers, not the repr."""
    message = refused('anchor', anchor=array('d', [0.1, 0.2]))
    assert '[0.1, 0.2]' in message, message
    message = refused('inertia', inertia=np.zeros((2, 3)))
    assert '[[0.0, 0.0, 0.0], [0.0, 0.0, 0.0]]' in message, message


def test_gravity_beyond_the_bound_is_refused_with_a_reason_not_a_math_domain_error():
    """gravity:=[1.0e+308, 0, 0] once passed and made the first step raise a math domain error."""
    message = refused('gravity', gravity=[1.0e308, 0.0, 0.0])
    assert f'{MAX_ACCELERATION:g}' in message, message


def test_frame_id_with_a_leading_slash_is_refused():
    """tf2 refuses frame ids that start with '/'; the message says so and suggests the fix."""
    message = refused('frame_id', frame_id='/world')
    assert 'slash' in message and "'world'" in message, message
    assert node_config(dict(DEFAULTS, frame_id='world/child')).frame_id == 'world/child'


# One invalid value of every parameter, and what the message must name.
INVALID = {
    'rate_hz': 0.0,
    'substeps': 0,
    'frame_id': '',
    'mass': -1.0,
    'box_size': [0.0, 1.0, 1.0],
    'inertia': [1.0, 0.0, 0.0, 1.0, 0.0, 3.0],
    'anchor': [math.nan, 0.0, 0.0],
    'initial_position': [0.0, math.inf, 0.0],
    'initial_orientation': [0.0, 0.0, 0.0, 2.0],
    'hold_initial_anchor': 'yes',
    'gravity': [0.0, 0.0],
    'baumgarte': 2.0,
    'frequency_hz': -1.0,
    'damping_ratio': -1.0,
    'max_force': 0.0,
    'linear_damping': -1.0,
    'angular_damping': math.nan,
    'workspace_radius': 0.0,
    'target_timeout': -1.0,
    'marker_rate_hz': -1.0,
    'diagnostics_rate_hz': -1.0,
    'diagnostics_anchor_warn': 0.0,
    'diagnostics_anchor_error': 0.01,
    'grab_margin': -1.0,
    'publish_rate_hz': 2000.0,
    'publish_tf': 1,
    'publish_odometry': 'yes',
    'body_frame_id': 'world',
    'robot_description': '<robot name="r"><link name="a"/>',
    'body_link': 'gripper',
    'robot_description_file': 3,
    'density': -1.0,
    'base': 'hovering',
    'base_pose': [0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0],
    'initial_joint_positions': [math.nan],
    'tracked_link': 'tool',
    'publish_clock': 'yes',
    'real_time_factor': -1.0,
    'wrench_timeout': math.nan,
    'max_wrench_force': -1.0,
    'max_wrench_torque': -math.inf,
    'max_force_per_weight': 0.0,
    'angular_friction': -1.0,
    'gravity_feed_forward': 1,
    'max_target_speed': 0.0,
    'max_target_acceleration': -1.0,
    'target_feed_forward': 'yes',
    'floor': 'yes',
    'floor_height': math.nan,
    'friction': -1.0,
    'restitution': 1.5,
    'restitution_threshold': -1.0,
    'contact_iterations': 0,
    'contact_margin': 0.0,
    'contact_slop': -1.0,
    'publish_force': 'yes',
    'coupling_stiffness': -1.0,
    'coupling_damping': math.inf,
    'force_output': 'wrenches',
    'device_frame_id': 3,
    'device_scale': 0.0,
    'device_pose': [0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0],
    'device_force_scale': math.nan,
    'device_timeout': -1.0,
    'tick_source': 'device',
}


def test_the_table_of_invalid_values_covers_every_parameter():
    """Every declared parameter has an invalid value below."""
    assert set(INVALID) == {p.name for p in PARAMETERS}


@pytest.mark.parametrize('name', list(INVALID))
def test_every_refusal_names_the_parameter_the_user_set(name):
    """The message names the ROS parameter (initial_orientation, not orientation), on one line."""
    refused(name, **{name: INVALID[name]})


@pytest.mark.parametrize('name', [n for n, v in DEFAULTS.items() if isinstance(v, list)])
def test_array_parameters_of_the_wrong_size_show_plain_numbers(name):
    """A too short double array, as rclpy hands it over, is shown as a list of its numbers."""
    message = refused(name, **{name: array('d', [0.5, 0.25])})
    assert '[0.5, 0.25]' in message, message


@pytest.mark.parametrize('name, value', [
    ('rate_hz', 0.5), ('rate_hz', 20000.0), ('substeps', 1001), ('workspace_radius', 1e13)])
def test_the_declared_ranges_hold_without_ros_too(name, value):
    """node_config keeps the node's ranges, so h = dt / substeps stays >= 1e-7 s."""
    bounds = next(p.bounds for p in PARAMETERS if p.name == name)
    assert not bounds[0] <= value <= bounds[1]
    refused(name, **{name: value})


def test_a_message_with_a_line_break_in_a_value_is_one_line():
    """A value whose repr spans lines (a 2-D array) is shown on one line."""
    refused('initial_orientation', initial_orientation=np.eye(2))


def test_the_descriptions_state_the_physical_bounds():
    """The parameter descriptions (``ros2 param describe``) carry the ranges."""
    descriptions = {p.name: p.description for p in PARAMETERS}
    assert f'{MIN_MASS:g}' in descriptions['mass'] and f'{MAX_MASS:g}' in descriptions['mass']
    assert f'{MIN_MOMENT:g}' in descriptions['inertia']
    assert f'{MAX_MOMENT:g}' in descriptions['inertia']
    assert f'{MAX_CONDITION:g}' in descriptions['anchor']
    assert f'{MAX_DISTANCE:g}' in descriptions['box_size']
    assert f'{MAX_ACCELERATION:g}' in descriptions['gravity']
    assert 'slash' in descriptions['frame_id']


def test_a_singular_gyroscopic_jacobian_keeps_the_angular_velocity():
    """
    Spin about the intermediate axis of diag(3, 4, 6) at 6 rad/s, h = 1: J is exactly singular.

    J = I + (h / 2)([w]x I - [I w]x) has determinant I2 (I1 I3 - (h |w| / 2)^2 (I3 - I2)
    (I2 - I1)) = 4 (18 - 9 * 2) = 0, in exact integer arithmetic. The spin about a principal
    axis is steady, so keeping w is the exact step; the solve would divide by zero.
    """
    assert gyroscopic_step((3.0, 0.0, 0.0, 4.0, 0.0, 6.0), (0.0, 6.0, 0.0), 1.0) == \
        (0.0, 6.0, 0.0)
    body = RigidBody(1.0, (3.0, 0.0, 0.0, 4.0, 0.0, 6.0))
    sim = MouseSimulation(Settings(body, gravity=(0.0, 0.0, 0.0)),
                          BodyState(angular_velocity=(0.0, 6.0, 0.0)))
    assert sim.step(1.0).angular_velocity == (0.0, 6.0, 0.0)


@pytest.mark.parametrize('name, value', [
    ('mass', 1.0e-300),
    ('box_size', array('d', [1.0e-120, 1.0e-120, 1.0e-120])),
    ('inertia', array('d', [1.0e-110, 0.0, 0.0, 1.0e-110, 0.0, 1.0e-110])),
    ('gravity', array('d', [1.0e308, 0.0, 0.0])),
    ('anchor', array('d', [0.1, 0.2])),
    ('initial_orientation', array('d', [0.0, 0.0, 0.0, 2.0])),
    ('frame_id', '/world'),
])
def test_the_node_refuses_them_at_run_time_and_keeps_stepping(simulated_body_factory, name,
                                                              value):
    """
    ``ros2 param set`` of each: refused with a one-line reason naming it; the node runs on.

    Double arrays are given as rclpy hands them to the callback from the service, array.array.
    """
    from rclpy.parameter import Parameter

    body = simulated_body_factory(rate_hz=200.0)
    node = body.node
    before = node.simulation.settings
    [result] = node.set_parameters([Parameter(name, value=value)])
    assert not result.successful
    assert name in result.reason and '\n' not in result.reason, result.reason
    assert 'array(' not in result.reason, result.reason
    assert node.simulation.settings is before
    heights = []
    body.add_tick_callback(lambda b: heights.append(b.pose.position[2]))
    body.step(20)
    assert len(heights) == 20 and all(math.isfinite(z) for z in heights)
