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
``SimulatedBody``: the ``mouse_constraint`` node in-process, stepped in lockstep on simulated time.

The node runs with ``publish_clock`` and no timer of its own (``stepped``): ``step`` runs its
ticks. One tick: the input that arrived is applied, the physics steps, ``/clock``, ``pose``
and ``twist`` (TF and odometry when on) go out stamped with the tick's simulated time, then the
executor is drained until no callback is ready (``lockstep.drain``). A node added with
``add_node`` and ``use_sim_time`` thus sees every tick, its ROS-time timers fire at exact
simulated times, and what it publishes in response to tick k is taken before tick k + 1, from
which it acts. Nothing waits on wall time but the watchdogs, which fail loudly.

Inputs go out as a user's would, as messages and service calls from a probe node of the
harness (``probe``, named ``simulated_body``); the node's own validation judges them, and an
input it refuses raises ``InputRefused`` with the node's reason. ``pose`` and ``twist`` are the
latest the node published, as numpy arrays and as the messages themselves.
"""

from typing import Any, Callable, List, Optional, Sequence

import numpy as np
from rclpy.executors import Executor, SingleThreadedExecutor
from rclpy.node import Node
from rclpy.parameter import Parameter
from sensor_msgs.msg import JointState

from .errors import HarnessClosed, NeverHeld
from .harness_checks import (check_context, check_executor, checked_seconds, checked_stamp_ns,
                             checked_ticks, claim_context, predicate_text, release_context)
from .harness_parameters import checked_parameters, set_parameters
from .lockstep import drain, isolated_context, wait_matched
from .probe import Probe
from .readings import body_pose, body_twist, BodyPose, BodyTwist, world_point
from ..node.mouse_constraint_node import MouseConstraintNode
from ..wire.messages import point_message, set_stamp, wrench_message

# Wall seconds a drain may keep finding work, and endpoints may take to match, before failing.
DRAIN_TIMEOUT = 10.0
MATCH_TIMEOUT = 5.0
# ``transform_broadcaster`` not given: the node's own default.
NODE_DEFAULT = object()


class SimulatedBody:
    """
    The ``mouse_constraint`` node stepped in lockstep with the nodes added to it.

    :param context: an initialized rclpy context to run in, used by no other harness; by
        default one of its own with discovery off (``isolated_context``), shut down by
        ``close``.
    :param executor: the ``SingleThreadedExecutor`` of ``context`` to spin on; by default one of
        its own.
    :param namespace: the node's namespace ('' or '/name').
    :param on_tick: called with the harness after every tick (after the drain).
    :param transform_broadcaster: as ``MouseConstraintNode`` takes it; by default the node's
        (tf2_ros's, where importable).
    :param drain_timeout: wall seconds a drain may keep finding work before it fails (finite,
        > 0).
    :param match_timeout: wall seconds endpoints may take to match before ``add_node`` fails.
    :param urdf_path: a URDF file the node reads as its ``robot_description``
        (``robot_description_file``): mesh paths relative to it resolve against its directory.
    :param parameters: any of the node's parameters, as keywords (``mass=2.0``, ``floor=True``);
        the node refuses an invalid one as it would at start (``StartupRefusal``).
    :raises TypeError: an unknown parameter name; a context, executor or timeout of another
        type (``harness_checks``).
    :raises ValueError: ``publish_clock=False`` or ``use_sim_time=True``: the harness is the
        clock; a context another harness uses, or not initialized; an executor of another
        context; a timeout not finite and > 0.
    """

    def __init__(self, *, context=None, executor: Optional[Executor] = None,
                 namespace: str = '', on_tick: Optional[Callable[['SimulatedBody'], Any]] = None,
                 transform_broadcaster: Any = NODE_DEFAULT, drain_timeout: float = DRAIN_TIMEOUT,
                 match_timeout: float = MATCH_TIMEOUT, urdf_path: Optional[Any] = None,
                 **parameters: Any) -> None:
        """Start the node and the probe; wait until the probe matches the node."""
        if urdf_path is not None:  # the node reads it; meshes relative to it resolve there
            parameters['robot_description_file'] = str(urdf_path)
        values = checked_parameters(parameters)
        values['publish_clock'] = True
        self.drain_timeout = checked_seconds('drain_timeout', drain_timeout)
        self.match_timeout = checked_seconds('match_timeout', match_timeout)
        if context is not None:
            check_context(context)
        if executor is not None:
            check_executor(executor, context)
        self._closed = False
        self._time_ns = 0
        self._own_context = context is None
        self._own_executor = executor is None
        self.context = None
        self.executor: Executor = None
        self.node: MouseConstraintNode = None
        self._probe: Optional[Probe] = None
        self._added: List[Node] = []
        self._tick_callbacks: List[Callable] = [] if on_tick is None else [on_tick]
        if context is not None:
            claim_context(context, self)
        self.context = isolated_context() if context is None else context
        claim_context(self.context, self)
        try:
            self.executor = (SingleThreadedExecutor(context=self.context) if executor is None
                             else executor)
            broadcaster = ({} if transform_broadcaster is NODE_DEFAULT
                           else {'transform_broadcaster': transform_broadcaster})
            self.node = MouseConstraintNode(
                context=self.context, namespace=namespace, stepped=True, qos_events=False,
                parameter_overrides=[Parameter(name, value=value)
                                     for name, value in values.items()], **broadcaster)
            self._probe = Probe(self.node, namespace=namespace, drain=self.drain)
            self.executor.add_node(self.node)
            self.executor.add_node(self._probe.node)
            wait_matched(self.executor, self._probe.node, self.node, timeout=match_timeout,
                         drain_timeout=drain_timeout)
        except BaseException:
            self.close()
            raise

    def __enter__(self) -> 'SimulatedBody':
        """Return the harness."""
        return self

    def __exit__(self, *_exception) -> None:
        """Close the harness."""
        self.close()

    def close(self) -> None:
        """
        Destroy the node and the probe; shut down the executor and context it made.

        What it published stays readable (``time``, ``pose``, ``twist``, ``anchor``); anything
        else raises ``HarnessClosed``. Closing again does nothing.
        """
        if self._closed:
            return
        self._closed = True
        if self.node is not None:
            self._time_ns = self.node.ticker.now_ns()
        executor = self.executor
        for node in self._added:
            if executor is not None:
                executor.remove_node(node)
        self._added = []
        for node in (None if self._probe is None else self._probe.node, self.node):
            if node is not None:
                if executor is not None:
                    executor.remove_node(node)
                node.destroy_node()
        # The probe stays: what the node published stays readable.
        self.node = None
        if executor is not None and self._own_executor:
            executor.shutdown()
        self.executor = None
        if self.context is not None:
            release_context(self.context, self)
            if self._own_context:
                self.context.try_shutdown()

    def _seen(self, what: str):
        """Return the probe's latest ``what`` (pose, twist, pose_anchor), None before one."""
        return None if self._probe is None else getattr(self._probe, what)

    def _open(self, what: str) -> None:
        """Raise ``HarnessClosed`` naming ``what`` when the harness is closed."""
        if self._closed:
            raise HarnessClosed(what)

    # --- what the node published -------------------------------------------------------------

    @property
    def time(self) -> float:
        """Return the latest tick's simulated time in seconds: 0 before the first."""
        return (self._time_ns if self._closed else self.node.ticker.now_ns()) * 1e-9

    @property
    def pose(self) -> Optional[BodyPose]:
        """Return the latest ``pose`` the node published, or None before the first tick."""
        return body_pose(self._seen('pose'))

    @property
    def anchor(self) -> Optional[np.ndarray]:
        """
        Return the anchor's world point (m) at the latest ``pose``, or None before the first tick.

        The dragged point: the body-frame ``anchor`` the node held when it published that pose
        (a grab's point once it grabbed), placed by the pose. What a drag brings to its target,
        where ``pose.position`` is the centre of mass.
        """
        return world_point(self._seen('pose'), self._seen('pose_anchor'))

    @property
    def joints(self) -> Optional[JointState]:
        """Return a robot's latest ``joint_states`` (names, positions, velocities, efforts)."""
        return self._probe.joint_states

    @property
    def twist(self) -> Optional[BodyTwist]:
        """Return the latest ``twist`` the node published, or None before the first tick."""
        return body_twist(self._seen('twist'))

    # --- nodes under test ---------------------------------------------------------------------

    def add_node(self, node: Node) -> Node:
        """
        Spin ``node`` with the body, in lockstep; return it.

        Waits (at most ``match_timeout`` wall seconds) until its publishers and subscriptions
        on the body's topics, and its clients of the body's services, have matched.

        :raises ValueError: ``node`` is in another context.
        :raises MatchTimeout: naming each endpoint that did not match, and why where its QoS
            says.
        """
        self._open('add_node')
        if node.context is not self.context:
            raise ValueError(f'{node.get_fully_qualified_name()} is in another context: create '
                             'it with context=body.context')
        self.executor.add_node(node)
        self._added.append(node)
        wait_matched(self.executor, node, self.node, timeout=self.match_timeout,
                     drain_timeout=self.drain_timeout)
        return node

    def add_tick_callback(self, callback: Callable[['SimulatedBody'], Any]) -> None:
        """Call ``callback(body)`` after every tick, once the executor is drained."""
        self._open('add_tick_callback')
        self._tick_callbacks.append(callback)

    # --- stepping -----------------------------------------------------------------------------

    def drain(self) -> int:
        """Run every callback that is ready until none is; return how many ran."""
        self._open('drain')
        return drain(self.executor, timeout=self.drain_timeout)

    def step(self, ticks: int = 1) -> None:
        """
        Run ``ticks`` ticks, draining the executor after each (and before the first).

        While the node is paused (``~/pause``) a tick runs no physics and the simulated time
        stands still; the executor is drained all the same.

        :raises TypeError: ``ticks`` is not a whole number (``2.9``, ``'3'``).
        :raises ValueError: ``ticks`` is below 0.
        """
        self._open('step')
        ticks = checked_ticks('ticks', ticks)
        node, callbacks = self.node, self._tick_callbacks
        self.drain()
        for _ in range(ticks):
            node.ticker.step()
            self.drain()
            for callback in callbacks:
                callback(self)

    def step_until(self, predicate: Callable[[], bool], max_ticks: int) -> int:
        """
        Step until ``predicate()`` holds; return the ticks it took (0 if it held at once).

        :raises NeverHeld: it did not hold within ``max_ticks``, with the time reached.
        :raises TypeError, ValueError: ``max_ticks`` is not a whole number >= 0.
        """
        self._open('step_until')
        max_ticks = checked_ticks('max_ticks', max_ticks)
        if predicate():
            return 0
        for ticks in range(1, max_ticks + 1):
            self.step()
            if predicate():
                return ticks
        paused = ' (the node is paused)' if self.node.ticker.paused else ''
        raise NeverHeld(f'{predicate_text(predicate)} did not hold within {max_ticks} ticks: '
                        f'simulated time {self.time:.6f} s{paused}')

    # --- inputs -------------------------------------------------------------------------------

    def grab(self, point: Sequence[float], *, frame_id: str = '') -> tuple:
        """
        Grab the body at the world ``point``: it becomes the anchor and the target.

        :returns: the anchor the node set (body frame, m).
        :raises InputRefused: the node refused it (off the body, another frame ...).
        """
        self._open('grab')
        self._probe.send('grab', point_message(point, frame_id, 0))
        return tuple(self.node.get_parameter('anchor').value)

    def target(self, point: Sequence[float], *, stamp: Optional[float] = None,
               frame_id: str = '') -> None:
        """
        Send a target: the anchor is dragged to ``point`` (m, world frame).

        :param stamp: the time the pointer was there (simulated s): a stream of stamped
            targets is timed by its stamps; None sends a zero stamp (timed by its arrival).
        :raises InputRefused: the node refused it (not finite, outside the workspace ...).
        """
        self._open('target')
        self._probe.send('target', point_message(point, frame_id, checked_stamp_ns(stamp)))

    def wrench(self, force: Sequence[float], torque: Sequence[float] = (0.0, 0.0, 0.0), *,
               stamp: Optional[float] = None, frame_id: str = '') -> None:
        """
        Push the body: ``force`` (N) through the COM and ``torque`` (N m), world frame.

        Applied from the tick at ``stamp`` (simulated s; None: the next tick) until
        ``wrench_timeout`` passes without another; a zero wrench ends it.

        :raises InputRefused: the node refused it (beyond its bounds, not finite ...).
        """
        self._open('wrench')
        message = wrench_message(force, torque, frame_id)
        set_stamp(message.header.stamp, checked_stamp_ns(stamp))
        self._probe.send('wrench', message)

    def release(self) -> str:
        """Call ``~/release``: the body flies free; return the node's reply."""
        self._open('release')
        return self._probe.call('release').message

    def reset(self) -> str:
        """
        Call ``~/reset``: the initial state, the configured anchor; return the node's reply.

        :raises RuntimeError: the node could not reset (its reply says why).
        """
        self._open('reset')
        response = self._probe.call('reset')
        if not response.success:
            raise RuntimeError(response.message)
        return response.message

    def set_parameters(self, **values: Any) -> None:
        """
        Change parameters of the node between steps, all or none (``set_parameters_atomically``).

        A new body, which the node loads off its tick, is swapped in (or refused) before this
        returns (``harness_parameters.set_parameters``): the next step runs with it.

        :raises TypeError: an unknown parameter name.
        :raises ValueError: the node refused the change, with its reason; or the change would
            take the clock from the harness.
        :raises TimeoutError: the body did not load within ``LOAD_TIMEOUT`` wall seconds.
        """
        self._open('set_parameters')
        set_parameters(self.node, values)
        self.drain()
