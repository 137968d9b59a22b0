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

"""A service call that got lost is sent again once a second; parameters read from another node."""

import time

from rcl_interfaces.msg import ParameterDescriptor, ParameterType
from rclpy.node import Node
from rclpy.parameter import Parameter
from std_srvs.srv import Trigger

from mouse_constraint_ros.timing.spin import ASK_AGAIN_SECONDS, call_until_answered, StopRequest
from mouse_constraint_ros.wire.remote_parameters import fetch_parameters


def test_a_request_sent_before_the_server_came_is_sent_again(ros):
    """
    The first request finds no server and is lost; the one sent a second later is answered.

    The server comes 0.3 s after the first request (as a server in another process comes to
    match the client's request writer after the client saw it): it serves one request only.
    """
    client = ros.probe.create_client(Trigger, 'late/serve')
    served = []

    def serve(_request, response):
        served.append(time.monotonic())
        response.success = True
        return response

    def come():
        starter.cancel()
        server = ros.add(Node('late', context=ros.context))
        server.create_service(Trigger, 'late/serve', serve)
    starter = ros.probe.create_timer(0.3, come)
    sent = time.monotonic()
    response = call_until_answered(client, Trigger.Request(), ros.executor, StopRequest(),
                                   deadline=sent + 10.0)
    assert response is not None and response.success
    assert len(served) == 1 and served[0] - sent >= ASK_AGAIN_SECONDS


def test_no_answer_by_the_deadline_is_none(ros):
    """No server at all: the requests go unanswered and the call gives None at its deadline."""
    client = ros.probe.create_client(Trigger, 'nobody/serve')
    deadline = time.monotonic() + 1.5 * ASK_AGAIN_SECONDS
    assert call_until_answered(client, Trigger.Request(), ros.executor, StopRequest(),
                               deadline=deadline) is None
    assert time.monotonic() >= deadline


def test_fetch_parameters_gives_the_values_of_the_types_asked_for(ros):
    """Doubles, arrays as tuples, an optional one not set left out; a wrong type names it."""
    holder = ros.add(Node('holder', context=ros.context, parameter_overrides=[
        Parameter('rate_hz', value=250.0), Parameter('anchor', value=[0.1, 0.2, 0.3])],
        automatically_declare_parameters_from_overrides=True))
    holder.declare_parameter('absent', descriptor=ParameterDescriptor(dynamic_typing=True))
    types = {'rate_hz': ParameterType.PARAMETER_DOUBLE,
             'anchor': ParameterType.PARAMETER_DOUBLE_ARRAY,
             'absent': ParameterType.PARAMETER_BOOL}
    values = fetch_parameters(ros.probe, ros.executor, StopRequest(), target_node='/holder',
                              types=types, timeout=10.0, optional={'absent'})
    assert values == {'rate_hz': 250.0, 'anchor': (0.1, 0.2, 0.3)}
    try:
        fetch_parameters(ros.probe, ros.executor, StopRequest(), target_node='/holder',
                         types={'rate_hz': ParameterType.PARAMETER_BOOL}, timeout=10.0)
    except RuntimeError as error:
        assert str(error) == '/holder has no bool parameter rate_hz'
    else:
        raise AssertionError('a double read as a bool')
