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

"""What a recording keeps: the recorded topics and each message as it arrived, serialized."""

from typing import NamedTuple, Optional

from geometry_msgs.msg import PointStamped, PoseStamped, TwistStamped
from rcl_interfaces.msg import ParameterEvent, ParameterType

from ..physics.algebra import Vector3
from ..wire.interface import GRAB_TOPIC, POSE_TOPIC, TARGET_TOPIC, TWIST_TOPIC

# The recorded topics (relative: namespaces and remaps apply) and their types, in CSV order.
TOPICS = {TARGET_TOPIC: PointStamped, POSE_TOPIC: PoseStamped, TWIST_TOPIC: TwistStamped,
          GRAB_TOPIC: PointStamped}
# The recorded node's parameter events that change its anchor (a grab sets it): kept too, so
# that each row uses the anchor in effect when its pose came.
PARAMETER_EVENTS_TOPIC = '/parameter_events'
# Every type a recording keeps, by key.
MESSAGE_TYPES = {**TOPICS, PARAMETER_EVENTS_TOPIC: ParameterEvent}


class Received(NamedTuple):
    """One message as received: topic key, receive time (ns, node clock), serialized CDR."""

    topic: str
    log_time: int
    data: bytes


def anchor_change(event: ParameterEvent) -> Optional[Vector3]:
    """Return the ``anchor`` (body frame, m) a parameter event sets, or None if it sets none."""
    for parameter in (*event.new_parameters, *event.changed_parameters):
        value = parameter.value
        if (parameter.name == 'anchor' and value.type == ParameterType.PARAMETER_DOUBLE_ARRAY
                and len(value.double_array_value) == 3):
            return tuple(float(c) for c in value.double_array_value)
    return None
