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
What ``mouse_target`` reads from the node to check a target or a grab before publishing it.

The node's parameters (``frame_id`` and ``workspace_radius`` for every target, ``box_size`` and
``grab_margin`` for a grab) from its parameter service, and the body's latest pose from
``pose``; the checks themselves are the node's own (``target_gate``, ``grab``).
"""

from typing import List, Optional

from geometry_msgs.msg import PoseStamped
from rcl_interfaces.msg import ParameterType
from rcl_interfaces.srv import GetParameters
from rclpy.node import Node

from ..inputs.grab import grab
from ..inputs.target_gate import TargetGate
from ..node.body_parameters import geometry_from
from ..physics import BodyState
from ..timing.spin import call_until_answered, StopRequest, wait_until
from ..wire.interface import POSE_TOPIC, STATE_QOS

# The node's parameters a target is checked against, and those a grab is checked against too.
GATE_PARAMETERS = {'frame_id': ParameterType.PARAMETER_STRING,
                   'workspace_radius': ParameterType.PARAMETER_DOUBLE}
GRAB_PARAMETERS = {'box_size': ParameterType.PARAMETER_DOUBLE_ARRAY,
                   'grab_margin': ParameterType.PARAMETER_DOUBLE,
                   'robot_description': ParameterType.PARAMETER_STRING,
                   'body_link': ParameterType.PARAMETER_STRING,
                   'density': ParameterType.PARAMETER_DOUBLE}


def fetch_parameters(node: Node, executor, target_node: str, types: dict, deadline: float,
                     stop: StopRequest) -> dict:
    """
    Return the values of the parameters ``types`` names (name: ParameterType) of a node.

    :raises RuntimeError: saying why the parameters could not be read by ``deadline``.
    :raises Interrupted: on Ctrl-C or SIGTERM.
    """
    client = node.create_client(GetParameters, f'{target_node}/get_parameters')
    try:
        if not wait_until(executor, stop, client.service_is_ready, deadline=deadline):
            raise RuntimeError(f'no parameter service {client.srv_name}')
        response = call_until_answered(client, GetParameters.Request(names=list(types)),
                                       executor, stop, deadline=deadline)
        if response is None:
            raise RuntimeError(f'{client.srv_name} did not answer')
        values = response.values
        if [value.type for value in values] != list(types.values()):
            raise RuntimeError(f'{target_node} has not the parameters {", ".join(types)} '
                               'of mouse_constraint')
        return {name: parameter_value(value) for name, value in zip(types, values)}
    finally:
        node.destroy_client(client)


def fetch_gate(node: Node, executor, target_node: str, deadline: float,
               stop: StopRequest) -> TargetGate:
    """
    Return the target policy of ``target_node`` from its parameter service.

    :raises RuntimeError: saying why the parameters could not be read by ``deadline``.
    :raises Interrupted: on Ctrl-C or SIGTERM.
    """
    values = fetch_parameters(node, executor, target_node, GATE_PARAMETERS, deadline, stop)
    return TargetGate(values['frame_id'], values['workspace_radius'])


def fetch_pose(node: Node, executor, deadline: float, stop: StopRequest) -> BodyState:
    """
    Return the body's pose from the next message on ``pose`` (velocities zero).

    :raises RuntimeError: when none came by ``deadline`` (e.g. the node is paused).
    :raises Interrupted: on Ctrl-C or SIGTERM.
    """
    poses = []
    subscription = node.create_subscription(PoseStamped, POSE_TOPIC, poses.append,
                                            STATE_QOS)
    try:
        if not wait_until(executor, stop, lambda: bool(poses), deadline=deadline):
            raise RuntimeError(f'no pose on {subscription.topic_name}')
        p, q = poses[-1].pose.position, poses[-1].pose.orientation
        return BodyState((p.x, p.y, p.z), (q.x, q.y, q.z, q.w))
    finally:
        node.destroy_subscription(subscription)


def grab_refusal(node: Node, executor, target_node: str, point: List[float], deadline: float,
                 stop: StopRequest) -> Optional[str]:
    """
    Return why ``target_node`` would ignore a grab at ``point`` as off its body, or None.

    The node's own test (``grab.grab``) on its latest pose, its shape (its URDF link's, or
    ``box_size``) and ``grab_margin``.

    :raises RuntimeError: saying why the body could not be read by ``deadline``.
    :raises ValueError: the node's shape cannot be read here (a mesh this machine lacks).
    :raises Interrupted: on Ctrl-C or SIGTERM.
    """
    values = fetch_parameters(node, executor, target_node, GRAB_PARAMETERS, deadline, stop)
    state = fetch_pose(node, executor, deadline, stop)
    margin = values['grab_margin']
    landed = grab(state, geometry_from(values), point)
    if landed.taken(margin):
        return None
    at = ', '.join(f'{c:.3f}' for c in state.position)
    return (f'{tuple(point)}: {landed.distance:.6g} m off the body at ({at}), farther '
            f'than grab_margin {margin:g} m from its shape')


def parameter_value(value) -> object:
    """Return the Python value of an ``rcl_interfaces/ParameterValue`` of the types used here."""
    if value.type == ParameterType.PARAMETER_STRING:
        return value.string_value
    if value.type == ParameterType.PARAMETER_DOUBLE_ARRAY:
        return [float(c) for c in value.double_array_value]
    return value.double_value
