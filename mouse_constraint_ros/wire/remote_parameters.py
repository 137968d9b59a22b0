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
unanswered: reading parameters twice does no harm. ``ParameterRequest`` asks the same without
waiting: a command's own spin loop polls it while it waits for other things too (the recorder,
for its first pose), and has it asked again when it knows that an answer can no longer be lost.
"""

import time
from typing import Callable, Collection, Dict, Mapping, Optional

from rcl_interfaces.msg import ParameterType
from rcl_interfaces.srv import GetParameters
from rclpy.client import Client
from rclpy.executors import Executor
from rclpy.node import Node

from ..timing.spin import ASK_AGAIN_SECONDS, call_until_answered, StopRequest, wait_until

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
        return parameter_values(response, target_node=target_node, types=types,
                                optional=optional)
    finally:
        node.destroy_client(client)


def parameter_values(response, *, target_node: str, types: Mapping[str, int],
                     optional: Collection[str] = ()) -> Dict[str, object]:
    """
    Return a ``GetParameters`` response to the names of ``types`` as Python values.

    :raises RuntimeError: an answer of another count or type, or a missing name not optional.
    """
    names = list(types)
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


class ParameterRequest:
    """
    Another node's parameters asked for without waiting: ``poll`` it from the spin loop.

    The request goes once the service is ready, and again each ``again`` seconds it goes
    unanswered, or at once on ``ask_again``: a client sees the service ready once it has matched
    the server's endpoints, which may not yet have matched the client's, and an answer sent
    then is lost. The client is made by the caller, before the endpoints whose match tells it
    that the server has matched the client's too (``ask_again`` then).

    :param client: a ``GetParameters`` client of the node.
    :param target_node: the node's name, as said in errors.
    :param types: the ``ParameterType`` of each name (``fetch_parameters``).
    :param optional: names that may be missing.
    :param again: seconds an unanswered request waits before it goes again.
    :param clock: seconds of a monotonic clock.
    """

    def __init__(self, client: Client, *, target_node: str, types: Mapping[str, int],
                 optional: Collection[str] = (), again: float = ASK_AGAIN_SECONDS,
                 clock: Callable[[], float] = time.monotonic) -> None:
        """Ask nothing yet."""
        self.client, self.target_node = client, target_node
        self._types, self._optional = dict(types), set(optional)
        self._again, self._clock = again, clock
        self._future = None
        self._sent_at: Optional[float] = None
        self.values: Optional[Dict[str, object]] = None
        self.error: Optional[str] = None  # why an answer came without the values
        self.asked = 0

    def poll(self) -> bool:
        """
        Take the answer if it came, else ask when it is time; return whether it has come.

        An answer without the parameters asked for (another count or type) leaves ``values``
        None and says why in ``error``.
        """
        if self.values is not None or self.error is not None:
            return True
        if self._future is not None and self._future.done():
            try:
                self.values = parameter_values(
                    self._future.result(), target_node=self.target_node, types=self._types,
                    optional=self._optional)
            except RuntimeError as error:
                self.error = str(error)
            return True
        if self.client.service_is_ready() and (
                self._sent_at is None or self._clock() - self._sent_at >= self._again):
            self._send()
        return False

    def ask_again(self) -> None:
        """Send the request again now, unless it was answered or the service is not seen."""
        if self.client.service_is_ready() and not (
                self._future is not None and self._future.done()):
            self._send()

    def unanswered(self, seconds: float) -> str:
        """Return why there are no values after ``seconds`` of asking, in the words of errors."""
        if self.error is not None:
            return self.error
        if self.asked:
            return f'{self.client.srv_name} did not answer in {seconds:g} s'
        return f'no parameter service {self.client.srv_name} after {seconds:g} s'

    def _send(self) -> None:
        if self._future is not None:
            self.client.remove_pending_request(self._future)
        self._future = self.client.call_async(GetParameters.Request(names=list(self._types)))
        self._sent_at = self._clock()
        self.asked += 1
