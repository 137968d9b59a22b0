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

"""A node that never answers, and a clock moved on by hand: for the tools' unanswered calls."""

import contextlib
from typing import Iterator

from geometry_msgs.msg import PoseStamped
import rclpy
from rclpy.node import Node
from std_srvs.srv import Trigger


@contextlib.contextmanager
def silent_node() -> Iterator[Node]:
    """
    Yield a node ``mouse_constraint`` of a context of its own that is never spun.

    It publishes ``pose`` (the tools see it there) and offers ``~/release`` and its parameter
    services: the tools' clients see them ready, and their requests go unanswered.
    """
    context = rclpy.Context()
    rclpy.init(context=context)
    node = Node('mouse_constraint', context=context)
    node.create_service(Trigger, '~/release', lambda _request, response: response)
    node.create_publisher(PoseStamped, 'pose', 10)
    try:
        yield node
    finally:
        node.destroy_node()
        rclpy.try_shutdown(context=context)


class FakeClock:
    """Seconds of a monotonic clock, moved on by hand (``now``)."""

    def __init__(self, now: float = 100.0) -> None:
        """Start at ``now``."""
        self.now = now

    def __call__(self) -> float:
        """Return the time."""
        return self.now
