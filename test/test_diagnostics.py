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

"""/diagnostics: the tick window, the levels of both statuses, and the node's messages."""

import math

from diagnostic_msgs.msg import DiagnosticArray
from diagnostic_msgs.msg import DiagnosticStatus
import pytest
from rclpy.parameter import Parameter

from mouse_constraint_ros.monitoring.diagnostics import constraint_status
from mouse_constraint_ros.monitoring.diagnostics import diagnostic_array
from mouse_constraint_ros.monitoring.diagnostics import INITIAL_ANCHOR
from mouse_constraint_ros.monitoring.diagnostics import NO_TARGET
from mouse_constraint_ros.monitoring.diagnostics import rate_status
from mouse_constraint_ros.monitoring.diagnostics import Thresholds
from mouse_constraint_ros.monitoring.diagnostics import USER_TARGET
from mouse_constraint_ros.monitoring.tick_window import TickCounters
from mouse_constraint_ros.monitoring.tick_window import TickWindow
from mouse_constraint_ros.monitoring.tick_window import Window
from mouse_constraint_ros.node.mouse_constraint_node import MouseConstraintNode
from mouse_constraint_ros.physics.settings import force_bound
from mouse_constraint_ros.wire.messages import stamp_nanoseconds

OK, WARN, ERROR = DiagnosticStatus.OK, DiagnosticStatus.WARN, DiagnosticStatus.ERROR
TOTALS = TickCounters(1000, 3, 0, 0)


def values(status: DiagnosticStatus) -> dict:
    """Return a status's key-value pairs as a dict."""
    return {kv.key: kv.value for kv in status.values}


def test_tick_window_takes_differences_between_samples():
    """Deltas of the counters over the node's clock; no window at first, on a new rate or clock."""
    window = TickWindow()
    assert window.sample(5_000_000_000, TickCounters(10, 1, 0, 0), 100.0) is None
    assert window.sample(6_000_000_000, TickCounters(110, 4, 2, 1), 100.0) == Window(
        1.0, 100, 3, 2, 1)
    assert window.sample(7_000_000_000, TickCounters(150, 4, 2, 1), 50.0) is None
    assert window.sample(6_500_000_000, TickCounters(170, 4, 2, 2), 50.0) is None
    assert window.sample(0, TickCounters(170, 4, 2, 2), 50.0) is None
    assert window.sample(500_000_000, TickCounters(195, 4, 2, 2), 50.0) is None
    assert window.sample(1_000_000_000, TickCounters(220, 4, 2, 2), 50.0).ticks == 25


@pytest.mark.parametrize('ticks, late, restarts, level, message', [
    (1000, 0, 0, OK, '1000.0 of 1000 Hz'),
    (990, 0, 0, OK, '990.0 of 1000 Hz'),
    (980, 0, 0, WARN, 'achieved 980.0 of 1000 Hz'),
    (899, 0, 0, WARN, 'achieved 899.0 of 1000 Hz'),
    (898, 0, 0, ERROR, 'achieved 898.0 of 1000 Hz'),
    (1000, 250, 0, OK, '1000.0 of 1000 Hz'),
    (1000, 251, 0, WARN, '25 % of ticks ran late'),
    (1000, 0, 1, WARN, 'clock restarted (jumped backwards or changed source)'),
])
def test_rate_levels(ticks, late, restarts, level, message):
    """Achieved vs requested rate, late ticks and clock restarts by the documented thresholds."""
    status = rate_status('n: rate', '/n', rate_hz=1000.0,
                         window=Window(1.0, ticks, late, 0, restarts), totals=TOTALS)
    assert (status.level, status.message) == (level, message)
    assert status.name == 'n: rate' and status.hardware_id == '/n'
    assert values(status)['requested rate (Hz)'] == '1000'
    assert float(values(status)['achieved rate (Hz)']) == ticks


def test_rate_allows_one_tick_of_jitter_and_reports_drops():
    """At a low rate one tick less is not a shortfall; dropped ticks are named."""
    assert rate_status('n', '', rate_hz=2.0, window=Window(1.0, 1, 0, 0, 0),
                       totals=TOTALS).level == OK
    status = rate_status('n', '', rate_hz=100.0, window=Window(1.0, 50, 0, 50, 0),
                         totals=TickCounters(90, 0, 60, 0))
    assert status.level == ERROR
    assert status.message == 'achieved 50.0 of 100 Hz (50 ticks dropped)'
    assert values(status)['dropped ticks'] == '50'
    assert values(status)['dropped ticks since start'] == '60'
    assert values(status)['last drop cause'] == 'n/a'


def test_rate_names_the_drop_cause_and_what_the_clock_waits_for():
    """The cause of dropped ticks is in the message; a clock that never came is a WARN."""
    cause = 'a tick takes too long'
    status = rate_status('n', '', rate_hz=100.0, window=Window(1.0, 50, 0, 50, 0),
                         totals=TickCounters(90, 0, 60, 0), drop_cause=cause)
    assert status.message == f'achieved 50.0 of 100 Hz (50 ticks dropped: {cause})'
    assert values(status)['last drop cause'] == cause
    waiting = rate_status('n', '', rate_hz=100.0, window=None, totals=TickCounters(0, 0, 0, 0),
                          waiting_for='/clock on /sim/clock')
    assert waiting.level == WARN
    assert waiting.message == 'waiting for /clock on /sim/clock: no tick runs until it comes'


def test_rate_without_a_window_is_measuring():
    """No window yet: OK, 'measuring', the window's values n/a."""
    status = rate_status('n', '', rate_hz=100.0, window=None, totals=TOTALS)
    assert (status.level, status.message) == (OK, 'measuring')
    assert values(status)['achieved rate (Hz)'] == values(status)['ticks run'] == 'n/a'
    assert values(status)['late ticks since start'] == '3'


@pytest.mark.parametrize('error, level', [
    (0.0, OK), (0.0499, OK), (0.05, WARN), (0.4999, WARN), (0.5, ERROR), (3.0, ERROR),
    (math.nan, ERROR), (math.inf, ERROR),
])
def test_anchor_error_levels(error, level):
    """The anchor error grades OK / WARN / ERROR at anchor_warn and anchor_error."""
    status = constraint_status('n: constraint', '/n', target_kind=USER_TARGET,
                               target=(0.0, 0.0, 1.0), anchor_error=error,
                               force=(0.0, 0.0, 19.6), force_bound=math.inf, target_age=0.2,
                               target_timeout=0.0)
    assert status.level == level
    assert values(status)['anchor error (m)'] == f'{error:.6g}'
    if level != OK:
        assert 'from the target' in status.message


def test_anchor_thresholds_come_from_the_parameters():
    """Thresholds(anchor_warn, anchor_error) move the levels."""
    thresholds = Thresholds(anchor_warn=0.001, anchor_error=0.01)
    levels = [constraint_status('n', '', target_kind=USER_TARGET, target=(0.0, 0.0, 0.0),
                                anchor_error=error, force=(0.0, 0.0, 0.0), force_bound=math.inf,
                                target_age=0.0, target_timeout=0.0,
                                thresholds=thresholds).level
              for error in (0.0005, 0.005, 0.05)]
    assert levels == [OK, WARN, ERROR]


def test_saturated_force_and_old_target_warn():
    """A force at its bound warns; so does a target older than half of target_timeout."""
    at_bound = constraint_status('n', '', target_kind=USER_TARGET, target=(0.0, 0.0, 1.0),
                                 anchor_error=0.01, force=(0.0, 6.0, 8.0), force_bound=10.0,
                                 target_age=0.1, target_timeout=0.0)
    assert (at_bound.level, at_bound.message) == (WARN, 'force at its bound 10 N')
    below = constraint_status('n', '', target_kind=USER_TARGET, target=(0.0, 0.0, 1.0),
                              anchor_error=0.01, force=(0.0, 6.0, 7.9), force_bound=10.0,
                              target_age=0.1, target_timeout=0.0)
    assert below.level == OK
    old = constraint_status('n', '', target_kind=USER_TARGET, target=(0.0, 0.0, 1.0),
                            anchor_error=0.01, force=(0.0, 0.0, 1.0), force_bound=math.inf,
                            target_age=0.6, target_timeout=1.0)
    assert old.level == WARN and old.message.startswith('no target for 0.60 s')
    assert values(old)['target age (s)'] == '0.6'
    assert constraint_status('n', '', target_kind=USER_TARGET, target=(0.0, 0.0, 1.0),
                             anchor_error=0.01, force=(0.0, 0.0, 1.0), force_bound=math.inf,
                             target_age=60.0, target_timeout=0.0).level == OK


def test_statuses_take_their_values_by_keyword_only():
    """Ten numbers and vectors in a row are easy to shift: only the name and id go by position."""
    with pytest.raises(TypeError, match='positional'):
        constraint_status('n', '', NO_TARGET, None, None, (0.0, 0.0, 0.0), 5.0, None, 1.0)
    with pytest.raises(TypeError, match='positional'):
        rate_status('n', '', 100.0, None, TOTALS)


def test_free_body_is_ok_with_values_not_applicable():
    """No target: OK, its position, age and anchor error n/a."""
    status = constraint_status('n', '', target_kind=NO_TARGET, target=None, anchor_error=None,
                               force=(0.0, 0.0, 0.0), force_bound=5.0, target_age=None,
                               target_timeout=1.0)
    assert (status.level, status.message) == (OK, NO_TARGET)
    assert values(status)['target position (m)'] == values(status)['anchor error (m)'] == 'n/a'


def test_array_is_stamped():
    """diagnostic_array stamps the header and keeps the statuses in order."""
    first, second = DiagnosticStatus(name='a'), DiagnosticStatus(name='b')
    array = diagnostic_array(12_345_000_000_007, [first, second])
    assert stamp_nanoseconds(array.header.stamp) == 12_345_000_000_007
    assert [s.name for s in array.status] == ['a', 'b']


def test_node_reports_rate_and_constraint(ros):
    """The node's /diagnostics: both statuses at the diagnostics rate, then a falling body."""
    node = ros.add(MouseConstraintNode(context=ros.context, parameter_overrides=[
        Parameter('rate_hz', value=200.0), Parameter('diagnostics_rate_hz', value=10.0),
        Parameter('marker_rate_hz', value=0.0)]))
    arrays = ros.collect(DiagnosticArray, '/diagnostics')
    assert ros.spin_until(lambda: len(arrays) >= 5, timeout=5.0)
    rate, constraint = arrays[-1].status[:2]
    assert rate.name == '/mouse_constraint: rate'
    assert constraint.name == '/mouse_constraint: constraint'
    assert rate.hardware_id == constraint.hardware_id == '/mouse_constraint'
    assert values(rate)['requested rate (Hz)'] == '200'
    assert float(values(rate)['achieved rate (Hz)']) == pytest.approx(200.0, rel=0.15)
    assert float(values(rate)['window (s)']) == pytest.approx(0.1, rel=0.3)
    assert rate.level != ERROR
    assert constraint.level == OK and values(constraint)['target'] == INITIAL_ANCHOR
    assert float(values(constraint)['anchor error (m)']) < 0.01
    stamps = [stamp_nanoseconds(a.header.stamp) for a in arrays]
    assert stamps == sorted(stamps) and stamps[0] > 0
    assert values(constraint)['force bound (N)'] == f'{force_bound(node.simulation.settings):.6g}'
    # A max_force below the weight (2 kg * 9.8 m/s^2): the force saturates, the body falls away.
    assert node.set_parameters([Parameter('max_force', value=5.0)])[0].successful
    count = len(arrays)
    assert ros.spin_until(lambda: arrays[-1].status[1].level == ERROR, timeout=5.0)
    constraint = arrays[-1].status[1]
    assert 'force at its bound 5 N' in constraint.message
    # Never past the bound. The joint at its bound still carries the angular friction's reaction
    # where that lowers its force (physics/kernel.py), so the force need not sit on the bound.
    assert 0.5 * 5.0 < float(values(constraint)['constraint force (N)']) <= 5.0
    # On its way to anchor_error (0.5 m) it spends ~0.25 s between 0.05 m and 0.5 m: WARN.
    levels = [a.status[1].level for a in arrays[count:]]
    assert WARN in levels


def test_namespaced_nodes_have_unique_status_names(ros):
    """Two nodes of one name in two namespaces: the status names differ, by namespace."""
    for namespace in ('left', 'right'):
        ros.add(MouseConstraintNode(context=ros.context, namespace=namespace,
                                    parameter_overrides=[
                                        Parameter('rate_hz', value=100.0),
                                        Parameter('diagnostics_rate_hz', value=10.0),
                                        Parameter('marker_rate_hz', value=0.0)]))
    arrays = ros.collect(DiagnosticArray, '/diagnostics')

    def names():
        return {status.name for array in arrays for status in array.status}

    assert ros.spin_until(lambda: len(names()) >= 8, timeout=10.0), names()
    assert names() == {f'/{ns}/mouse_constraint: {kind}'
                       for ns in ('left', 'right')
                       for kind in ('rate', 'constraint', 'simulator', 'inputs')}


def test_the_weight_bound_counts_as_the_force_bound(ros):
    """
    max_force_per_weight below one weight: the force saturates at k m |g|, and diagnostics say so.

    max_force stays unlimited: the bound is the joint's, not the max_force parameter.
    """
    per_weight = 0.25
    node = ros.add(MouseConstraintNode(context=ros.context, parameter_overrides=[
        Parameter('rate_hz', value=200.0), Parameter('diagnostics_rate_hz', value=10.0),
        Parameter('marker_rate_hz', value=0.0),
        Parameter('max_force_per_weight', value=per_weight)]))
    settings = node.simulation.settings
    assert math.isinf(settings.constraint.max_force)
    bound = per_weight * settings.body.mass * math.hypot(*settings.gravity)
    arrays = ros.collect(DiagnosticArray, '/diagnostics')
    assert ros.spin_until(lambda: arrays and 'force at its bound' in arrays[-1].status[1].message,
                          timeout=5.0)
    constraint = arrays[-1].status[1]
    assert f'force at its bound {bound:g} N' in constraint.message
    assert values(constraint)['force bound (N)'] == f'{bound:.6g}'  # six digits, as shown
    # Never past the bound but by the arithmetic's rounding (1e-12 of it here): rounding to six
    # digits keeps the order, so the force shown is at most that bound shown. This bound,
    # 4.903325 N, sits on a six-digit rounding edge: the force a rounding above it shows 4.90333.
    shown = float(values(constraint)['constraint force (N)'])
    assert 0.5 * bound < shown <= float(f'{bound * (1.0 + 1e-12):.6g}')
