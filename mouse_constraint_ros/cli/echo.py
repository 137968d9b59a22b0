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
What ``mouse_ctl echo`` prints: a line per message it shows, with the rate the messages come at.

``ECHOES`` names what can be echoed: ``pose``, ``twist`` and ``force`` (what the node
publishes; ``force`` is the force the pointer feels, with ``publish_force``) and ``wrench``
(the pushes on the node's ``wrench`` input, a force through the COM and a torque);
each is a relative topic of stamped doubles, read raw (``wire.cdr.stamped``), and the names
and units of its fields. Another stamped output of the node is echoed by adding its row.

``EchoPrinter`` takes each message as received. It keeps the stamps of the last second of them
(``RateMeter``), so that each line ends with the rate the messages come at on the node's clock
(the stamps: in lockstep or at any real-time factor, the node's own rate when none is lost),
and shows at most ``print_rate`` lines per second of those stamps (a 1 kHz node would flood a
terminal); 0 shows every message. A message whose bytes are not its type is counted, not shown.

When no message comes, ``silence`` says why as the graph tells it (``Graph``): no node, a topic
nothing publishes, or a node that publishes it and is paused, which its ``/diagnostics``
simulator status says (``paused_in``).
"""

from collections import deque
from typing import Callable, Deque, NamedTuple, Optional, Tuple

from diagnostic_msgs.msg import DiagnosticArray
from geometry_msgs.msg import PoseStamped, TwistStamped, WrenchStamped

from ..wire.cdr.stamped import decode_stamped, Refusal
from ..wire.interface import (FORCE_TOPIC, PAUSED_KEY, POSE_TOPIC, SIMULATOR_STATUS_SUFFIX,
                              TWIST_TOPIC, WRENCH_TOPIC)

# The stamps the rate is measured over (ns of the node's clock).
RATE_WINDOW_NS = 1_000_000_000


class Echo(NamedTuple):
    """
    A stamped topic to echo: its name and type, and its fields as (label, size, unit).

    ``source`` says what publishes it, for when nothing does; ``from_node``: the node publishes
    it (while it runs), else the node reads it (its input); ``switch``: the node's boolean
    parameter that turns it on, if any.
    """

    topic: str
    message_type: type
    fields: Tuple[Tuple[str, int, str], ...]
    source: str
    from_node: bool = True
    switch: Optional[str] = None

    @property
    def count(self) -> int:
        """Return the number of doubles after the header."""
        return sum(size for _, size, _ in self.fields)


ECHOES = {
    'pose': Echo(POSE_TOPIC, PoseStamped,
                 (('position', 3, 'm'), ('orientation', 4, '(x, y, z, w)')),
                 'the node publishes it at every tick it publishes'),
    'twist': Echo(TWIST_TOPIC, TwistStamped, (('linear', 3, 'm/s'), ('angular', 3, 'rad/s')),
                  'the node publishes it at every tick it publishes'),
    'force': Echo(FORCE_TOPIC, WrenchStamped, (('force', 3, 'N'), ('torque', 3, 'N m')),
                  'the node publishes it with publish_force true', switch='publish_force'),
    'wrench': Echo(WRENCH_TOPIC, WrenchStamped, (('force', 3, 'N'), ('torque', 3, 'N m')),
                   "the node's wrench input: mouse_wrench or another client publishes it",
                   from_node=False),
}


class RateMeter:
    """The rate of the stamps received within the last ``RATE_WINDOW_NS`` of them."""

    def __init__(self) -> None:
        """Start with no stamp."""
        self._stamps: Deque[int] = deque()

    def add(self, stamp_ns: int) -> None:
        """Take a stamp; one that goes back (a reset, a clock jump) starts the window again."""
        stamps = self._stamps
        if stamps and stamp_ns < stamps[-1]:
            stamps.clear()
        stamps.append(stamp_ns)
        while stamp_ns - stamps[0] > RATE_WINDOW_NS:
            stamps.popleft()

    def rate(self) -> Optional[float]:
        """Return the messages per second of stamps, None before two distinct stamps."""
        stamps = self._stamps
        if len(stamps) < 2 or stamps[-1] == stamps[0]:
            return None
        return (len(stamps) - 1) * 1e9 / (stamps[-1] - stamps[0])


def vector(values) -> str:
    """Return numbers as '(x, y, z)', each to the micro-unit."""
    return '(' + ', '.join(f'{value:.6f}' for value in values) + ')'


class EchoPrinter:
    """
    Lines for the messages of one ``Echo``, at most ``print_rate`` a second of their stamps.

    :param echo: what is echoed.
    :param write: called with each line.
    :param print_rate: the most lines a second of stamps (Hz); 0 shows every message.
    """

    def __init__(self, echo: Echo, write: Callable[[str], None], *,
                 print_rate: float = 10.0) -> None:
        """Show nothing yet."""
        self._echo, self._write = echo, write
        self._gap_ns = 0 if print_rate == 0.0 else round(1e9 / print_rate)
        self._shown: Optional[int] = None
        self.meter = RateMeter()
        self.topic = echo.topic  # resolved once subscribed
        self.received = 0
        self.printed = 0
        self.unreadable = 0

    def take(self, data: bytes) -> None:
        """Take one message as received (its serialized bytes)."""
        fields = decode_stamped(data, self._echo.count)
        if isinstance(fields, Refusal):
            self.unreadable += 1
            return
        self.received += 1
        stamp = fields.stamp_ns
        self.meter.add(stamp)
        shown = self._shown
        if shown is not None and 0 <= stamp - shown < self._gap_ns:
            return
        self._shown = stamp
        self.printed += 1
        self._write(self.line(stamp, fields.values))

    def line(self, stamp_ns: int, values) -> str:
        """Return the line of one message: stamp, fields with units, the rate."""
        parts, start = [f'{stamp_ns * 1e-9:.6f} s'], 0
        for label, size, unit in self._echo.fields:
            parts.append(f'{label} {vector(values[start:start + size])} {unit}')
            start += size
        rate = self.meter.rate()
        parts.append('rate -' if rate is None else f'rate {rate:.1f} Hz')
        return '  '.join(parts)


def paused_in(array: DiagnosticArray, node_name: str) -> Optional[bool]:
    """
    Return whether a ``/diagnostics`` message says the node ``node_name`` is paused.

    :param node_name: the node's fully qualified name (``/robot/mouse_constraint``).
    :returns: None when ``array`` has no simulator status of that node.
    """
    for status in array.status:
        if status.name == node_name + SIMULATOR_STATUS_SUFFIX:
            for pair in status.values:
                if pair.key == PAUSED_KEY:
                    return pair.value == 'true'
    return None


class Graph(NamedTuple):
    """
    What the graph says of an echo that got no message: the node, the topic's publishers.

    ``paused``: whether the node's /diagnostics say it is paused; ``switched_on``: the value of
    the echo's ``switch`` parameter on the node; None where not known.
    """

    node: str
    node_found: bool
    publishers: int
    paused: Optional[bool] = None
    switched_on: Optional[bool] = None


def silence(echo: Echo, topic: str, timeout: float, graph: Graph) -> str:
    """
    Return why no message came on ``topic`` (``echo``'s, resolved) in ``timeout`` s.

    The topic is switched off (``force`` with publish_force false, its publisher silent or
    none). Nothing publishes it: the node is not there (the usual reason), or it is and nothing
    publishes it (an input nobody sends). Something publishes it and sent nothing: the node is
    paused, as its /diagnostics say, or its clock stands still.
    """
    head = f'no message on {topic} after {timeout:g} s: '
    node = graph.node
    if graph.switched_on is False:
        return head + f'{node} has {echo.switch} false: it publishes {topic} once it is true'
    if graph.publishers == 0:
        if echo.from_node and not graph.node_found:
            return head + (f'no node {node}: is the node running (same ROS_DOMAIN_ID and '
                           'namespace, --node)?')
        there = f'{node} is running, but ' if echo.from_node else ''
        return head + f'{there}nothing publishes {topic} ({echo.source})'
    count = f'{graph.publishers} publisher' + ('s' if graph.publishers > 1 else '')
    if not echo.from_node:
        return head + f'{topic} has {count}, none sent a message'
    if graph.paused:
        return head + (f'{node} is paused: it publishes {topic} again once resumed '
                       '(mouse_ctl resume) or stepped (mouse_ctl step)')
    still = ('its clock may stand still (use_sim_time: no /clock)' if graph.paused is False else
             f'{node} may be paused (mouse_ctl resume), or its clock stand still (use_sim_time: '
             'no /clock)')
    return head + f'{topic} has {count}, none sent a message: {still}'
