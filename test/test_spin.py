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
The executables' one spin loop: it ends on a condition, a stop, a deadline or a shutdown.

Both executors the package uses are tried: the EventsExecutor (node, recorder) and the
SingleThreadedExecutor (``mouse_target``). ``NodeRun``, the ending of the serving executables'
``main``, serves a node so and tears it down in order however its block is left.
"""

import os
import signal
import threading
import time

import pytest
import rclpy
from rclpy.executors import ExternalShutdownException, SingleThreadedExecutor
from rclpy.experimental import EventsExecutor
from rclpy.node import Node

from mouse_constraint_ros.timing.spin import Interrupted
from mouse_constraint_ros.timing.spin import NodeRun
from mouse_constraint_ros.timing.spin import spin_until
from mouse_constraint_ros.timing.spin import SpinEnd
from mouse_constraint_ros.timing.spin import STOP_SIGNALS
from mouse_constraint_ros.timing.spin import StopRequest
from mouse_constraint_ros.timing.spin import wait_until


@pytest.fixture(params=[EventsExecutor, SingleThreadedExecutor], ids=['events', 'single'])
def spinning(request, ros):
    """Return an executor of each kind on the test's context, with one node added."""
    executor = request.param(context=ros.context)
    node = Node('spin_test', context=ros.context)
    executor.add_node(node)
    yield executor, node
    executor.shutdown()
    node.destroy_node()


def requested(signum: int) -> StopRequest:
    """Return a stop request as a handled ``signum`` leaves it, without installing handlers."""
    stop = StopRequest()
    stop.signal = signum
    return stop


def test_spins_callbacks_until_the_condition_holds(spinning):
    """A timer's callbacks run inside the loop; it returns once they made the condition true."""
    executor, node = spinning
    calls = []
    node.create_timer(0.01, lambda: calls.append(None))
    assert spin_until(executor, StopRequest(), condition=lambda: len(calls) >= 3) \
        is SpinEnd.CONDITION
    assert len(calls) == 3


def test_a_signal_stops_the_loop_and_the_handlers_are_restored(spinning):
    """SIGINT sent from a callback ends the loop with STOPPED; the handlers go back on exit."""
    executor, node = spinning
    before = {signum: signal.getsignal(signum) for signum in STOP_SIGNALS}
    node.create_timer(0.05, lambda: os.kill(os.getpid(), signal.SIGINT))
    with StopRequest() as stop:
        assert spin_until(executor, stop) is SpinEnd.STOPPED
    assert stop.signal == signal.SIGINT
    assert {signum: signal.getsignal(signum) for signum in STOP_SIGNALS} == before


def test_a_condition_that_holds_wins_over_a_stop(spinning):
    """Both at once: the condition (e.g. the recording is complete) is what ended the loop."""
    executor, _ = spinning
    assert spin_until(executor, requested(signal.SIGTERM), condition=lambda: True) \
        is SpinEnd.CONDITION
    assert spin_until(executor, requested(signal.SIGTERM), condition=lambda: False) \
        is SpinEnd.STOPPED


def test_the_deadline_ends_the_loop_once_passed(spinning):
    """Nothing happens: DEADLINE, not before the deadline."""
    executor, _ = spinning
    deadline = time.monotonic() + 0.2
    assert spin_until(executor, StopRequest(), condition=lambda: False, deadline=deadline) \
        is SpinEnd.DEADLINE
    assert time.monotonic() > deadline


def test_a_shutdown_context_ends_the_loop_without_an_exception(spinning, ros):
    """The context shut down from another thread while spinning, or before: SHUTDOWN."""
    executor, _ = spinning
    shutdown = threading.Timer(0.2, ros.context.shutdown)
    shutdown.start()
    try:
        assert spin_until(executor, StopRequest()) is SpinEnd.SHUTDOWN
    finally:
        shutdown.join()
    assert spin_until(executor, StopRequest()) is SpinEnd.SHUTDOWN


def test_wait_until_says_whether_the_condition_held_and_raises_on_a_stop(spinning, ros):
    """True on the condition, False at the deadline, Interrupted with the signal on a stop."""
    executor, _ = spinning
    deadline = time.monotonic() + 0.1
    assert wait_until(executor, StopRequest(), lambda: True, deadline=deadline)
    assert not wait_until(executor, StopRequest(), lambda: False, deadline=deadline)
    with pytest.raises(Interrupted) as interrupted:
        wait_until(executor, requested(signal.SIGHUP), lambda: False, deadline=deadline + 60.0)
    assert interrupted.value.signal == signal.SIGHUP
    ros.context.shutdown()
    with pytest.raises(ExternalShutdownException):
        wait_until(executor, StopRequest(), lambda: False, deadline=deadline + 60.0)


class TornDown(Node):
    """A node that notes in ``order`` when it is destroyed."""

    def __init__(self, order: list, **kwargs) -> None:
        """Create the node; ``order`` receives 'node' when it is destroyed."""
        super().__init__('node_run_test', **kwargs)
        self.order = order

    def destroy_node(self) -> None:
        """Note the destruction, then destroy."""
        self.order.append('node')
        super().destroy_node()


def test_a_node_run_serves_until_a_signal_then_tears_down_in_order(ros):
    """SIGTERM from a callback: exit 0; then handlers back, node destroyed, closers, shutdown."""
    before = {signum: signal.getsignal(signum) for signum in STOP_SIGNALS}
    order = []

    def closer() -> None:
        handlers = {signum: signal.getsignal(signum) for signum in STOP_SIGNALS}
        order.append(('closer', handlers == before, ros.context.ok()))

    with NodeRun(context=ros.context) as run:
        run.node = TornDown(order, context=ros.context)
        run.close(closer)
        run.node.create_timer(0.05, lambda: os.kill(os.getpid(), signal.SIGTERM))
        assert run.serve() == 0
    assert run.stop.signal == signal.SIGTERM
    assert order == ['node', ('closer', True, True)]
    assert not ros.context.ok()


def test_a_node_run_ends_with_the_context_and_tears_down_on_an_exception(ros):
    """A shutdown from elsewhere is a normal end; an exception leaves the block torn down too."""
    order = []
    with NodeRun(context=ros.context) as run:
        run.node = TornDown(order, context=ros.context)
        run.node.create_timer(0.05, ros.context.shutdown)
        assert run.serve() == 0
        assert not run.stop
    assert order == ['node']
    second = rclpy.Context()
    rclpy.init(context=second)
    with pytest.raises(RuntimeError, match='refused'):
        with NodeRun(context=second) as run:
            run.node = TornDown(order, context=second)
            raise RuntimeError('refused')
    assert order == ['node', 'node']
    assert not second.ok()
