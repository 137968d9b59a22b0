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

"""The start-up texts without ROS: refusals, unknown keys, rcl's errors, the logger's name."""

import array
import math

import pytest
from rclpy.parameter import Parameter

from mouse_constraint_ros.node.parameters import DEFAULTS, node_config, PARAMETERS
from mouse_constraint_ros.node.startup import (CLOCK_LOOP, clock_loop, describe,
                                               override_refusal, rcl_reason,
                                               refusal_reason, requested_logger_name, type_hint,
                                               TYPE_NAMES, unknown_parameter_warnings, value_type,
                                               yaml_text)

SPECS = {spec.name: spec for spec in PARAMETERS}


@pytest.mark.parametrize('value', [
    None, True, 0, 2, 2.0, 'world', [True, False], [1, 2], [1.0, 2.0], ['a', 'b'], [b'\x00'],
    array.array('d', [1.0, 2.0]), array.array('q', [1, 2]), (0.0, 1.0),
] + [spec.default for spec in PARAMETERS])
def test_value_type_names_the_type_rclpy_finds(value):
    """The pure type name is rclpy's own, for every default and every kind of value."""
    assert value_type(value) == Parameter.Type.from_parameter_value(value).name


def test_every_type_has_a_name_in_the_refusals():
    """Each settable rclpy type reads as a phrase, so no refusal shows a bare enum name."""
    settable = {t.name for t in Parameter.Type} - {'NOT_SET'}
    assert set(TYPE_NAMES) == settable


@pytest.mark.parametrize('value, text', [
    (True, 'true'), (False, 'false'), (2.0, '2.0'), (2, '2'), (math.nan, '.nan'),
    (math.inf, '.inf'), (-math.inf, '-.inf'), ([0, 0.5], '[0, 0.5]'),
    (array.array('d', [1.0]), '[1.0]'), ('w', "'w'"),
])
def test_yaml_text_writes_values_as_a_params_file_does(value, text):
    assert yaml_text(value) == text


@pytest.mark.parametrize('value, expected, hint', [
    (2, 'DOUBLE', '2.0'), ([0, 0, -10], 'DOUBLE_ARRAY', '[0.0, 0.0, -10.0]'),
    (2.0, 'INTEGER', '2'), (1, 'BOOL', 'true'), (0, 'BOOL', 'false'),
    (2.5, 'INTEGER', None), (2, 'BOOL', None), ('2', 'DOUBLE', None),
])
def test_type_hint_only_where_the_fix_is_plain(value, expected, hint):
    assert type_hint(value, expected) == hint


@pytest.mark.parametrize('name, value, expected', [
    ('mass', 2, 'mass: 2 is an integer, mass takes a double: write 2.0'),
    ('substeps', 2.0, 'substeps: 2.0 is a double, substeps takes an integer: write 2'),
    ('hold_initial_anchor', 1,
     'hold_initial_anchor: 1 is an integer, hold_initial_anchor takes a bool: write true'),
    ('gravity', [0, 0, -10], 'gravity: [0, 0, -10] is a list of integers, gravity takes a list '
     'of doubles: write [0.0, 0.0, -10.0]'),
    ('frame_id', 3, 'frame_id: 3 is an integer, frame_id takes a string'),
    ('substeps', 2.5, 'substeps: 2.5 is a double, substeps takes an integer'),
    ('rate_hz', 0.0, 'rate_hz must be >= 1.0, got 0.0'),
    ('substeps', 0, 'substeps must be an integer >= 1, got 0'),
    ('substeps', 5000, 'substeps must be <= 1000, got 5000'),
    ('mass', -1.0, 'mass must be > 0.0, got -1.0'),
    ('mass', 1e200, 'mass must be within [1e-100, 1e+100] kg, got 1e+200: beyond, the effective '
     'mass (1 / m) or the impulses and energies (m) of the step overflow'),
    ('mass', math.nan, 'mass must be finite, got nan'),
])
def test_a_refusal_names_the_parameter_the_reason_and_the_fix(name, value, expected):
    """The lines test_startup_refusals reads from the executable, here from the function."""
    given = (value, Parameter.Type.from_parameter_value(value).name)
    assert refusal_reason(SPECS[name], 'rclpy text', given) == expected


def test_a_value_out_of_range_reads_as_the_node_refuses_any_invalid_value():
    """The declared range's refusal is node_config's own; one it would take, said plainly."""
    for spec in PARAMETERS:
        if spec.bounds is None:
            continue
        low, high = spec.bounds
        for value in (low - 1, 2 * high + 1)[:1 if math.isinf(high) else 2]:
            given = (type(spec.default)(value), value_type(spec.default))
            with pytest.raises(ValueError) as refused:
                node_config({**DEFAULTS, spec.name: given[0]})
            assert refusal_reason(spec, 'rclpy text', given) == str(refused.value)
    narrow = SPECS['mass']._replace(bounds=(3.0, 4.0))
    assert refusal_reason(narrow, 'rclpy text', (2.5, 'DOUBLE')) == \
        'mass: 2.5 is outside its range [3.0, 4.0]'


def test_a_refusal_without_an_override_or_a_plainer_reason_is_rclpys():
    error = ValueError('rclpy text')
    assert refusal_reason(SPECS['mass'], error) == 'mass: rclpy text'
    assert refusal_reason(SPECS['frame_id'], error, ('world', 'STRING')) == \
        'frame_id: rclpy text'


def test_unknown_keys_are_warned_about_with_the_nearest_name():
    """The keys rclpy reads are not unknown; a key close to none gets no suggestion."""
    known = [spec.name for spec in PARAMETERS]
    given = ['baumgarde', 'use_sim_time', 'qos_overrides./pose.publisher.depth', 'mass',
             'zzzzzz']
    assert unknown_parameter_warnings(given, known + ['use_sim_time'], known) == [
        "ignoring unknown parameter 'baumgarde': did you mean 'baumgarte'?",
        "ignoring unknown parameter 'zzzzzz'",
    ]


def test_the_clock_loop_is_both_flags_at_once():
    assert [clock_loop(p, u) for p in (False, True) for u in (False, True)] == [
        None, None, None, CLOCK_LOOP]


def test_the_description_names_rate_mode_and_clock():
    config = node_config(DEFAULTS)
    line = describe(config)
    assert line.startswith(f'{config.rate_hz:g} Hz x {config.settings.substeps} substeps')
    assert 'rigid, baumgarte' in line and 'publishing /clock' not in line
    soft = describe(node_config({**DEFAULTS, 'frequency_hz': 5.0, 'publish_clock': True}))
    assert 'soft, 5 Hz' in soft and soft.endswith(
        f'publishing /clock at real time factor {DEFAULTS["real_time_factor"]:g}')


def test_the_description_says_where_the_floor_is():
    """The shipped configuration turns the floor on: the start line says so, and where."""
    assert ', no floor' in describe(node_config(DEFAULTS))
    floored = describe(node_config({**DEFAULTS, 'floor': True, 'floor_height': -0.25,
                                    'restitution': 0.5}))
    assert ', floor at z -0.25 m (friction 0.5, restitution 0.5)' in floored


@pytest.mark.parametrize('args, name', [
    ([], 'n'),
    (['--ros-args', '-r', '__node:=other'], 'other'),
    (['--ros-args', '-r', '__name:=other', '-r', '__ns:=/robot/arm'], 'robot.arm.other'),
    (['--ros-args', '-r', 'n:__ns:=/robot'], 'robot.n'),
    (['--ros-args', '-r', 'topic:=other'], 'n'),
])
def test_the_requested_logger_name_follows_the_remaps(args, name):
    assert requested_logger_name(args, 'n') == name


def test_rcls_reason_loses_its_source_locations_and_gains_the_fix():
    error = RuntimeError("failed to initialize rcl: Couldn't parse params file: 'Sequence "
                         "should be of same type. Value type 'integer' do not belong', at "
                         './src/parser.c:123, at ./src/rcl/arguments.c:406')
    reason = rcl_reason(error)
    assert reason.startswith("Couldn't parse params file") and '.c:' not in reason
    assert reason.endswith('e.g. [0.2, 0.0, 0.05])')
    assert rcl_reason(RuntimeError('Error opening YAML file, at ./x.c:1')).endswith(
        '(no such file, or not readable)')


URDF_WITH_A_COMMENT = ('<?xml version="1.0"?>\n<!-- A box. Run it: make run -->\n'
                       '<robot name="r"><link name="b"/></robot>')


def test_an_override_rcl_cannot_take_is_named_with_the_way_round():
    """
    -p robot_description:="$(cat f.urdf)" with ': ' in a comment: the cause and the params file.

    rcl reads the value as YAML, which makes it a mapping or an error; a value that is text,
    a number or a list passes, and so does the same name outside -p.
    """
    args = ['mouse_constraint_node', '--ros-args', '-p', 'body_link:=b',
            '-p', f'robot_description:={URDF_WITH_A_COMMENT}']
    reason = override_refusal(args)
    assert reason.startswith("Couldn't parse parameter override rule: -p robot_description:=...")
    assert "rcl reads an override's value as YAML, where ': ' and ' #' are not text" in reason
    assert 'make run URDF=path/to.urdf' in reason and '--params-file out.yaml' in reason
    assert '\n' not in reason
    mapping = override_refusal(['n', '--ros-args', '-p', 'frame_id:=a: b'])
    assert '-p frame_id:=... (a mapping, not a value;' in mapping
    assert mapping.endswith('or use --params-file')
    for fine in ('frame_id:=odom', 'gravity:=[0.0, 0.0, -1.0]', "frame_id:='a: b'",
                 f'robot_description:={URDF_WITH_A_COMMENT.replace(": ", " ")}'):
        assert override_refusal(['n', '--ros-args', '-p', fine]) is None, fine
    assert override_refusal(['n', '--ros-args', '-r', 'a:=b: c']) is None
    # What rcl says when it refuses one itself: the same line.
    error = RuntimeError("failed to initialize rcl: Couldn't parse parameter override rule: "
                         f"'-p robot_description:={URDF_WITH_A_COMMENT[:60]}, at ./a.c:1")
    assert rcl_reason(error).startswith(
        "Couldn't parse parameter override rule: -p robot_description:=... (rcl cannot parse it;")
