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
The harness's probe: its own node, which sends a user's inputs and keeps what the node publishes.

Inputs go out as a user's would, as messages and service calls on the node's topics and
services; the node's own validation judges them, and ``send`` raises ``InputRefused`` with the
node's reason when the node refused one. The latest ``pose`` and ``twist`` are kept as the
messages, the pose with the anchor in effect when the node published it.
"""

from typing import Callable, Optional

from geometry_msgs.msg import PointStamped, PoseStamped, TwistStamped, WrenchStamped
from rclpy.event_handler import PublisherEventCallbacks, SubscriptionEventCallbacks
from rclpy.node import Node
from rclpy.parameter import Parameter
from rclpy.type_description_service import START_TYPE_DESCRIPTION_SERVICE_PARAM
from sensor_msgs.msg import JointState
from std_srvs.srv import Trigger

from .errors import InputRefused
from ..node.mouse_constraint_node import MouseConstraintNode
from ..wire.interface import (GRAB_TOPIC, JOINT_STATES_QOS, JOINT_STATES_TOPIC, POSE_TOPIC,
                              STATE_QOS, TARGET_QOS, TARGET_TOPIC, TWIST_TOPIC, WRENCH_QOS,
                              WRENCH_TOPIC)

# The name of the probe's node.
PROBE_NAME = 'simulated_body'


class Probe:
    """
    A node beside ``node``: its input publishers and service clients, its pose and twist.

    :param node: the node under test, whose refusals ``send`` checks.
    :param namespace: the node's namespace.
    :param drain: runs every callback that is ready (the harness's drain).
    """

    def __init__(self, node: MouseConstraintNode, *, namespace: str,
                 drain: Callable[[], object]) -> None:
        """Create the probe's node, its subscriptions, publishers and clients."""
        self._target_node = node
        self._drain = drain
        self.pose: Optional[PoseStamped] = None
        self.twist: Optional[TwistStamped] = None
        self.joint_states: Optional[JointState] = None  # a robot's
        # The anchor in effect when the node published ``pose``: a grab changes it between ticks.
        self.pose_anchor = None
        # Only what it sends and reads: every entity of a node is added to the executor's wait
        # set at each of the waits of a drain (two or more a tick). No parameter or type
        # services and no QoS event handlers (``wait_matched`` names what does not match, with
        # the QoS policy): 11 entities fewer in each wait.
        probe = self.node = Node(
            PROBE_NAME, namespace=namespace, context=node.context,
            start_parameter_services=False, parameter_overrides=[
                Parameter(START_TYPE_DESCRIPTION_SERVICE_PARAM, value=False)])
        quiet = {'event_callbacks': SubscriptionEventCallbacks(use_default_callbacks=False)}
        probe.create_subscription(PoseStamped, POSE_TOPIC, self._on_pose, STATE_QOS, **quiet)
        probe.create_subscription(TwistStamped, TWIST_TOPIC, self._on_twist, STATE_QOS, **quiet)
        probe.create_subscription(JointState, JOINT_STATES_TOPIC, self._on_joint_states,
                                  JOINT_STATES_QOS, **quiet)
        quiet = {'event_callbacks': PublisherEventCallbacks(use_default_callbacks=False)}
        self.publishers = {
            'target': probe.create_publisher(PointStamped, TARGET_TOPIC, TARGET_QOS, **quiet),
            'grab': probe.create_publisher(PointStamped, GRAB_TOPIC, TARGET_QOS, **quiet),
            'wrench': probe.create_publisher(WrenchStamped, WRENCH_TOPIC, WRENCH_QOS, **quiet)}
        name = node.get_fully_qualified_name()
        self.clients = {service: probe.create_client(Trigger, f'{name}/{service}')
                        for service in ('reset', 'release')}

    def _on_pose(self, message: PoseStamped) -> None:
        self.pose = message
        self.pose_anchor = self._target_node.get_parameter('anchor').value

    def _on_twist(self, message: TwistStamped) -> None:
        self.twist = message

    def _on_joint_states(self, message: JointState) -> None:
        self.joint_states = message

    def send(self, kind: str, message) -> None:
        """Publish ``message`` on the ``kind`` input, drain, and raise if the node refused it."""
        node = self._target_node
        before = node.refusals[0]
        self.publishers[kind].publish(message)
        self._drain()
        count, refusal = node.refusals
        if count > before:
            raise InputRefused(refusal.key, refusal.reason)

    def call(self, service: str) -> Trigger.Response:
        """Call the node's ``~/service`` (a Trigger), drain, and return its answer."""
        client = self.clients[service]
        future = client.call_async(Trigger.Request())
        self._drain()
        if not future.done():
            raise AssertionError(f'{client.srv_name} did not answer within a drain')
        return future.result()
