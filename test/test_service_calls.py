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
A service call that got lost is sent again once a second; parameters read from another node.

The tools' calls of the node's services (``ServiceCalls``): one that a node never answers is
given up after its timeout, in the web view's, the RViz marker's and the node follower's
clients alike, so that none keeps a pending request for each call.
"""

import time

from rcl_interfaces.msg import ParameterDescriptor, ParameterType
from rcl_interfaces.srv import GetParameters
from rclpy.node import Node
from rclpy.parameter import Parameter
from std_srvs.srv import Trigger

from mouse_constraint_ros.marker.node import MouseMarkerNode
from mouse_constraint_ros.pointer.node_follower import ASK_AGAIN_SECONDS as ASK_PARAMETERS
from mouse_constraint_ros.pointer.service_calls import GIVE_UP_SECONDS, ServiceCalls
from mouse_constraint_ros.timing.spin import ASK_AGAIN_SECONDS, call_until_answered, StopRequest
from mouse_constraint_ros.wire.remote_parameters import fetch_parameters, ParameterRequest
from test_support.silent_node import FakeClock, silent_node


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


def test_a_parameter_request_asks_when_ready_again_when_told_and_takes_the_answer(ros):
    """
    A ParameterRequest asks again after ``again`` s, or when told to; answered, no more.

    The silent node's service is ready and never answers: the request goes again after
    ``again`` s of its clock unanswered, and at once on ``ask_again``. A node that answers
    comes: the next request is answered, its values taken, and nothing is asked any more. An
    answer without the parameters asked for says why, as ``fetch_parameters`` would.
    """
    clock = FakeClock()
    types = {'anchor': ParameterType.PARAMETER_DOUBLE_ARRAY}
    with silent_node():
        client = ros.probe.create_client(GetParameters, '/mouse_constraint/get_parameters')
        request = ParameterRequest(client, target_node='/mouse_constraint', types=types,
                                   again=2.0, clock=clock)
        assert request.asked == 0 and request.unanswered(2.0) == (
            'no parameter service /mouse_constraint/get_parameters after 2 s')
        assert ros.spin_until(lambda: request.poll() or request.asked == 1)
        assert request.unanswered(2.0) == '/mouse_constraint/get_parameters did not answer in 2 s'
        clock.now += 1.9
        assert not request.poll() and request.asked == 1
        clock.now += 0.1
        assert not request.poll() and request.asked == 2
        request.ask_again()
        assert request.asked == 3 and len(client._pending_requests) == 1
    ros.add(Node('mouse_constraint', context=ros.context, parameter_overrides=[
        Parameter('anchor', value=[0.1, 0.2, 0.3])],
        automatically_declare_parameters_from_overrides=True))
    asked = request.asked
    clock.now += 2.0
    assert ros.spin_until(request.poll, timeout=10.0)
    assert request.values == {'anchor': (0.1, 0.2, 0.3)} and request.asked > asked
    asked = request.asked
    clock.now += 10.0
    request.ask_again()
    assert request.poll() and request.asked == asked
    wrong = ParameterRequest(client, target_node='/mouse_constraint',
                             types={'anchor': ParameterType.PARAMETER_BOOL})
    assert ros.spin_until(wrong.poll, timeout=10.0)
    assert wrong.values is None and wrong.unanswered(2.0) == (
        '/mouse_constraint has no bool parameter anchor')


def test_a_call_unanswered_for_its_timeout_is_given_up(ros):
    """Three releases to a node that never answers: pending until 5 s, then none, each said."""
    clock, given_up = FakeClock(), []
    client = ros.probe.create_client(Trigger, 'mouse_constraint/release')
    calls = ServiceCalls(clock=clock)
    with silent_node():
        assert ros.spin_until(client.service_is_ready)
        for number in range(3):
            calls.call(client, Trigger.Request(), on_give_up=lambda n=number: given_up.append(n))
            clock.now += 1.0
        ros.spin_for(0.1)
        assert calls.pending == 3 and len(client._pending_requests) == 3
        clock.now += GIVE_UP_SECONDS - 3.0
        assert calls.give_up_late() == 1 and given_up == [0]
        clock.now += 2.0
        assert calls.give_up_late() == 2 and given_up == [0, 1, 2]
        assert calls.pending == 0 and client._pending_requests == {}


def test_the_marker_keeps_no_request_for_an_unanswered_release(ros):
    """
    The RViz marker's releases to a node that never answers: each given up after its timeout.

    Its work timer gives them up, and its node follower's questions for the parameters, asked
    again every 2 s, leave one pending at a time.
    """
    clock = FakeClock()
    marker = ros.add(MouseMarkerNode(context=ros.context, clock=clock))
    with silent_node():
        assert ros.spin_until(marker.release_client.service_is_ready)
        for _ in range(4):
            marker._release(clock.now)
            clock.now += 1.0  # the release gate opens after 1 s unanswered
        assert len(marker.release_client._pending_requests) == 4
        clock.now += GIVE_UP_SECONDS
        marker._work()
        assert marker.release_client._pending_requests == {}
        assert marker.calls.given_up == 4
        follower = marker.follower
        assert ros.spin_until(follower._get_parameters.service_is_ready)
        for _ in range(5):
            follower.look()
            clock.now += ASK_PARAMETERS + 0.1
        assert not follower.parameters_known
        assert len(follower._get_parameters._pending_requests) == 1
