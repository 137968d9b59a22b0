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
The node's ``/diagnostics``: tick-rate, constraint and simulator statuses (no rclpy here).

The node samples its tick counters into a ``TickWindow`` (``tick_window``) at the diagnostics
rate; the window's differences give the achieved rate (ticks actually run per second of the
node's clock, not the timer's period), late and dropped ticks. ``rate_status`` and
``constraint_status`` grade them against ``Thresholds``:

=================================  =================  ===================  ==============
check                              OK                 WARN                 ERROR
=================================  =================  ===================  ==============
achieved / requested rate (*)      >= 0.99            < 0.99               < 0.9
ticks run late (in catch-up)       <= 25 % of them    > 25 %
clock restarted (**)               no                 yes, in the window
waiting for the first /clock       no                 yes
anchor error (m)                   < anchor_warn      >= anchor_warn       >= anchor_error
constraint force (N) (***)         < bound            >= 0.999 bound
target age, if target_timeout > 0  < timeout / 2      >= timeout / 2
=================================  =================  ===================  ==============

(*) allowing one tick of jitter at the window's edges: (ticks + 1) / (seconds * rate_hz).
(**) the clock jumped backwards (a /clock replay restarting) or changed source (``use_sim_time``
flipped): the node restarts its tick grid there, with no catch-up and no ticks dropped.
(***) the bound the joint enforces (``physics.settings.force_bound``): the smaller of
``max_force`` and ``max_force_per_weight`` m |g|; no check when both are unlimited.

Dropped ticks are named with their cause: missed time beyond the catch-up bound, or a timer
callback that reached its wall-time budget (a tick costs more than the node can run at
``rate_hz``, e.g. many substeps). With ``use_sim_time`` and no /clock yet the node's clock reads
zero and no tick runs: the rate status says what it waits for instead of "measuring".

The rate status also carries what is published (``publishing_values``): the publish rate,
whether TF is broadcast (and why not), and the odometry topic.

``anchor_warn`` and ``anchor_error`` come from the node's parameters (``diagnostics_anchor_warn``,
``diagnostics_anchor_error``); a non-finite anchor error is an ERROR. The anchor error, force and
target age are those of the latest tick; the rate, late and dropped ticks are over the window.
"""

import math
from typing import List, NamedTuple, Optional, Sequence

from diagnostic_msgs.msg import DiagnosticArray, DiagnosticStatus, KeyValue

from .tick_window import TickCounters, Window
from ..physics.algebra import Vector3
from ..wire.interface import PAUSED_KEY
from ..wire.messages import set_stamp

# The levels, as the statuses carry them (bytes: ``max`` of two is the worse).
OK = DiagnosticStatus.OK
WARN = DiagnosticStatus.WARN
ERROR = DiagnosticStatus.ERROR

# Kinds of target, as the constraint status names them.
USER_TARGET = 'user target'
INITIAL_ANCHOR = 'holding the initial anchor'
NO_TARGET = 'none (free body)'


class Thresholds(NamedTuple):
    """
    Where the levels change; see the module's table.

    :param rate_warn: achieved / requested rate below which the rate is WARN.
    :param rate_error: the same for ERROR.
    :param late_warn: share of the window's ticks run late above which the rate is WARN.
    :param anchor_warn: anchor error (m) from which the constraint is WARN.
    :param anchor_error: anchor error (m) from which the constraint is ERROR.
    :param force_saturated: share of the force bound from which the force counts as at its bound.
    :param target_age_warn: share of target_timeout from which an old target is WARN.
    """

    rate_warn: float = 0.99
    rate_error: float = 0.9
    late_warn: float = 0.25
    anchor_warn: float = 0.05
    anchor_error: float = 0.5
    force_saturated: float = 0.999
    target_age_warn: float = 0.5


# The keys of the window's fields in the rate status, in ``Window`` order.
WINDOW_KEYS = ('window (s)', 'ticks run', 'late ticks', 'dropped ticks', 'clock restarts')


def _value(number: Optional[float], digits: int = 6) -> str:
    """Return ``number`` to ``digits`` significant digits, 'n/a' for None."""
    return 'n/a' if number is None else f'{number:.{digits}g}'


def _status(name: str, hardware_id: str, *, level: bytes, problems: List[str], fine: str,
            values: Sequence[KeyValue]) -> DiagnosticStatus:
    """Return a status at ``level``: its message the problems, or ``fine`` without any."""
    return DiagnosticStatus(level=level, name=name, hardware_id=hardware_id,
                            message='; '.join(problems) if problems else fine,
                            values=list(values))


def rate_status(name: str, hardware_id: str, *, rate_hz: float, window: Optional[Window],
                totals: TickCounters, thresholds: Thresholds = Thresholds(),
                drop_cause: Optional[str] = None,
                waiting_for: Optional[str] = None) -> DiagnosticStatus:
    """
    Return the tick-rate status: requested vs achieved rate, late and dropped ticks.

    :param name: the status name, ``<fully qualified node name>: rate``.
    :param hardware_id: the status's hardware_id.
    :param rate_hz: the requested rate (the ``rate_hz`` parameter).
    :param window: the last window, or None when there is none yet (OK, "measuring").
    :param totals: the counters since the node started.
    :param thresholds: where the levels change.
    :param drop_cause: why ticks were last dropped, or None if none ever were.
    :param waiting_for: what keeps the clock from running (WARN), e.g.
        ``'/clock on /clock'``, or None.
    """
    level = OK
    problems = []
    achieved = None
    if waiting_for is not None:
        level = WARN
        problems.append(f'waiting for {waiting_for}: no tick runs until it comes')
    if window is None:
        fine = 'measuring'
    else:
        achieved = window.ticks / window.seconds
        fine = f'{achieved:.1f} of {rate_hz:g} Hz'
        expected = window.seconds * rate_hz
        share = min(1.0, (window.ticks + 1) / expected)
        if share < thresholds.rate_warn:
            level = ERROR if share < thresholds.rate_error else WARN
            dropped = ''
            if window.dropped and drop_cause:
                dropped = f' ({window.dropped} ticks dropped: {drop_cause})'
            elif window.dropped:
                dropped = f' ({window.dropped} ticks dropped)'
            problems.append(f'achieved {achieved:.1f} of {rate_hz:g} Hz' + dropped)
        if window.ticks and window.late > thresholds.late_warn * window.ticks:
            level = max(level, WARN)
            problems.append(f'{100.0 * window.late / window.ticks:.0f} % of ticks ran late')
        if window.clock_restarts:
            level = max(level, WARN)
            problems.append('clock restarted (jumped backwards or changed source)')
    values = [
        KeyValue(key='requested rate (Hz)', value=_value(rate_hz)),
        KeyValue(key='achieved rate (Hz)', value=_value(achieved)),
    ]
    # The window's fields, n/a while there is no window.
    for index, key in enumerate(WINDOW_KEYS):
        values.append(KeyValue(key=key, value=_value(None if window is None else window[index])))
    values += [
        KeyValue(key='late ticks since start', value=str(totals.late)),
        KeyValue(key='dropped ticks since start', value=str(totals.dropped)),
        KeyValue(key='clock restarts since start', value=str(totals.clock_restarts)),
        KeyValue(key='last drop cause', value=drop_cause or 'n/a'),
    ]
    return _status(name, hardware_id, level=level, problems=problems, fine=fine, values=values)


def publishing_values(publish_rate_hz: float, tf_status: str,
                      odometry_topic: Optional[str]) -> List[KeyValue]:
    """
    Return the rate status's lines on publishing: the publish rate, TF and odometry.

    Informational, they leave the level as it is: TF off (publish_tf false, or tf2_ros not
    importable) is a configuration, which the ``tf`` line names with its reason.

    :param publish_rate_hz: the ``publish_rate_hz`` parameter (0 = every tick).
    :param tf_status: ``'<frame_id> -> <body_frame_id>'`` while TF is broadcast, else
        ``'off: <why>'``.
    :param odometry_topic: the odometry topic's resolved name, or None when it is off.
    """
    return [
        KeyValue(key='publish rate (Hz)',
                 value='every tick' if publish_rate_hz == 0.0 else _value(publish_rate_hz)),
        KeyValue(key='tf', value=tf_status),
        KeyValue(key='odometry', value='off' if odometry_topic is None else odometry_topic),
    ]


def constraint_status(name: str, hardware_id: str, *, target_kind: str,
                      target: Optional[Vector3], anchor_error: Optional[float], force: Vector3,
                      force_bound: float, target_age: Optional[float], target_timeout: float,
                      thresholds: Thresholds = Thresholds(),
                      floor_contacts: Optional[int] = None) -> DiagnosticStatus:
    """
    Return the constraint status: anchor error, constraint force, target and its age.

    :param name: the status name, ``<fully qualified node name>: constraint``.
    :param hardware_id: the status's hardware_id.
    :param target_kind: ``USER_TARGET``, ``INITIAL_ANCHOR`` or ``NO_TARGET``.
    :param target: the target (m), or None.
    :param anchor_error: the anchor's distance from the target (m), or None without one.
    :param force: the constraint force (N).
    :param force_bound: the force bound the joint enforces (N, may be inf): ``force_bound`` of
        the settings, the smaller of ``max_force`` and ``max_force_per_weight`` m |g|.
    :param target_age: seconds since the last user target, or None.
    :param target_timeout: the node's ``target_timeout`` (s, 0 = never).
    :param thresholds: where the levels change.
    :param floor_contacts: how many of the body's points touch the floor (a box's corners, a
        hull's vertices), None without a floor.
    """
    level = OK
    problems = []
    magnitude = math.hypot(*force)
    if anchor_error is not None:
        if not math.isfinite(anchor_error) or anchor_error >= thresholds.anchor_error:
            level = ERROR
        elif anchor_error >= thresholds.anchor_warn:
            level = WARN
        if level != OK:
            problems.append(f'anchor {anchor_error:.3g} m from the target')
    if (target is not None and math.isfinite(force_bound)
            and magnitude >= thresholds.force_saturated * force_bound):
        level = max(level, WARN)
        problems.append(f'force at its bound {force_bound:g} N')
    if (target_age is not None and target_timeout > 0.0
            and target_age >= thresholds.target_age_warn * target_timeout):
        level = max(level, WARN)
        problems.append(f'no target for {target_age:.2f} s (released at {target_timeout:g} s)')
    fine = target_kind
    if anchor_error is not None:
        fine += f', anchor within {thresholds.anchor_warn:g} m'
    values = [
        KeyValue(key='target', value=target_kind),
        KeyValue(key='target position (m)',
                 value='n/a' if target is None else ' '.join(_value(c) for c in target)),
        KeyValue(key='target age (s)', value=_value(target_age, 4)),
        KeyValue(key='anchor error (m)', value=_value(anchor_error)),
        KeyValue(key='constraint force (N)', value=_value(magnitude)),
        KeyValue(key='force bound (N)', value=_value(force_bound)),
        KeyValue(key='target timeout (s)', value=_value(target_timeout)),
        KeyValue(key='floor contacts',
                 value='no floor' if floor_contacts is None else str(floor_contacts)),
    ]
    return _status(name, hardware_id, level=level, problems=problems, fine=fine, values=values)


def diagnostic_array(stamp_ns: int, statuses: Sequence[DiagnosticStatus]) -> DiagnosticArray:
    """Return a ``diagnostic_msgs/DiagnosticArray`` of ``statuses`` stamped ``stamp_ns``."""
    array = DiagnosticArray(status=list(statuses))
    set_stamp(array.header.stamp, stamp_ns)
    return array


class Pacing(NamedTuple):
    """The clock's side of the simulator status, over the window since the last sample."""

    publish_clock: bool
    paused: bool
    real_time_factor: float
    achieved_factor: Optional[float]
    slipped: float
    simulated_time: float


def simulator_status(name: str, hardware_id: str, *, pacing: Pacing, force: Vector3,
                     torque: Vector3, wrench_age: Optional[float],
                     wrench_timeout: float) -> DiagnosticStatus:
    """
    Return the simulator status: clock source, pause, real time factor and the external wrench.

    WARN when the node is the clock and simulated time slipped in the window (the machine did
    not keep ``real_time_factor``); OK otherwise, paused included (pausing is asked for).

    :param name: the status name, ``<fully qualified node name>: simulator``.
    :param hardware_id: the status's hardware_id.
    :param pacing: clock source, pause and factors.
    :param force: the wrench's force applied now (N, world frame).
    :param torque: the wrench's torque applied now (N m, world frame).
    :param wrench_age: seconds since the applied wrench came, or None without one.
    :param wrench_timeout: the node's ``wrench_timeout`` (s, 0 = never).
    """
    level = OK
    problems = []
    if pacing.publish_clock and pacing.slipped > 0.0:
        level = WARN
        problems.append(f'real_time_factor {pacing.real_time_factor:g} not kept: simulated '
                        f'time fell {pacing.slipped:.3g} s behind in the window')
    parts = ['paused' if pacing.paused else 'running']
    if pacing.publish_clock and pacing.achieved_factor is not None:
        parts.append(f'publishing /clock, {pacing.achieved_factor:.3g}x real time')
    elif pacing.publish_clock:
        parts.append('publishing /clock')
    if wrench_age is not None:
        parts.append(f'wrench {math.hypot(*force):.3g} N, {math.hypot(*torque):.3g} N m')
    values = [
        KeyValue(key='clock',
                 value='published (/clock)' if pacing.publish_clock else "the node's clock"),
        KeyValue(key=PAUSED_KEY, value='true' if pacing.paused else 'false'),
        KeyValue(key='simulated time (s)', value=_value(pacing.simulated_time, 12)),
        KeyValue(key='real time factor', value=_value(pacing.real_time_factor)),
        KeyValue(key='achieved real time factor', value=_value(pacing.achieved_factor, 4)),
        KeyValue(key='slipped simulated time (s)', value=_value(pacing.slipped, 4)),
        KeyValue(key='wrench force (N)', value=' '.join(_value(c) for c in force)),
        KeyValue(key='wrench torque (N m)', value=' '.join(_value(c) for c in torque)),
        KeyValue(key='wrench age (s)', value=_value(wrench_age, 4)),
        KeyValue(key='wrench timeout (s)', value=_value(wrench_timeout)),
    ]
    return _status(name, hardware_id, level=level, problems=problems, fine=', '.join(parts),
                   values=values)
