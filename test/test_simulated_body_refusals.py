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
``SimulatedBody`` refuses, with one error that says why, what it cannot run as asked.

A context another harness uses, an uninitialized one, an executor it cannot drain or of another
context, a watchdog time that is not finite and > 0, a number of ticks that is not a whole number
>= 0, a stamp a message cannot hold, and any use once closed.
"""

import math

import numpy as np
import pytest
from rclpy.context import Context
from rclpy.executors import MultiThreadedExecutor, SingleThreadedExecutor
from rclpy.experimental import EventsExecutor
from rclpy.node import Node

from mouse_constraint_ros.testing import HarnessClosed, SimulatedBody
from mouse_constraint_ros.testing.lockstep import isolated_context


@pytest.mark.ros
def test_a_context_another_harness_uses_is_refused():
    """Two harnesses in one context would cross-talk: the second is refused, the first runs on."""
    with SimulatedBody() as first:
        with pytest.raises(ValueError, match='already used by another SimulatedBody'):
            SimulatedBody(context=first.context)
        first.grab((0.2, 0.1, 1.05))
        first.step(2)
        assert first.time == pytest.approx(0.002, abs=1e-12)
    given = isolated_context()
    try:
        with SimulatedBody(context=given) as body:
            body.step(1)
            with pytest.raises(ValueError, match='already used'):
                SimulatedBody(context=given)
        with SimulatedBody(context=given) as again:  # free once the first is closed
            again.step(1)
    finally:
        given.try_shutdown()


@pytest.mark.ros
def test_a_context_that_is_not_initialized_is_refused(capfd):
    """An uninitialized or shut down context: one ValueError, no noise of a half-made executor."""
    with pytest.raises(ValueError, match='not initialized'):
        SimulatedBody(context=Context())
    ended = isolated_context()
    ended.shutdown()
    with pytest.raises(ValueError, match='not initialized or is shut down'):
        SimulatedBody(context=ended)
    with pytest.raises(TypeError, match='rclpy Context'):
        SimulatedBody(context='default')
    import gc
    gc.collect()
    assert 'Exception ignored' not in capfd.readouterr().err


@pytest.mark.ros
def test_an_executor_it_cannot_drain_or_of_another_context_is_refused(capfd):
    """The events and the multi-threaded executors: TypeError; another context's: ValueError."""
    context = isolated_context()
    try:
        for executor in (EventsExecutor(context=context), MultiThreadedExecutor(context=context)):
            with pytest.raises(TypeError, match='must be a SingleThreadedExecutor'):
                SimulatedBody(context=context, executor=executor)
            if hasattr(executor, 'shutdown'):
                executor.shutdown()
        other = SingleThreadedExecutor(context=context)
        with pytest.raises(ValueError, match='another context'):
            SimulatedBody(executor=other)
        other.shutdown()
        with SimulatedBody(context=context) as body:  # refused, nothing was taken
            body.step(1)
    finally:
        context.try_shutdown()
    assert 'Exception ignored' not in capfd.readouterr().err


@pytest.mark.parametrize('name', ['drain_timeout', 'match_timeout'])
@pytest.mark.parametrize('value', [math.nan, math.inf, 0.0, -1.0])
def test_a_watchdog_that_is_not_finite_and_positive_is_refused(name, value):
    """Not a number would switch the watchdog off, inf or 0 never let it run: both refused."""
    with pytest.raises(ValueError, match=f'{name} must be finite and > 0 s'):
        SimulatedBody(**{name: value})


def test_a_watchdog_of_another_type_is_refused():
    """A watchdog time is a number of seconds."""
    with pytest.raises(TypeError, match='drain_timeout must be a number of seconds'):
        SimulatedBody(drain_timeout='10')


def test_ticks_that_are_not_a_whole_number_from_zero_are_refused(simulated_body):
    """step(-1), step(2.9), step('3'), step(True), step_until(max_ticks=-5): each refused."""
    body = simulated_body
    for ticks, error in ((-1, ValueError), (2.9, TypeError), ('3', TypeError),
                         (True, TypeError)):
        with pytest.raises(error, match='ticks'):
            body.step(ticks)
    for ticks, error in ((-5, ValueError), (2.5, TypeError)):
        with pytest.raises(error, match='max_ticks'):
            body.step_until(lambda: False, max_ticks=ticks)
    assert body.time == 0.0
    body.step(np.int64(3))
    body.step(0)
    assert body.time == pytest.approx(0.003, abs=1e-12)
    assert body.step_until(lambda: True, max_ticks=0) == 0


@pytest.mark.parametrize('stamp', [2.0 ** 32 + 1.0, 1e10, 1e300, 2.0 ** 31, -1e-9, math.inf])
def test_a_stamp_the_message_cannot_hold_is_refused(simulated_body, stamp):
    """Time's seconds are an int32: t + 2^32 s would wrap to t, 1e10 s to 1410065408 s."""
    with pytest.raises(ValueError, match='stamp must be a finite time >= 0 s and below 2'):
        simulated_body.target((0.5, 0.2, 1.0), stamp=stamp)
    with pytest.raises(ValueError, match='stamp must be'):
        simulated_body.wrench((0.0, 0.0, 1.0), stamp=stamp)


def test_a_stamp_of_another_type_is_refused(simulated_body):
    """A stamp is a time in seconds: not a string, not a bool."""
    for stamp in ('1.0', True):
        with pytest.raises(TypeError, match='stamp must be a time in seconds'):
            simulated_body.target((0.5, 0.2, 1.0), stamp=stamp)


@pytest.mark.ros
def test_after_close_each_use_raises_one_closed_error():
    """step, drain, inputs, services, parameters, nodes: HarnessClosed; readings stay."""
    body = SimulatedBody()
    body.step(5)
    body.close()
    body.close()  # again: nothing
    uses = {
        'step': lambda: body.step(1), 'step_until': lambda: body.step_until(bool, 3),
        'drain': body.drain, 'target': lambda: body.target((0.5, 0.2, 1.0)),
        'grab': lambda: body.grab((0.2, 0.1, 1.05)), 'wrench': lambda: body.wrench((0, 0, 1)),
        'release': body.release, 'reset': body.reset,
        'set_parameters': lambda: body.set_parameters(mass=3.0),
        'add_tick_callback': lambda: body.add_tick_callback(print),
        'add_node': lambda: body.add_node(Node('late', context=other)),
    }
    other = isolated_context()
    for what, use in uses.items():
        with pytest.raises(HarnessClosed, match=f'^{what}: this SimulatedBody is closed'):
            use()
    other.try_shutdown()
    assert body.time == pytest.approx(0.005, abs=1e-12)
    assert body.pose.time == pytest.approx(0.005, abs=1e-12) and body.anchor.shape == (3,)
