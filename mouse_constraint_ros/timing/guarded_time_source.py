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
A time source that survives a hostile ``/clock``: rclpy's, ignoring the messages it cannot take.

With ``use_sim_time`` rclpy's ``TimeSource`` turns each ``/clock`` message into a ``Time``,
and a negative one (``{clock: {sec: -1}}``) raises ``ValueError`` inside the executor, which
ends the node. ``GuardedTimeSource`` takes every message rclpy's does and, for one that raises,
changes nothing (the clock stays where it was) and tells ``on_ignored`` what it ignored.
``guard_time_source`` puts it in place of a node's own, with the same ``use_sim_time``
handling (the parameter, its changes, the ``/clock`` subscription).
"""

from typing import Callable

from rclpy.node import Node
from rclpy.time_source import TimeSource
from rosgraph_msgs.msg import Clock


class GuardedTimeSource(TimeSource):
    """
    rclpy's ``TimeSource`` that ignores the ``/clock`` messages it cannot take.

    :param on_ignored: called with a sentence saying which message was ignored and why.
    """

    def __init__(self, *, node: Node, on_ignored: Callable[[str], None]) -> None:
        """Attach to ``node`` as rclpy's own time source does."""
        self._on_ignored = on_ignored
        self.ignored = 0
        super().__init__(node=node)

    def clock_callback(self, msg: Clock) -> None:
        """Set the clocks to ``msg``, or ignore it (and say so) when it is no time."""
        try:
            super().clock_callback(msg)
        except ValueError as error:
            self.ignored += 1
            self._on_ignored(
                f'ignoring /clock {msg.clock.sec} s {msg.clock.nanosec} ns: {error} (ROS time '
                'cannot be negative); the clock stays where it was')


def guard_time_source(node: Node, on_ignored: Callable[[str], None]) -> GuardedTimeSource:
    """
    Replace ``node``'s time source by a ``GuardedTimeSource``; return it.

    Call it right after ``Node.__init__``, before spinning: rclpy's source is detached (its
    ``/clock`` subscription destroyed, its parameter callback removed) and the guarded one
    attached to the node and its clock.
    """
    original = node._time_source
    node.remove_on_set_parameters_callback(original._on_parameter_event)
    original.detach_node()
    guarded = GuardedTimeSource(node=node, on_ignored=on_ignored)
    guarded.attach_clock(node.get_clock())
    node._time_source = guarded
    return guarded
