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
A robot's joints in a recording: its ``joint_states`` read, and their CSV columns.

A node that serves a whole robot publishes ``joint_states`` every published tick, stamped as
the tick's pose. A row of such a tick carries that message's values (``JointValues``), and the
CSV has three columns a joint after the single body's, named by the joint:
``joint.<name>.position``, ``joint.<name>.velocity`` and ``joint.<name>.effort`` (rad, rad/s and
N m, or m, m/s and N for a prismatic joint), empty where the row's message has no such value.
"""

from typing import List, NamedTuple, Optional, Sequence, Tuple

from rclpy.serialization import deserialize_message
from sensor_msgs.msg import JointState

# The quantities of a joint, in the order of its columns.
JOINT_QUANTITIES = ('position', 'velocity', 'effort')


class JointValues(NamedTuple):
    """One ``joint_states`` message: the joints' names and their values, in its order."""

    names: Tuple[str, ...]
    position: Tuple[float, ...]
    velocity: Tuple[float, ...]
    effort: Tuple[float, ...]

    def value(self, name: str, quantity: str) -> Optional[float]:
        """Return ``name``'s value of ``quantity`` (``JOINT_QUANTITIES``), or None without."""
        try:
            index = self.names.index(name)
        except ValueError:
            return None
        values = getattr(self, quantity)
        return values[index] if index < len(values) else None


def read_joint_states(data: bytes) -> Optional[Tuple[int, JointValues]]:
    """
    Return the stamp (ns) and the values of a serialized ``joint_states`` message.

    None for bytes that hold no JointState, as a malformed message is passed over.
    """
    try:
        message = deserialize_message(data, JointState)
    except RuntimeError:
        return None
    stamp = message.header.stamp
    return stamp.sec * 1_000_000_000 + stamp.nanosec, JointValues(
        tuple(message.name), tuple(message.position), tuple(message.velocity),
        tuple(message.effort))


def joint_columns(names: Sequence[str]) -> Tuple[str, ...]:
    """Return the CSV columns of the joints ``names``: each joint's quantities in turn."""
    return tuple(f'joint.{name}.{quantity}' for name in names for quantity in JOINT_QUANTITIES)


def joint_fields(joints: Optional[JointValues], names: Sequence[str]) -> List[object]:
    """Return a row's values in ``joint_columns(names)`` order; '' where there is none."""
    if joints is not None and joints.names == tuple(names) and \
            len(joints.position) == len(joints.velocity) == len(joints.effort) == len(names):
        # The node's message: every value, in the columns' order.
        return [value for values in zip(joints.position, joints.velocity, joints.effort)
                for value in values]
    fields: List[object] = []
    for name in names:
        for quantity in JOINT_QUANTITIES:
            value = None if joints is None else joints.value(name, quantity)
            fields.append('' if value is None else value)
    return fields
