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
Reading another node's parameters through its ``get_parameters`` service, for the commands.

``fetch_parameters`` spins the command's executor (``spin.wait_until``) while it waits, so that
Ctrl-C is seen, and gives plain Python values, checked against the types asked for.
It asks with ``spin.call_until_answered``, which sends the request again while it goes
unanswered: reading parameters twice does no harm.
"""

import time
from typing import Collection, Dict, Mapping

from rcl_interfaces.msg import ParameterType
from rcl_interfaces.srv import GetParameters
from rclpy.executors import Executor
from rclpy.node import Node

from ..timing.spin import call_until_answered, StopRequest, wait_until

# The ParameterValue field of each type a command asks for.
_FIELDS = {ParameterType.PARAMETER_BOOL: 'bool_value',
           ParameterType.PARAMETER_DOUBLE: 'double_value',
           ParameterType.PARAMETER_STRING: 'string_value',
           ParameterType.PARAMETER_DOUBLE_ARRAY: 'double_array_value'}
_TYPE_NAMES = {ParameterType.PARAMETER_BOOL: 'bool', ParameterType.PARAMETER_DOUBLE: 'double',
               ParameterType.PARAMETER_STRING: 'string',
               ParameterType.PARAMETER_DOUBLE_ARRAY: 'double array'}


def fetch_parameters(node: Node, executor: Executor, stop: StopRequest, *, target_node: str,
                     types: Mapping[str, int], timeout: float,
                     optional: Collection[str] = ()) -> Dict[str, object]:
    """
    Return ``target_node``'s parameters named in ``types``, each as a Python value.

    :param types: the ``ParameterType`` of each name (bool, double, string, double array).
    :param optional: names that may be missing (not set): they are left out of the result.
    :param timeout: seconds to wait for the service, then as long for its answer.
    :raises RuntimeError: saying why they could not be read.
    :raises Interrupted: when ``stop`` is requested meanwhile.
    """
    client = node.create_client(GetParameters, f'{target_node}/get_parameters')
    try:
        if not wait_until(executor, stop, client.service_is_ready,
                          deadline=time.monotonic() + timeout):
            raise RuntimeError(f'no parameter service {client.srv_name} after {timeout:g} s')
        names = list(types)
        response = call_until_answered(client, GetParameters.Request(names=names), executor,
                                       stop, deadline=time.monotonic() + timeout)
        if response is None:
            raise RuntimeError(f'{client.srv_name} did not answer in {timeout:g} s')
        values = response.values
        if len(values) != len(names):
            raise RuntimeError(f'{target_node} answered {len(values)} of {len(names)} '
                               'parameters')
        result = {}
        for name, value in zip(names, values):
            wanted = types[name]
            if value.type == ParameterType.PARAMETER_NOT_SET and name in optional:
                continue
            if value.type != wanted:
                raise RuntimeError(f'{target_node} has no {_TYPE_NAMES[wanted]} parameter '
                                   f'{name}')
            field = getattr(value, _FIELDS[wanted])
            result[name] = tuple(float(v) for v in field) if wanted == (
                ParameterType.PARAMETER_DOUBLE_ARRAY) else field
        return result
    finally:
        node.destroy_client(client)
