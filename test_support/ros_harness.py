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

"""Helpers for tests that run nodes in-process: contexts, spinning, and collecting messages."""

import copy
import time
from typing import Callable, List, Sequence

import numpy as np
from rcl_interfaces.srv import ListParameters
import rclpy
from rclpy.executors import SingleThreadedExecutor
from rclpy.impl.implementation_singleton import rclpy_implementation as _rclpy
from rclpy.node import Node
from rclpy.qos import QoSProfile, ReliabilityPolicy
from rosgraph_msgs.msg import Clock

from mouse_constraint_ros.testing.lockstep import drain
from mouse_constraint_ros.timing.spin import call_until_answered, StopRequest
from mouse_constraint_ros.wire.messages import stamp_nanoseconds


class RosHarness:
    """
    One rclpy context with an executor, torn down after the test.

    :param nodes: nodes added with ``add``; the executor spins all of them.
    """

    def __init__(self) -> None:
        """Initialize a new context and an executor on it."""
        self.context = rclpy.Context()
        rclpy.init(context=self.context)
        self.executor = SingleThreadedExecutor(context=self.context)
        self.nodes: List[Node] = []
        self.probe = self.add(Node('test_probe', context=self.context))

    def add(self, node: Node) -> Node:
        """Spin ``node`` with the others; return it."""
        self.nodes.append(node)
        self.executor.add_node(node)
        return node

    def spin_for(self, seconds: float) -> None:
        """Spin all nodes for ``seconds`` of wall time."""
        deadline = time.monotonic() + seconds
        while time.monotonic() < deadline:
            self.executor.spin_once(timeout_sec=min(0.01, max(0.0, deadline - time.monotonic())))

    def spin_until(self, condition: Callable[[], bool], timeout: float = 10.0) -> bool:
        """Spin until ``condition()`` holds or ``timeout`` seconds pass; return whether it held."""
        return spin_until(self.executor, condition, timeout)

    def drain(self) -> None:
        """Run every ready callback, and those they make ready, until none is."""
        drain(self.executor, timeout=10.0)

    def call(self, service_type, name: str, request):
        """Call the service ``name`` from the probe; return the response."""
        client = self.probe.create_client(service_type, name)
        assert client.wait_for_service(timeout_sec=5.0)
        future = client.call_async(request)
        assert self.spin_until(future.done)
        return future.result()

    def discovered_by(self, node_name: str, timeout: float = 20.0) -> bool:
        """
        Return whether ``node_name`` answered the probe within ``timeout`` seconds.

        A publisher's subscription count says that the probe matched the other process's
        reader, not that this reader matched the probe's writer; until it has, what the writer
        sends reaches that reader late (resent once it matched: after messages of other topics
        sent later) or not at all, and a burst's first messages are out of order or lost.
        A reply from ``node_name``'s parameter service says it has: the request's writer is
        announced after every endpoint the probe made before, in order, on one reliable
        discovery stream. A request sent before that match is lost too, so it goes again
        (``call_until_answered``).
        """
        client = self.probe.create_client(ListParameters, f'{node_name}/list_parameters')
        try:
            return call_until_answered(client, ListParameters.Request(), self.executor,
                                       StopRequest(),
                                       deadline=time.monotonic() + timeout) is not None
        finally:
            self.probe.destroy_client(client)

    def collect(self, message_type, topic: str, depth: int = 1000) -> list:
        """Subscribe the probe to ``topic``; return the list that received messages fill."""
        received: list = []
        qos = QoSProfile(depth=depth, reliability=ReliabilityPolicy.RELIABLE)
        self.probe.create_subscription(message_type, topic, received.append, qos)
        return received

    def shutdown(self) -> None:
        """Destroy the nodes and shut the context down."""
        self.executor.shutdown()
        for node in self.nodes:
            node.destroy_node()
        rclpy.try_shutdown(context=self.context)


def spin_until(executor, condition: Callable[[], bool], timeout: float = 10.0) -> bool:
    """
    Spin ``executor`` on wall time until ``condition()`` holds; return whether it did in time.

    For what comes on wall-clock timers (the node's markers) while a ``SimulatedBody`` is not
    stepped: its simulated time stands still meanwhile; and for the bench's observer process,
    which waits so for the node it watches.
    """
    deadline = time.monotonic() + timeout
    while not condition():
        if time.monotonic() > deadline:
            return False
        executor.spin_once(timeout_sec=0.01)
    return True


def service_of(node: Node, name: str):
    """Return ``node``'s service whose name ends with ``name`` (as ``/release``)."""
    [service] = [s for s in node.services if s.srv_name.endswith(name)]
    return service


def waits_at(service, context, timeout: float = 10.0) -> bool:
    """
    Wait until a request waits at ``service`` to be taken; return whether one came in time.

    Nothing is taken: the executor that spins the service's node finds the request as it
    waited. Call it while nothing spins that node.

    :param context: the rclpy context of the service's node.
    """
    with service.handle, context.handle:
        wait_set = _rclpy.WaitSet(0, 0, 0, 0, 1, 0, context.handle)
        wait_set.clear_entities()
        wait_set.add_service(service.handle)
        wait_set.wait(int(timeout * 1e9))
        return service.handle.pointer in wait_set.get_ready_entities('service')


def assert_on_grid(stamps: Sequence[int], period_ns: int, dropped: int) -> None:
    """
    Assert ``stamps`` whole periods apart, each period skipped a tick the node says it dropped.

    On its own timer, a node whose process stalls past its catch-up bound (0.1 s) drops the
    ticks it missed and counts them (``dropped_ticks``, and a warning): the grid holds however
    loaded the machine is, and a gap the node did not count fails. Without a drop, every step
    is one period.

    :param dropped: the ticks the node dropped while ``stamps`` went out (or more).
    """
    steps = np.diff(np.asarray(stamps, dtype=np.int64))
    assert steps.size > 0 and np.all(steps >= period_ns) and np.all(steps % period_ns == 0), \
        f'steps off a grid of {period_ns} ns: {sorted(set(steps.tolist()))}'
    skipped = int((steps // period_ns - 1).sum())
    assert skipped <= dropped, f'{skipped} ticks missing, {dropped} dropped by the node'


def stamp_of(message) -> int:
    """Return a message's header stamp in nanoseconds."""
    return stamp_nanoseconds(message.header.stamp)


class SimClock:
    """Drives a node's /clock from the harness's probe, and waits until the node saw each time."""

    def __init__(self, ros: RosHarness, node: Node) -> None:
        """Create the /clock publisher and wait for the node's subscription."""
        self.ros, self.node = ros, node
        self.publisher = ros.probe.create_publisher(Clock, '/clock', 10)
        assert ros.spin_until(lambda: self.publisher.get_subscription_count() > 0)

    def publish(self, sec: int, nanosec: int) -> None:
        """Publish a /clock of ``sec`` s and ``nanosec`` ns as they are (even invalid ones)."""
        message = Clock()
        message.clock.sec, message.clock.nanosec = sec, nanosec
        self.publisher.publish(message)

    def advance_to(self, ns: int) -> None:
        """
        Publish ``ns`` and spin until the node's clock reads it and its tick timer has run.

        The timer has run for the time read when it is no longer due (its next call lies
        ahead): no wall-time wait, whatever the machine's load.
        """
        self.publish(*divmod(ns, 1_000_000_000))
        node = self.node
        assert self.ros.spin_until(lambda: node.get_clock().now().nanoseconds == ns,
                                   timeout=10.0)
        assert self.ros.spin_until(lambda: ran_for_now(node), timeout=10.0)
        # What the ticks published reaches the probe.
        self.ros.drain()


def ran_for_now(node) -> bool:
    """Return whether the node's tick timer has run for its clock's reading (or is paused)."""
    timer = node.ticker.timer
    return timer is None or timer.is_canceled() or timer.time_until_next_call() > 0


class RecordingBroadcaster:
    """A TransformBroadcaster double: keeps a copy of every transform it is sent."""

    def __init__(self) -> None:
        """Start with nothing sent and no node."""
        self.sent = []
        self.nodes = []

    def factory(self, node):
        """Play ``tf2_ros.TransformBroadcaster(node)``: remember the node, return self."""
        self.nodes.append(node)
        return self

    def sendTransform(self, transform) -> None:  # noqa: N802 (tf2_ros's name)
        """Record a copy (the node reuses its message)."""
        self.sent.append(copy.deepcopy(transform))
