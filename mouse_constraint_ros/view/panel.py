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
The view's panel: its buttons' calls to the node's services, and the numbers and status it shows.

``NodeServices`` calls ``~/pause``, ``~/step``, ``~/reset`` and ``~/release`` and hands each
answer to the page; ``PanelReadings`` reads the COM speed and the force felt from the newest
twist and force; ``status_text`` and ``numbers_text`` write what the panel shows.
"""

import math
from typing import Callable, Dict, Optional, Tuple

from geometry_msgs.msg import TwistStamped, WrenchStamped
from rclpy.node import Node
from rclpy.qos import QoSProfile
from rclpy.serialization import deserialize_message
from std_srvs.srv import SetBool, Trigger

from ..physics.algebra import Vector3
from ..pointer.newest_message import NewestMessage
from ..pointer.node_readouts import force_text, number_text, Readouts
from ..pointer.service_calls import ServiceCalls
from ..wire.interface import (FORCE_TOPIC, NODE_NAME, PAUSE_SERVICE, RELEASE_SERVICE,
                              RESET_SERVICE, STEP_SERVICE, TWIST_TOPIC)


def node_name(private: str) -> str:
    """Return a private name of the node (``~/reset``) as the view reaches it (relative)."""
    return NODE_NAME + private[1:] if private.startswith('~') else private


def _vector(raw: Optional[bytes], message_type,
            field) -> Tuple[Optional[bytes], Optional[Vector3]]:
    """
    Return (``raw``, the Vector3 ``field(message)`` of it as a tuple), or (None, None).

    A message that does not decode is passed over: the panel shows n/a until a good one comes.
    """
    if raw is None:
        return None, None
    try:
        vector = field(deserialize_message(raw, message_type))
    except Exception:
        return None, None
    return raw, (vector.x, vector.y, vector.z)


class NodeServices:
    """
    The node's services the panel's buttons call, each answer shown on the page.

    :param node: the view's node, which makes the clients (and whose executor runs them).
    :param target_node: the node's full name, as the answers name it.
    :param show_reply: shows a line on the page (the scene's ``show_reply``).
    :param calls: where the calls wait for their answers, each given up when unanswered.
    """

    def __init__(self, node: Node, target_node: str, show_reply: Callable[[str], None],
                 calls: ServiceCalls) -> None:
        """Create a client for each of the node's services."""
        self.target_node, self._show_reply, self.calls = target_node, show_reply, calls
        self.clients: Dict[str, object] = {
            name: node.create_client(kind, node_name(name)) for name, kind in (
                (PAUSE_SERVICE, SetBool), (STEP_SERVICE, Trigger), (RESET_SERVICE, Trigger),
                (RELEASE_SERVICE, Trigger))}

    def call(self, service: str, data: Optional[bool] = None, *,
             on_answer: Optional[Callable[[], None]] = None) -> bool:
        """
        Call one of the node's services; show its answer on the page.

        :param service: the service's name (private to the node).
        :param data: the request's ``data`` (SetBool).
        :param on_answer: called once the node answered, after the page shows it (also when
            that fails), or once the call was given up unanswered (``ServiceCalls``).
        :returns: whether the call went out (False: no such service).
        """
        client = self.clients[service]
        name = self.target_node + service[1:]
        if not client.service_is_ready():
            self._show_reply(f'{name}: no such service (is the node running?)')
            return False
        request = client.srv_type.Request()
        if data is not None:
            request.data = data

        def answered(done) -> None:
            try:
                response = done.result()
                if response is not None:
                    self._show_reply(f'{name}: {response.message}')
            finally:
                if on_answer is not None:
                    on_answer()

        def given_up() -> None:
            self._show_reply(f'{name}: no answer in {self.calls.timeout:g} s')
            if on_answer is not None:
                on_answer()
        self.calls.call(client, request, on_answer=answered, on_give_up=given_up)
        return True


class PanelReadings:
    """
    The COM speed and the force felt, from the newest twist and force the node published.

    :param reader: a node no executor spins (``NewestMessage``'s).
    :param qos: the subscriptions' QoS (only the newest matters).
    """

    def __init__(self, reader: Node, qos: QoSProfile) -> None:
        """Subscribe to the twist and to the force the pointer feels (with publish_force)."""
        self.twists = NewestMessage(reader, TwistStamped, TWIST_TOPIC, qos)
        self.forces = NewestMessage(reader, WrenchStamped, FORCE_TOPIC, qos)
        self._twist_raw: Optional[bytes] = None
        self._force_raw: Optional[bytes] = None

    def speed(self) -> Optional[float]:
        """Return the COM speed of the newest twist (m/s), or None before a good one."""
        self._twist_raw, linear = _vector(self.twists.take() or self._twist_raw, TwistStamped,
                                          lambda m: m.twist.linear)
        return None if linear is None else math.sqrt(sum(c * c for c in linear))

    def force(self, publish_force: bool) -> Optional[Vector3]:
        """
        Return the newest force felt (N), or None while it is off or no good message came.

        :param publish_force: the node's parameter: the last force shown goes with it (off
            shows n/a again), not with its publisher, which stays when it is turned off.
        """
        held = self._force_raw if publish_force else None
        self._force_raw, force = _vector(self.forces.take() or held, WrenchStamped,
                                         lambda m: m.wrench.force)
        return force


def status_text(target_node: str, topic: str, present: Optional[bool]) -> str:
    """
    Return the panel's status: looking for the node, the node, or no node.

    :param target_node: the node's full name.
    :param topic: the pose topic the view reads.
    :param present: None while discovery may still run, then whether the node is there.
    """
    if present is None:
        return f'looking for **{target_node}** on `{topic}`'
    return (f'**{target_node}** on `{topic}`' if present else
            f'**no node on {topic}**: waiting for it (`make run`)')


def numbers_text(speed: Optional[float], readouts: Readouts, force: Optional[Vector3],
                 mode: str) -> str:
    """
    Return the panel's numbers, one a line; n/a where one is not known.

    :param speed: the COM speed (m/s).
    :param readouts: what /diagnostics said: the anchor error and the rate.
    :param force: the force felt (N).
    :param mode: the joint's mode, from the node's parameters.
    """
    return '  \n'.join((
        f'COM speed: {number_text(speed, "m/s")}',
        f'anchor error: {number_text(readouts.anchor_error, "mm", scale=1e3, decimals=2)}',
        f'force felt: {force_text(force)}',
        f'rate: {number_text(readouts.rate_hz, "Hz", decimals=1)}',
        f'mode: {mode}'))
