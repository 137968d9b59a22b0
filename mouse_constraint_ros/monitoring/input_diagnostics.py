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
The inputs status of /diagnostics: what the node refused and why, and whether a device is heard.

A device whose poses are all refused (another frame, not finite, outside the workspace) moves
nothing, and before ``device_timeout`` it would still feel the held body's force; this status
says so to whoever reads /diagnostics (``mouse_ctl echo inputs``): how many inputs were refused,
by reason, the last one's line, the device's state and, when it clocks the ticks, how many it
ran, how many came early or late, and how many it sent that never came (the gaps in their
stamps: ``inputs.pose_gaps``). It is WARN while inputs are being refused or poses lost (some
since the last report) or the device is silent (its force is then zero).
"""

from typing import Mapping, NamedTuple, Optional

from diagnostic_msgs.msg import DiagnosticStatus, KeyValue

OK, WARN = DiagnosticStatus.OK, DiagnosticStatus.WARN
# The device states: no pose came on target_pose yet; poses come; none valid for the timeout.
DEVICE_UNHEARD = 'no pose on target_pose yet'
DEVICE_SILENT = 'silent: force zero'


class InputReport(NamedTuple):
    """What the inputs status says: the refusals so far and the device's state."""

    refused: int
    by_key: Mapping[str, int]
    last_line: str
    new_refusals: int
    device_age: Optional[float]
    device_silent: bool
    device_timeout: float
    # With tick_source target_pose: the ticks the device's poses ran, early and late ones.
    device_ticks: Optional[tuple] = None
    # With tick_source target_pose: the device's poses lost (gaps in their stamps), in all and
    # since the last report.
    device_lost: Optional[int] = None
    new_lost: int = 0


def device_state(report: InputReport) -> str:
    """Return the device's state in words: unheard, silent, or the age of its last valid pose."""
    if report.device_age is None:
        return DEVICE_UNHEARD
    if report.device_silent:
        return f'{DEVICE_SILENT} (no valid pose for {report.device_age:.3f} s)'
    return f'valid pose {report.device_age:.3f} s ago'


def input_status(name: str, hardware_id: str, report: InputReport) -> DiagnosticStatus:
    """
    Return the inputs status of ``report``.

    :param name: the status name, ``<fully qualified node name>: inputs``.
    :param hardware_id: the status's hardware_id.
    """
    problems = []
    if report.new_refusals:
        problems.append(f'{report.new_refusals} inputs refused since the last report, the last '
                        f'{report.last_line}')
    if report.new_lost:
        problems.append(f'{report.new_lost} device poses lost since the last report (gaps in '
                        'their stamps)')
    if report.device_silent:
        problems.append(f'device {device_state(report)}')
    by_key = ', '.join(f'{key} {count}' for key, count in sorted(report.by_key.items()))
    values = [
        KeyValue(key='refused inputs', value=str(report.refused)),
        KeyValue(key='refused by reason', value=by_key or 'none'),
        KeyValue(key='last refusal', value=report.last_line or 'none'),
        KeyValue(key='device', value=device_state(report)),
        KeyValue(key='device timeout (s)', value=f'{report.device_timeout:g}'),
        KeyValue(key='device ticks (early, late)', value='off: tick_source clock'
                 if report.device_ticks is None else '{} ({}, {})'.format(*report.device_ticks)),
        KeyValue(key='device poses lost', value='off: tick_source clock'
                 if report.device_lost is None else str(report.device_lost)),
    ]
    return DiagnosticStatus(level=WARN if problems else OK, name=name, hardware_id=hardware_id,
                            message='; '.join(problems) if problems else (
                                'no input refused since the last report' if report.refused
                                else 'no input refused'),
                            values=values)
