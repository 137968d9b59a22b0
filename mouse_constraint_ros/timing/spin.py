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
Ctrl-C, SIGTERM and SIGHUP as a request to stop, and the one spin loop of the executables.

rclpy's own handlers shut the context down from the signal, while a timer callback may be
publishing: the publish then raises with a traceback. Here the signal only sets a flag
(``StopRequest``); the spin loop sees it within one ``POLL_PERIOD`` and the node is torn down
in order. SIGHUP (the terminal closed) ends the node like SIGTERM: Python's default for it kills
the process with no clean-up.

``spin_until`` is the loop of every executable: it spins an executor with ``spin_once`` until
a condition holds, a stop is requested, a deadline passes or the context is shut down, and
returns which (a ``SpinEnd``). ``wait_until`` is the same loop for waits inside a command, where
a stop is an ``Interrupted`` and a deadline False. ``call_until_answered`` waits so for a
service's answer and sends the request again each ``ASK_AGAIN_SECONDS`` it goes unanswered: a
client sees a service in another process as ready once it has matched the server's endpoints,
which may not yet have matched the client's, and a request sent then is lost (the service stays
silent however long the client waits). That is for a request that may be served twice: an
unanswered request may also be one the server is still serving. A request that must be served
once (``~/step``) goes with ``call_once``, sent once and waited for until its deadline, after
``call_until_answered`` had the server's node answer an idempotent request from a client made
later (``mouse_ctl``: the node's ``list_parameters``): a participant announces its endpoints in
order, on reliable discovery streams, so a node that answered the later client has matched the
earlier one, and the request sent once is not lost.

``NodeRun`` is the ending of ``main`` in the executables that serve a node until stopped
(``mouse_constraint``, ``mouse_view``, ``mouse_marker``): the node spun so, then destroyed and
the context shut down, in that order, however ``main`` leaves.

Not ``executor.spin()``: in this rclpy (7.1.6) the EventsExecutor's ``spin()`` busy-waits at a
full core and never returns to Python. Nor ``spin_until_future_complete``, which saves a little
CPU but leaks 32 B per call here (bench/spin_leak.py). ``spin_once`` with a timeout does neither
and lets the loop see the stop flag.
"""

import enum
import signal
import time
from types import FrameType
from typing import Callable, List, Optional

import rclpy
from rclpy.client import Client
from rclpy.context import Context
from rclpy.executors import Executor, ExternalShutdownException
from rclpy.experimental import EventsExecutor
from rclpy.node import Node

STOP_SIGNALS = (signal.SIGINT, signal.SIGTERM, signal.SIGHUP)
# Longest one spin_once blocks before the loop looks at the stop flag and the clock again (s).
POLL_PERIOD = 0.05
# A request unanswered this long (s) is sent again (call_until_answered).
ASK_AGAIN_SECONDS = 1.0


class StopRequest:
    """Install handlers for STOP_SIGNALS that record the request; restore them on exit."""

    def __init__(self) -> None:
        """Create the request, not yet installed."""
        self.signal: Optional[int] = None
        self._previous = {}

    def __bool__(self) -> bool:
        """Return whether a stop was requested."""
        return self.signal is not None

    def _handle(self, signum: int, _frame: Optional[FrameType]) -> None:
        self.signal = signum

    def __enter__(self) -> 'StopRequest':
        """Install the handlers."""
        for signum in STOP_SIGNALS:
            self._previous[signum] = signal.signal(signum, self._handle)
        return self

    def __exit__(self, *_exception) -> None:
        """Restore the previous handlers."""
        for signum, handler in self._previous.items():
            signal.signal(signum, handler)


class SpinEnd(enum.Enum):
    """Why ``spin_until`` returned."""

    CONDITION = 'the condition held'
    STOPPED = 'a stop was requested'
    DEADLINE = 'the deadline passed'
    SHUTDOWN = 'the context was shut down'


class Interrupted(Exception):
    """A stop was requested while waiting; ``signal`` is its number."""

    def __init__(self, signum: int) -> None:
        """Record the signal."""
        super().__init__(signal.Signals(signum).name)
        self.signal = signum


def spin_until(executor: Executor, stop: StopRequest, *,
               condition: Optional[Callable[[], bool]] = None,
               deadline: Optional[float] = None, period: float = POLL_PERIOD,
               pace: Optional[Callable[[], Optional[float]]] = None) -> SpinEnd:
    """
    Spin ``executor`` with ``spin_once`` until one of the ends, and return which.

    Before each ``spin_once`` it looks, in this order, at ``condition()``, at ``stop``, at the
    executor's context and at the deadline: a condition that holds wins over a stop that came
    at the same time, and nothing is spun once the context is shut down.

    :param executor: the executor, its nodes added; it blocks at most ``period`` per call.
    :param stop: the stop request (a signal came when it is true).
    :param condition: spin until it returns true; None to spin until another end.
    :param deadline: ``time.monotonic()`` after which to give up; None for none.
    :param period: the ``spin_once`` timeout (s), the longest a stop goes unseen.
    :param pace: called before each ``spin_once``: it makes the calls the loop owes (a
        ``LoopTimer``'s), or posts them to the executor, and returns the time (s) until the
        next, or None for none; the ``spin_once`` waits no longer than that.
    """
    context = executor.context
    while True:
        if condition is not None and condition():
            return SpinEnd.CONDITION
        if stop:
            return SpinEnd.STOPPED
        if not context.ok():
            return SpinEnd.SHUTDOWN
        if deadline is not None and time.monotonic() > deadline:
            return SpinEnd.DEADLINE
        timeout = period
        if pace is not None:
            until_next = pace()
            if until_next is not None and until_next < period:
                timeout = until_next if until_next > 0.0 else 0.0
        try:
            executor.spin_once(timeout_sec=timeout)
        except ExternalShutdownException:
            return SpinEnd.SHUTDOWN


def wait_until(executor: Executor, stop: StopRequest, condition: Callable[[], bool], *,
               deadline: float) -> bool:
    """
    Spin ``executor`` until ``condition()`` holds; return whether it did before ``deadline``.

    :param deadline: ``time.monotonic()`` after which to return False.
    :raises Interrupted: as soon as ``stop`` is requested.
    :raises ExternalShutdownException: when the context is shut down meanwhile.
    """
    end = spin_until(executor, stop, condition=condition, deadline=deadline)
    if end is SpinEnd.STOPPED:
        raise Interrupted(stop.signal)
    if end is SpinEnd.SHUTDOWN:
        raise ExternalShutdownException()
    return end is SpinEnd.CONDITION


def call_until_answered(client: Client, request, executor: Executor, stop: StopRequest, *,
                        deadline: float) -> Optional[object]:
    """
    Return the service's response to ``request``, sent again while it goes unanswered.

    A request for which no response came within ``ASK_AGAIN_SECONDS`` is dropped and sent again,
    until ``deadline`` (``time.monotonic()``); for requests that may be served twice.

    :returns: the response, or None when none came by ``deadline``.
    :raises Interrupted: when ``stop`` is requested meanwhile.
    """
    while True:
        future = client.call_async(request)
        again = min(deadline, time.monotonic() + ASK_AGAIN_SECONDS)
        if wait_until(executor, stop, future.done, deadline=again):
            return future.result()
        client.remove_pending_request(future)
        if time.monotonic() >= deadline:
            return None


def call_once(client: Client, request, executor: Executor, stop: StopRequest, *,
              deadline: float) -> Optional[object]:
    """
    Return the service's response to ``request``, sent once however long it goes unanswered.

    For a request that must not be served twice: an answer that is slow to come is waited for,
    never asked again. Unanswered by ``deadline`` (``time.monotonic()``), its pending entry is
    removed from ``client``, so that a late answer is dropped.

    :returns: the response, or None when none came by ``deadline``.
    :raises Interrupted: when ``stop`` is requested meanwhile.
    """
    future = client.call_async(request)
    try:
        return future.result() if wait_until(executor, stop, future.done,
                                             deadline=deadline) else None
    finally:
        client.remove_pending_request(future)


class NodeRun:
    """
    A node served until a stop or the context's shutdown, then torn down in order.

    ``with NodeRun() as run:`` requests stops on STOP_SIGNALS for the block (``run.stop``: the
    executables init rclpy without its own handlers); the node made in it is ``run.node``, and
    ``run.serve()`` spins it on an EventsExecutor until a signal or the context's shutdown, both
    a normal end. However the block is left (``serve`` returned, a ``return`` before it, an
    exception), the handlers go back, ``run.node`` is destroyed, what ``close`` was given runs,
    in that order, and the context is shut down.

    :param context: the context to shut down; None for rclpy's default, the executables' one.
    """

    def __init__(self, *, context: Optional[Context] = None) -> None:
        """Create the run, its stop request not yet installed and no node."""
        self.stop = StopRequest()
        self.node: Optional[Node] = None
        self._context = context
        self._closers: List[Callable[[], None]] = []

    def close(self, closer: Callable[[], None]) -> None:
        """Have ``closer`` run on the way out, after the node is destroyed."""
        self._closers.append(closer)

    def serve(self, pace: Optional[Callable[[], Optional[float]]] = None) -> int:
        """
        Spin ``node`` until a signal or the context's shutdown; return 0, the exit status.

        :param pace: the calls the loop makes itself between events (``spin_until``).
        """
        executor = EventsExecutor(context=self.node.context)
        executor.add_node(self.node)
        spin_until(executor, self.stop, pace=pace)
        return 0

    def __enter__(self) -> 'NodeRun':
        """Install the stop request's handlers."""
        try:
            self.stop.__enter__()
        except BaseException:
            self._tear_down()
            raise
        return self

    def __exit__(self, *exception) -> None:
        """Restore the handlers; destroy the node, run the closers, shut the context down."""
        try:
            self.stop.__exit__(*exception)
        finally:
            self._tear_down()

    def _tear_down(self) -> None:
        if self.node is not None:
            self.node.destroy_node()
        for closer in self._closers:
            closer()
        rclpy.try_shutdown(context=self._context)
