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
A client's view of the ``mouse_constraint`` node: whether it is there, and its parameters.

``NodeFollower`` is the part the web view and the RViz marker server share: each look
(``look``, on the owner's timer) counts the publishers of the pose topic, says in one log line
when the node comes or goes, and reads the parameters a client draws with (``ViewParameters``)
with the node's ``get_parameters`` whenever it comes (back); between looks it follows
``/parameter_events``. It says there is no node only after looking ``discovery_seconds``: a
running node is seen at once when the first discovery announcements meet, else at Fast DDS's
next periodic announcement, up to 3 s after the client starts.
"""

import time
from typing import Callable, Optional

from rcl_interfaces.msg import ParameterEvent
from rcl_interfaces.srv import GetParameters
from rclpy.node import Node
from rclpy.qos import qos_profile_parameter_events

from .node_readouts import ViewParameters
from .service_calls import ServiceCalls
from ..wire.interface import NODE_NAME, node_name

# The parameters a client draws with.
PARAMETER_NAMES = list(ViewParameters._fields)
# How long after its start a client looks for the node before it says there is none (s): one
# period of Fast DDS's participant announcements (3 s), and the client's own start.
DISCOVERY_SECONDS = 5.0
# A question for the parameters unanswered this long is asked again (s).
ASK_AGAIN_SECONDS = 2.0


class NodeFollower:
    """
    The node's presence and parameters, as one client sees them.

    :param node: the client's node (its namespace is the followed node's).
    :param topic: the resolved pose topic whose publishers say the node is there.
    :param on_parameters: called with the parameters whenever they change.
    :param discovery_seconds: how long it looks before it says there is no node.
    :param clock: seconds of a monotonic clock.
    """

    def __init__(self, node: Node, *, topic: str,
                 on_parameters: Callable[[ViewParameters], None],
                 discovery_seconds: float = DISCOVERY_SECONDS,
                 clock: Callable[[], float] = time.monotonic) -> None:
        """Create the parameter client and the /parameter_events subscription."""
        self._node, self._topic = node, topic
        self._on_parameters = on_parameters
        self._clock = clock
        self._discovered_by = clock() + discovery_seconds
        self.target_node = node_name(node.get_namespace(), NODE_NAME)
        self.parameters = ViewParameters()
        self.present: Optional[bool] = None  # None: still looking
        self.parameters_known = False  # answered by the node since it came
        self._asked_at: Optional[float] = None  # when the question in flight went
        self._get_parameters = node.create_client(GetParameters, f'{NODE_NAME}/get_parameters')
        self._calls = ServiceCalls(timeout=ASK_AGAIN_SECONDS, clock=clock)
        node.create_subscription(ParameterEvent, '/parameter_events', self._on_event,
                                 qos_profile_parameter_events)

    def look(self) -> None:
        """Look for the node: log when it comes or goes; ask for its parameters when it came."""
        present = self._node.count_publishers(self._topic) > 0
        if not present and self.present is None and self._clock() < self._discovered_by:
            return  # Still discovering: a running node may not be seen yet.
        if present != self.present:
            self._node.get_logger().info(
                f'{self.target_node} publishes on {self._topic}' if present else
                f'no node on {self._topic}: waiting for it')
        now = self._clock()
        if not present:
            self.parameters_known, self._asked_at = False, None
        elif (not self.parameters_known and self._get_parameters.service_is_ready()
              and (self._asked_at is None or now - self._asked_at > ASK_AGAIN_SECONDS)):
            self._asked_at = now
            # The question before, unanswered, is given up: one at a time is pending.
            self._calls.call(self._get_parameters, GetParameters.Request(names=PARAMETER_NAMES),
                             on_answer=self._answered)
        self.present = present

    def _answered(self, done) -> None:
        self._asked_at = None
        response = done.result()
        if response is None or len(response.values) != len(PARAMETER_NAMES):
            return  # Asked again at the next look.
        self.parameters_known = True  # before the owner hears of them: it may draw with them
        self._set(zip(PARAMETER_NAMES, response.values))

    def _on_event(self, event: ParameterEvent) -> None:
        if event.node != self.target_node:
            return
        self._set((p.name, p.value) for p in (*event.new_parameters, *event.changed_parameters))

    def _set(self, pairs) -> None:
        self.parameters = self.parameters.with_values(pairs)
        self._on_parameters(self.parameters)
