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
What a recording keeps: the recorded topics and each message as it arrived, serialized.

Besides the topics (the node's inputs ``target``, ``grab`` and ``wrench``, its ``pose`` and
``twist``, and a robot's ``joint_states``) it keeps what changes the recorded node's target and
anchor without passing through them: the node's ``/parameter_events`` that change a parameter
of ``NODE_PARAMETERS`` (a grab sets ``anchor``), and the service events of its ``~/reset`` and
``~/release`` (``<node>/reset/_service_event``, published by the node's service introspection).
"""

import struct
from typing import Dict, NamedTuple, Optional

from geometry_msgs.msg import PointStamped, PoseStamped, TwistStamped, WrenchStamped
from rcl_interfaces.msg import ParameterEvent, ParameterType
from sensor_msgs.msg import JointState
from std_srvs.srv import Trigger

from ..wire.interface import (GRAB_TOPIC, JOINT_STATES_TOPIC, POSE_TOPIC, TARGET_TOPIC,
                              TWIST_TOPIC, WRENCH_TOPIC)

# The recorded topics (relative: namespaces and remaps apply) and their types, in CSV order;
# the progress line counts the messages of the first four.
TOPICS = {TARGET_TOPIC: PointStamped, POSE_TOPIC: PoseStamped, TWIST_TOPIC: TwistStamped,
          GRAB_TOPIC: PointStamped, WRENCH_TOPIC: WrenchStamped, JOINT_STATES_TOPIC: JointState}
# The topics only a node that serves a whole robot publishes: a recording of a single body has
# no trace of them (no CSV column, no MCAP channel).
ROBOT_TOPICS = (JOINT_STATES_TOPIC,)
COUNTED_TOPICS = (TARGET_TOPIC, POSE_TOPIC, TWIST_TOPIC, GRAB_TOPIC)
# The recorded node's parameter events that change a parameter of NODE_PARAMETERS: kept too,
# so that each row uses the anchor in effect when its pose came.
PARAMETER_EVENTS_TOPIC = '/parameter_events'
# The recorded node's services whose calls set its target, by key: the service events
# (``<node>/<name>/_service_event``) are kept.
RESET_EVENTS = 'reset'
RELEASE_EVENTS = 'release'
SERVICE_EVENTS = (RESET_EVENTS, RELEASE_EVENTS)
# Every type a recording keeps, by key.
MESSAGE_TYPES = {**TOPICS, PARAMETER_EVENTS_TOPIC: ParameterEvent,
                 RESET_EVENTS: Trigger.Event, RELEASE_EVENTS: Trigger.Event}
# The recorded node's parameters that the rows follow, and their types: the anchor, what
# ~/reset makes the target (the initial anchor's world position, when held), the rates of
# the grid the stamps lie on, and which wrenches it takes and for how long.
NODE_PARAMETERS = {'anchor': ParameterType.PARAMETER_DOUBLE_ARRAY,
                   'hold_initial_anchor': ParameterType.PARAMETER_BOOL,
                   'initial_position': ParameterType.PARAMETER_DOUBLE_ARRAY,
                   'initial_orientation': ParameterType.PARAMETER_DOUBLE_ARRAY,
                   'rate_hz': ParameterType.PARAMETER_DOUBLE,
                   'publish_rate_hz': ParameterType.PARAMETER_DOUBLE,
                   'max_wrench_force': ParameterType.PARAMETER_DOUBLE,
                   'max_wrench_torque': ParameterType.PARAMETER_DOUBLE,
                   'wrench_timeout': ParameterType.PARAMETER_DOUBLE}
# The recorded node's body, read at the start only: a URDF link's hull is outlined on the
# figure (``body_outline``); without robot_description the node's body is the box.
BODY_PARAMETERS = {'robot_description': ParameterType.PARAMETER_STRING,
                   'body_link': ParameterType.PARAMETER_STRING,
                   'density': ParameterType.PARAMETER_DOUBLE}
# The length of each array parameter of NODE_PARAMETERS.
_LENGTHS = {'anchor': 3, 'initial_position': 3, 'initial_orientation': 4}


class Received(NamedTuple):
    """One message as received: topic key, receive time (ns, node clock), serialized CDR."""

    topic: str
    log_time: int
    data: bytes


def service_event_topic(node_name: str, key: str) -> str:
    """Return the topic of the service events of ``node_name``'s service ``key``."""
    return f'{node_name}/{key}/_service_event'


def parameter_changes(event: ParameterEvent) -> Dict[str, object]:
    """
    Return the parameters of NODE_PARAMETERS that ``event`` sets, by name, as Python values.

    A value of another type, or an array of another length, is left out.
    """
    changes: Dict[str, object] = {}
    for parameter in (*event.new_parameters, *event.changed_parameters):
        value, wanted = parameter.value, NODE_PARAMETERS.get(parameter.name)
        if wanted is None or value.type != wanted:
            continue
        if wanted == ParameterType.PARAMETER_BOOL:
            changes[parameter.name] = value.bool_value
        elif wanted == ParameterType.PARAMETER_DOUBLE:
            changes[parameter.name] = value.double_value
        elif len(value.double_array_value) == _LENGTHS[parameter.name]:
            changes[parameter.name] = tuple(float(c) for c in value.double_array_value)
    return changes


_STAMP = {0: struct.Struct('>iI'), 1: struct.Struct('<iI')}


def header_stamp(data: bytes) -> Optional[int]:
    """
    Return the header stamp (ns) of a serialized stamped message, or None if it has none.

    The stamp is the first field: after the 4-byte CDR encapsulation header (whose second byte
    is 1 for little endian, 0 for big endian), an int32 sec and a uint32 nanosec.
    """
    if len(data) < 12 or data[0] != 0 or data[1] not in _STAMP:
        return None
    sec, nanosec = _STAMP[data[1]].unpack_from(data, 4)
    return sec * 1_000_000_000 + nanosec
