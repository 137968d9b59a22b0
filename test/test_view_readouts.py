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

"""The web view's push throttle, and what it reads from the node's parameters and diagnostics."""

import math

from hypothesis import given, settings, strategies as st
import pytest
from rcl_interfaces.msg import ParameterType, ParameterValue

# mouse_view serves its page with viser (requirements/view.txt; no rosdep key: package.xml).
pytest.importorskip('viser', reason='mouse_view needs viser: pip install -r requirements/view.txt')
from mouse_constraint_ros.monitoring.diagnostics import (constraint_status, diagnostic_array,
                                                         Pacing, rate_status, simulator_status,
                                                         TickCounters, USER_TARGET, Window)
from mouse_constraint_ros.pointer.node_readouts import number_text, Readouts, ViewParameters
from mouse_constraint_ros.pointer.push_throttle import MAX_PUSH_RATE, PushThrottle
from mouse_constraint_ros.view.command import host_warning, page_address


def test_a_1khz_stream_is_pushed_at_60_hz_and_its_last_pose_is_not_lost():
    """1 kHz for a second: a push every 17th pose (1/60 s apart at least), the last one flushed."""
    throttle, pushes = PushThrottle(), []
    for tick in range(1000):
        now = tick * 1e-3
        if throttle.offer(tick, now) is not None:
            pushes.append((now, tick))
    every = math.ceil(1e3 / MAX_PUSH_RATE)
    assert [tick for _, tick in pushes] == list(range(0, 1000, every))
    gaps = [b[0] - a[0] for a, b in zip(pushes, pushes[1:])]
    assert min(gaps) >= 1.0 / MAX_PUSH_RATE - 1e-12
    assert throttle.holding and pushes[-1][1] != 999
    assert throttle.flush(0.999) is None
    assert throttle.flush(pushes[-1][0] + 1.0 / MAX_PUSH_RATE + 1e-9) == 999
    assert not throttle.holding and throttle.flush(5.0) is None


def test_a_slow_stream_is_pushed_whole():
    """Poses 0.1 s apart are each pushed at once."""
    throttle = PushThrottle()
    assert [throttle.offer(n, 0.1 * n) for n in range(5)] == list(range(5))


@settings(max_examples=100, deadline=None)
@given(st.lists(st.floats(0.0, 0.05), min_size=1, max_size=400), st.floats(1.0, 200.0))
def test_never_faster_than_the_rate_and_always_the_newest(gaps, rate):
    """Any arrival times: pushes at least 1/rate apart, each the newest offered then."""
    throttle, now, last_push = PushThrottle(rate), 0.0, -math.inf
    for index, gap in enumerate(gaps):
        now += gap
        pushed = throttle.offer(index, now)
        if pushed is not None:
            assert pushed == index and now - last_push >= 1.0 / rate - 1e-12
            last_push = now
    flushed = throttle.flush(now + 1.0 / rate + 1e-9)
    assert flushed in (None, len(gaps) - 1)
    assert not throttle.holding


def test_a_rate_must_be_positive():
    """0 or NaN pushes per second is refused."""
    for rate in (0.0, -1.0, math.nan):
        with pytest.raises(ValueError):
            PushThrottle(rate)


def _value(kind: int, **fields) -> ParameterValue:
    return ParameterValue(type=kind, **fields)


def test_parameters_take_known_valid_values_and_pass_over_the_rest():
    """box_size, anchor, frequency_hz, floor, floor_height, grab_margin read; others ignored."""
    parameters = ViewParameters().with_values([
        ('box_size', _value(ParameterType.PARAMETER_DOUBLE_ARRAY,
                            double_array_value=[1.0, 0.5, 0.25])),
        ('anchor', _value(ParameterType.PARAMETER_DOUBLE_ARRAY,
                          double_array_value=[-0.5, 0.0, 0.1])),
        ('frequency_hz', _value(ParameterType.PARAMETER_DOUBLE, double_value=5.0)),
        ('floor', _value(ParameterType.PARAMETER_BOOL, bool_value=True)),
        ('floor_height', _value(ParameterType.PARAMETER_DOUBLE, double_value=-0.5)),
        ('frame_id', _value(ParameterType.PARAMETER_STRING, string_value='map')),
        ('grab_margin', _value(ParameterType.PARAMETER_DOUBLE, double_value=0.02)),
        ('a_parameter_of_tomorrow', _value(ParameterType.PARAMETER_INTEGER, integer_value=3)),
    ])
    assert parameters == ViewParameters('map', (1.0, 0.5, 0.25), (-0.5, 0.0, 0.1), 5.0, True,
                                        -0.5, 0.02)
    assert parameters.mode == 'soft, 5 Hz' and ViewParameters().mode == 'rigid'
    unchanged = parameters.with_values([
        ('box_size', _value(ParameterType.PARAMETER_DOUBLE_ARRAY,
                            double_array_value=[1.0, 0.0, 0.25])),
        ('box_size', _value(ParameterType.PARAMETER_DOUBLE_ARRAY, double_array_value=[1.0])),
        ('anchor', _value(ParameterType.PARAMETER_DOUBLE_ARRAY,
                          double_array_value=[math.nan, 0.0, 0.0])),
        ('floor', _value(ParameterType.PARAMETER_DOUBLE, double_value=1.0)),
        ('frequency_hz', _value(ParameterType.PARAMETER_DOUBLE, double_value=math.inf)),
        ('floor_height', _value(ParameterType.PARAMETER_NOT_SET)),
        ('grab_margin', _value(ParameterType.PARAMETER_DOUBLE, double_value=-0.01)),
        ('grab_margin', _value(ParameterType.PARAMETER_DOUBLE, double_value=math.nan)),
    ])
    assert unchanged == parameters


NODE = '/robot/mouse_constraint'


def _diagnostics(name: str, *, paused: bool):
    window = Window(1.0, 1000, 0, 0, 0)
    totals = TickCounters(1000, 0, 0, 0)
    pacing = Pacing(False, paused, 1.0, None, 0.0, 1.0)
    return diagnostic_array(0, [
        rate_status(f'{name}: rate', name, rate_hz=1000.0, window=window, totals=totals),
        constraint_status(f'{name}: constraint', name, target_kind=USER_TARGET,
                          target=(0.0, 0.0, 1.0), anchor_error=0.0125, force=(0.0, 0.0, 1.0),
                          force_bound=100.0, target_age=0.1, target_timeout=0.0),
        simulator_status(f'{name}: simulator', name, pacing=pacing, force=(0.0,) * 3,
                         torque=(0.0,) * 3, wrench_age=None, wrench_timeout=0.5)])


def test_the_readouts_are_the_nodes_own_diagnostics():
    """The rate, anchor error and pause state the node's status builders write, for that node."""
    readouts = Readouts().updated(_diagnostics(NODE, paused=True), NODE)
    assert readouts == Readouts(1000.0, 0.0125, True)
    assert Readouts().updated(_diagnostics('/other/mouse_constraint', paused=True),
                              NODE) == Readouts()
    assert readouts.updated(_diagnostics(NODE, paused=False), NODE).paused is False


def test_numbers_and_addresses():
    """n/a without a number; the loopback needs no warning; another host gets one line."""
    assert number_text(None, 'm/s') == 'n/a'
    assert number_text(0.0125, 'mm', scale=1e3, decimals=2) == '12.50 mm'
    assert host_warning('127.0.0.1') is None
    warning = host_warning('0.0.0.0')
    assert warning is not None and '\n' not in warning and '0.0.0.0' in warning
    assert page_address('0.0.0.0', 8080) == 'http://127.0.0.1:8080'
    assert page_address('::1', 8081) == 'http://[::1]:8081'
    assert page_address('::', 8173) == 'http://[::1]:8173'
