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
The newest message of a fast topic, taken when the view wants it rather than each time one comes.

The node publishes its pose and twist at its publish rate, 1 kHz by default; the view needs the
newest at most 60 times a second. A subscription in an executor costs a Python callback per
message, 2 000 a second for pose and twist; ``NewestMessage`` keeps its subscription out of
every executor (on a node of its own that is never spun) with depth 1, so the middleware keeps
only the newest message, and ``take`` reads it, serialized, with rclpy's own take (as
``rclpy.wait_for_message`` does).
"""

from typing import Optional

from rclpy.node import Node
from rclpy.qos import QoSProfile


class NewestMessage:
    """
    The newest serialized message on ``topic``, read on demand.

    :param node: a node that no executor spins (its subscriptions are taken only here).
    :param message_type: the topic's message type.
    :param topic: the topic, resolved as the node resolves names.
    :param qos: the subscription's QoS; depth 1 keeps only the newest.
    """

    def __init__(self, node: Node, message_type, topic: str, qos: QoSProfile) -> None:
        """Subscribe; nothing is taken until ``take``."""
        self.subscription = node.create_subscription(message_type, topic, lambda _: None, qos,
                                                     raw=True)

    @property
    def topic_name(self) -> str:
        """Return the subscription's resolved topic."""
        return self.subscription.topic_name

    def take(self) -> Optional[bytes]:
        """Return the newest message that came since the last take, serialized, or None."""
        newest = None
        subscription = self.subscription
        with subscription.handle:
            while True:
                taken = subscription.handle.take_message(subscription.msg_type, True)
                if taken is None:
                    return newest
                newest = taken[0]
