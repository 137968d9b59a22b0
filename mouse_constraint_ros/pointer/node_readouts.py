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
What the view reads from the node: the parameters it draws with, and the panel's live numbers.

``ViewParameters`` holds the node parameters the page needs: ``frame_id`` (of the points the
view sends), the body's shape (``robot_description``, ``body_link`` and ``density``: a URDF
link, else the box of ``box_size``; ``body_shape`` makes it), ``anchor`` (the dragged point, in
the body's frame: the link frame of a URDF), ``frequency_hz`` (0: rigid mode, else soft),
``grab_margin`` (how far off the body a grab is taken) and, where the node has them, ``floor``,
``floor_height`` and ``publish_force`` (whether the felt force is on: its publisher stays when
it is turned off), and a whole robot's ``base``, ``base_pose`` and ``tracked_link``
(``robot_shape``). ``with_values`` takes them from a ``GetParameters`` answer or a
``/parameter_events`` message: a parameter it does not know, of another type or with a value it
cannot draw (a non-finite or non-positive box edge, a negative density) is passed over, never
raised on.

``Readouts`` picks the node's own statuses out of ``/diagnostics`` (``<node>: rate``,
``<node>: constraint``, ``<node>: simulator``): the achieved rate, the anchor error and whether
it is paused. No rclpy here: messages in, plain values out.
"""

import math
from typing import Iterable, NamedTuple, Optional, Tuple

from diagnostic_msgs.msg import DiagnosticArray
from rcl_interfaces.msg import ParameterType, ParameterValue

from ..physics.algebra import Vector3
from ..wire.interface import PAUSED_KEY, SIMULATOR_STATUS_SUFFIX

# The node's statuses are named '<fully qualified node name><suffix>' (see the diagnostics
# module; the simulator's suffix and its paused key are the interface's); the keys are the ones
# its builders write.
RATE_SUFFIX, CONSTRAINT_SUFFIX = ': rate', ': constraint'
ACHIEVED_RATE_KEY = 'achieved rate (Hz)'
ANCHOR_ERROR_KEY = 'anchor error (m)'


class ViewParameters(NamedTuple):
    """The node's parameters the page is drawn with (the node's defaults until it answers)."""

    frame_id: str = ''
    box_size: Vector3 = (0.4, 0.2, 0.1)
    anchor: Vector3 = (0.2, 0.1, 0.05)
    frequency_hz: float = 0.0
    floor: bool = False
    floor_height: float = 0.0
    grab_margin: float = 0.01
    robot_description: str = ''
    body_link: str = ''
    density: float = 0.0
    publish_force: bool = False
    base: str = 'fixed'
    base_pose: Tuple[float, ...] = (0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 1.0)
    tracked_link: str = ''

    @property
    def mode(self) -> str:
        """Return 'rigid' (frequency_hz 0) or 'soft, <f> Hz'."""
        return 'rigid' if self.frequency_hz == 0.0 else f'soft, {self.frequency_hz:g} Hz'

    def with_values(self, pairs: Iterable[Tuple[str, ParameterValue]]) -> 'ViewParameters':
        """Return these parameters with the known, valid ones of ``pairs`` (name, value) set."""
        changes = {}
        for name, value in pairs:
            parsed = _parse(name, value)
            if parsed is not None:
                changes[name] = parsed
        return self._replace(**changes)


def _vector(value: ParameterValue, positive: bool) -> Optional[Vector3]:
    array = tuple(float(c) for c in value.double_array_value)
    if len(array) != 3 or not all(math.isfinite(c) for c in array):
        return None
    if positive and not all(c > 0.0 for c in array):
        return None
    return array


def _parse(name: str, value: ParameterValue):
    kind = value.type
    if name in ('frame_id', 'robot_description', 'body_link', 'base', 'tracked_link') \
            and kind == ParameterType.PARAMETER_STRING:
        return value.string_value
    if name in ('box_size', 'anchor') and kind == ParameterType.PARAMETER_DOUBLE_ARRAY:
        return _vector(value, positive=name == 'box_size')
    if name == 'base_pose' and kind == ParameterType.PARAMETER_DOUBLE_ARRAY:
        pose = tuple(float(c) for c in value.double_array_value)
        return pose if len(pose) == 7 and all(math.isfinite(c) for c in pose) else None
    if name in ('frequency_hz', 'floor_height', 'grab_margin', 'density') \
            and kind == ParameterType.PARAMETER_DOUBLE:
        number = value.double_value
        return number if math.isfinite(number) and (name == 'floor_height' or number >= 0.0) \
            else None
    if name in ('floor', 'publish_force') and kind == ParameterType.PARAMETER_BOOL:
        return value.bool_value
    return None


def _number(text: str) -> Optional[float]:
    try:
        number = float(text)
    except ValueError:
        return None
    return number if math.isfinite(number) else None


class Readouts(NamedTuple):
    """The node's live numbers from its last ``/diagnostics`` (None: not reported yet)."""

    rate_hz: Optional[float] = None
    anchor_error: Optional[float] = None
    paused: Optional[bool] = None

    def updated(self, array: DiagnosticArray, node_name: str) -> 'Readouts':
        """
        Return these readouts with what ``array`` says about the node ``node_name``.

        :param array: a ``/diagnostics`` message, from any node.
        :param node_name: the node's fully qualified name (``/robot/mouse_constraint``).
        """
        readouts = self
        for status in array.status:
            values = {pair.key: pair.value for pair in status.values}
            if status.name == node_name + RATE_SUFFIX and ACHIEVED_RATE_KEY in values:
                readouts = readouts._replace(rate_hz=_number(values[ACHIEVED_RATE_KEY]))
            elif status.name == node_name + CONSTRAINT_SUFFIX and ANCHOR_ERROR_KEY in values:
                readouts = readouts._replace(anchor_error=_number(values[ANCHOR_ERROR_KEY]))
            elif status.name == node_name + SIMULATOR_STATUS_SUFFIX and PAUSED_KEY in values:
                readouts = readouts._replace(paused=values[PAUSED_KEY] == 'true')
        return readouts


def number_text(number: Optional[float], unit: str, *, scale: float = 1.0,
                decimals: int = 3) -> str:
    """Return ``number`` times ``scale`` with ``decimals`` decimals and ``unit``, or 'n/a'."""
    return 'n/a' if number is None else f'{scale * number:.{decimals}f} {unit}'


def force_text(force: Optional[Vector3]) -> str:
    """Return the felt force as its magnitude and components in N, or 'n/a' without one."""
    if force is None:
        return 'n/a (publish_force off)'
    x, y, z = force
    # Rounded first, and -0.0 made 0.0: a component that rounds to zero shows no sign.
    shown = ', '.join(f'{round(c, 2) + 0.0:.2f}' for c in force)
    return f'{math.sqrt(x * x + y * y + z * z):.2f} N ({shown})'
