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
The node's own ``anchor`` parameter: set by a grab, restored by ``~/reset``.

A grab makes the grabbed point the anchor through the node's ``anchor`` parameter, validated as
any change, so that the configuration, ``ros2 param get`` and the markers all show it. That
anchor is not the configured one: ``~/reset`` restores the anchor the node started with or was
last given through its parameters.
"""

from typing import Iterable, Optional, Tuple

from rclpy.node import Node
from rclpy.parameter import Parameter

from ..physics.algebra import Vector3


class AnchorParameter:
    """
    Sets the node's ``anchor`` parameter for a grab or a reset; keeps the configured anchor.

    :param node: the node whose parameter is set.
    :param configured: the anchor the node starts with.
    """

    def __init__(self, node: Node, configured: Vector3) -> None:
        """Keep ``configured`` as the anchor ``restore`` returns to."""
        self._node = node
        self.configured = configured
        # True while the node sets its own anchor parameter for a grab or a reset.
        self.setting = False

    def set_to(self, anchor: Vector3) -> Optional[str]:
        """Set the node's ``anchor`` parameter to ``anchor``; None, or why it could not be."""
        self.setting = True
        try:
            [result] = self._node.set_parameters([Parameter('anchor', value=list(anchor))])
        finally:
            self.setting = False
        return None if result.successful else result.reason

    def restore(self, current: Vector3) -> Optional[Tuple[Vector3, str]]:
        """Set the configured anchor again; None, or (that anchor, why it could not be)."""
        configured = self.configured
        if current == configured:
            return None
        reason = self.set_to(configured)
        return None if reason is None else (configured, reason)

    def changed(self, changes: Iterable[Parameter], anchor: Vector3) -> None:
        """Take ``anchor`` as the configured one when a user's change sets it."""
        if not self.setting and any(p.name == 'anchor' for p in changes):
            self.configured = anchor
