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
The ``mouse_constraint`` node: parameters, topics, services and timers, wired to pure parts.

It holds no physics and no policy of its own: a ``MouseSimulation`` does the stepping,
``TickGrid`` says which ticks are due on the node's clock and ``TickBudget`` which of them one
callback runs; with ``publish_clock`` ``SimulatedClock`` and ``ClockPacer`` pace them.
``PublishTicks`` says which ticks publish (``publish_rate_hz``), ``StatePublishers`` sends pose,
twist, TF and odometry (raw CDR), ``TargetGate`` and ``WrenchGate`` judge the input and
``input_timeouts`` when it expires, ``parameters`` validates the configuration, ``startup``
words the refusals, ``markers`` and ``diagnostics`` build the monitoring messages.

The node's concerns are its parts: ``tick_loop`` (the timer, the due ticks, one tick),
``simulator_controls`` (the node as the clock, pause, step, reset, release, the wrench),
``monitors`` (markers and diagnostics timers) and ``parameter_changes`` (declaration and
``ros2 param set``); this module wires them and handles the target and the grab.

Start-up refuses what it cannot run with one FATAL line tagged with the node's real name and
exit 1 (``startup``); unknown keys in the parameters given to the node are warned about.
"""

import sys
from typing import Any, Callable, List, NoReturn, Optional

from geometry_msgs.msg import PointStamped
import rclpy
from rclpy.clock import Clock, ClockType
from rclpy.experimental import EventsExecutor
from rclpy.impl.implementation_singleton import rclpy_implementation as _rclpy
from rclpy.node import Node
from rclpy.parameter import Parameter
from rclpy.service_introspection import ServiceIntrospectionState
from rclpy.signals import SignalHandlerOptions
from std_srvs.srv import Trigger

from .monitors import Monitors
from .parameter_changes import ParameterChanges
from .parameters import node_config, PARAMETERS
from .simulator_controls import SimulatorControls
# CLOCK_LOOP and StartupRefusal: importable from the node, where its refusals come from.
from .startup import (CLOCK_LOOP, clock_loop, describe, rcl_reason,  # noqa: F401
                      requested_logger_name, StartupRefusal, unknown_parameter_warnings)
from .tick_loop import TickLoop
from ..inputs.grab import grab
from ..inputs.input_timeouts import target_release_text, timed_out
from ..inputs.target_gate import apart, TargetGate
from ..inputs.target_stamps import TargetStamps
from ..inputs.throttle import Throttle
from ..physics import MouseSimulation
from ..physics.algebra import Vector3
from ..physics.target_motion import STREAM_GAP
from ..timing.guarded_time_source import guard_time_source
from ..timing.spin import spin_until, StopRequest
from ..timing.tick_budget import TickBudget
from ..timing.tick_grid import CoreClock
from ..wire.interface import (GRAB_TOPIC, NODE_NAME, RELEASE_SERVICE, RESET_SERVICE,
                              SERVICE_EVENT_QOS, TARGET_QOS, TARGET_TOPIC)
from ..wire.messages import point_from_message, stamp_nanoseconds
from ..wire.state_publishers import (BroadcasterFactory, DEFAULT_BROADCASTER, StatePublishers,
                                     TF_UNAVAILABLE)

# Throttle period of the warnings about bad input and missed rate (s).
WARN_PERIOD = 2.0
# Period (s, steady clock) of the check that a simulated clock has started.
CLOCK_WATCH_PERIOD = 1.0
# The node's transform_broadcaster when none is given: tf2_ros's, where importable.
_DEFAULT_BROADCASTER = object()


class MouseConstraintNode(ParameterChanges, TickLoop, SimulatorControls, Monitors,
                          Node):
    """
    Serves one rigid body dragged by the mouse constraint.

    Subscribes ``target`` (PointStamped), publishes ``pose`` (PoseStamped) and ``twist``
    (TwistStamped) at the publish rate (every tick by default), TF and ``odom`` (Odometry) when
    on, offers ``~/reset`` and ``~/release`` (Trigger).

    A point on ``grab`` (PointStamped) that lies on the body's box (``grab`` module) becomes the
    anchor and the target: the node sets its own ``anchor`` parameter to it, so that the
    configuration, ``ros2 param get`` and the markers all show the grabbed point. Targets then
    drag that point, ``~/release`` lets go of it, ``~/reset`` restores the configured anchor:
    the one the node started with or was last given through its parameters.
    """

    def __init__(self, *, transform_broadcaster: Optional[BroadcasterFactory] = (
            _DEFAULT_BROADCASTER), **kwargs: Any) -> None:
        """
        Declare parameters and build the simulation.

        :param transform_broadcaster: makes the TF broadcaster from the node (anything with
            ``sendTransform(TransformStamped)`` that sends before it returns); by default
            ``tf2_ros.TransformBroadcaster``, or none when tf2_ros is not importable; None: no
            TF.
        :param kwargs: passed to ``rclpy.node.Node``.
        :raises StartupRefusal: (a ValueError) a parameter or the configuration is invalid; the
            node is destroyed then.
        """
        super().__init__(NODE_NAME, **kwargs)
        guard_time_source(self, lambda text: self._warn('clock ignored', lambda: text))
        try:
            for parameter in PARAMETERS:
                self._declare(parameter)
            self._config = node_config(self._parameter_values())
        except ValueError as error:
            self._refuse(str(error))
        self._warn_about_unknown_parameters()
        loop = clock_loop(self._config.publish_clock, self.get_parameter('use_sim_time').value)
        if loop is not None:
            self._refuse(loop)
        self._simulation = MouseSimulation(self._config.settings, self._config.initial_state)
        self._user_target = False
        self._last_target_ns: Optional[int] = None
        self._gate = TargetGate(self._config.frame_id, self._config.workspace_radius)
        self._stamps, self._core_clock = TargetStamps(STREAM_GAP), CoreClock()
        # The anchor of the parameters (start or ros2 param set), which ~/reset restores.
        self._configured_anchor = self._config.settings.constraint.anchor
        # True while the node sets its own anchor parameter for a grab or a reset.
        self._setting_anchor = False
        self._throttle = Throttle(self.get_logger().warning, period=WARN_PERIOD)
        # Through a function of its own: rclpy keys a log call's severity by its caller, and the
        # warnings are logged from the same line of Throttle.
        self._notes = Throttle(lambda text: self.get_logger().info(text), period=WARN_PERIOD)
        self._hold_initial_anchor()
        self.ticks_run = 0
        self.late_ticks = 0
        self.dropped_ticks = 0
        self.clock_restarts = 0
        # Why ticks were last dropped, for /diagnostics; None while none were.
        self.drop_cause: Optional[str] = None
        # Which due ticks a timer callback runs, and when it rests (node clock only).
        self._budget = TickBudget()
        # Which clock the grid runs on: simulated (True) or system time.
        self._grid_sim_time = self.get_clock().ros_time_is_active
        # Timers that must run while a simulated clock stands still or has not started.
        self._steady_clock = Clock(clock_type=ClockType.STEADY_TIME)
        self._simulator_controls_init()

        # The stamp of the latest tick (ns), which the markers carry.
        self._stamp_ns = 0
        if transform_broadcaster is _DEFAULT_BROADCASTER:
            factory, unavailable = DEFAULT_BROADCASTER, TF_UNAVAILABLE
        else:
            factory, unavailable = transform_broadcaster, None
        self._state_publishers = StatePublishers(
            self, broadcaster_factory=factory, unavailable=unavailable,
            **self._publishing(self._config))
        # The publishers themselves, for tools that wrap their publish (bench/node_variant.py).
        self._pose_publisher = self._state_publishers.pose_publisher
        self._twist_publisher = self._state_publishers.twist_publisher
        self.create_subscription(PointStamped, TARGET_TOPIC, self._on_target, TARGET_QOS)
        self.create_subscription(PointStamped, GRAB_TOPIC, self._on_grab, TARGET_QOS)
        for name, callback in ((RESET_SERVICE, self._on_reset),
                               (RELEASE_SERVICE, self._on_release)):
            # Their calls set the target: published as service events (mouse_record follows).
            self.create_service(Trigger, name, callback).configure_introspection(
                self.get_clock(), SERVICE_EVENT_QOS, ServiceIntrospectionState.CONTENTS)
        self._timer = None
        self._start_timer()
        self._simulator_controls_setup()
        self._setup_monitors()
        self.create_timer(CLOCK_WATCH_PERIOD, self._watch_clock, clock=self._steady_clock)
        self.add_on_set_parameters_callback(self._on_set_parameters)
        self.get_logger().info(self._describe())
        if not self._state_publishers.tf_on:
            self.get_logger().info(f'TF {self._state_publishers.tf_status}')

    def _refuse(self, reason: str) -> NoReturn:
        """Destroy the half-built node and raise StartupRefusal with its logger's name."""
        logger_name = self.get_logger().name
        self.destroy_node()
        raise StartupRefusal(logger_name, reason) from None

    def _warn_about_unknown_parameters(self) -> None:
        """Warn once for each given parameter the node does not have, with the nearest name."""
        for line in unknown_parameter_warnings(self._parameter_overrides, self._parameters,
                                               [p.name for p in PARAMETERS]):
            self.get_logger().warning(line)

    @property
    def simulation(self) -> MouseSimulation:
        """Return the body's simulation, for tests and tools running in the same process."""
        return self._simulation

    def _describe(self) -> str:
        return describe(self._config)

    def _hold_initial_anchor(self) -> None:
        self._user_target = False
        self._simulation.target = (self._config.initial_anchor()
                                   if self._config.hold_initial_anchor else None)

    def _warn(self, reason: str, message: Callable[[], str]) -> None:
        """Log ``message()`` at most once per WARN_PERIOD for each ``reason`` (``throttle``)."""
        self._throttle(reason, message)

    def _on_target(self, message: PointStamped) -> None:
        point = point_from_message(message)
        refusal = self._gate.refusal(message.header.frame_id, point)
        if refusal is not None:
            self._warn(refusal.key, lambda: f'ignoring target {refusal.reason}')
            return
        now, arrival = self._now_ns(), self._simulation.time
        stamp = stamp_nanoseconds(message.header.stamp)
        if self.ticks_run and self._stamps.refusal(stamp, now_ns=now, tick_s=self._dt) is None:
            stamped, moved = self._core_clock.time_of(stamp, tick_stamp_ns=self._stamp_ns,
                                                      tick_core_time=arrival, tick_s=self._dt)
            if moved:
                # Ticks were dropped (or paused) since the last stamp: a new stream.
                self._simulation.target = point
            self._simulation.set_target(point, time=stamped, stamped=True)
        else:
            self._simulation.set_target(point, time=arrival)
        self._user_target = True
        self._last_target_ns = now

    def _on_grab(self, message: PointStamped) -> None:
        """Make a point on the body the anchor and the target; ignore (and say) any other."""
        point = point_from_message(message)
        refusal = self._gate.refusal(message.header.frame_id, point)
        if refusal is not None:
            self._warn('grab ' + refusal.key, lambda: f'ignoring grab {refusal.reason}')
            return
        landed = grab(self._simulation.state, self._config.box_size, point)
        margin = self._config.grab_margin
        if not landed.taken(margin):
            off, bound = apart(landed.distance, margin)
            self._warn('grab off body', lambda: (
                f'ignoring grab {point}: {off} m off the body, farther than '
                f'grab_margin {bound} m from its box'))
            return
        reason = self._set_anchor(landed.anchor)
        if reason is not None:
            self._warn('grab anchor', lambda: f'ignoring grab {point}: {reason}')
            return
        # Untimed: a grab starts a new stream of targets (nothing moves: the target is where
        # the anchor is).
        self._simulation.target = point
        self._user_target = True
        self._last_target_ns = self._now_ns()

    def _set_anchor(self, anchor: Vector3) -> Optional[str]:
        """
        Set the node's own ``anchor`` parameter, validated as any change; None or the reason.

        The parameter callback builds the configuration with it, so later changes of other
        parameters keep it; it does not count as the configured anchor.
        """
        self._setting_anchor = True
        try:
            [result] = self.set_parameters([Parameter('anchor', value=list(anchor))])
        finally:
            self._setting_anchor = False
        return None if result.successful else result.reason

    def _release_if_timed_out(self, now: int) -> None:
        timeout = self._config.target_timeout
        if self._user_target and timed_out(self._last_target_ns, now, timeout):
            self._simulation.target = None
            self._user_target = False
            self.get_logger().info(target_release_text(timeout))


def main(args: Optional[List[str]] = None) -> int:
    """Run the node until Ctrl-C, SIGTERM or SIGHUP; exit 0 then, 1 when it cannot start."""
    # rcl logs "Failed to parse global arguments" of its own before it raises; the FATAL line
    # below says it all, and with the reason.
    quiet = rclpy.logging.LoggingSeverity.FATAL
    previous = rclpy.logging.get_logger_level('rcl')
    rclpy.logging.set_logger_level('rcl', quiet)
    try:
        rclpy.init(args=args, signal_handler_options=SignalHandlerOptions.NO)
    except _rclpy.RCLError as error:
        name = requested_logger_name(sys.argv if args is None else args, NODE_NAME)
        rclpy.logging.get_logger(name).fatal(f'cannot start: {rcl_reason(error)}')
        return 1
    finally:
        if rclpy.logging.get_logger_level('rcl') == quiet:  # not set by --log-level
            rclpy.logging.set_logger_level('rcl', previous)
    node = None
    try:
        with StopRequest() as stop:
            node = MouseConstraintNode()
            executor = EventsExecutor(context=node.context)
            executor.add_node(node)
            # Until a signal or the context's shutdown: both end the node normally.
            spin_until(executor, stop)
    except StartupRefusal as error:
        rclpy.logging.get_logger(error.logger_name).fatal(f'invalid parameters: {error}')
        return 1
    finally:
        if node is not None:
            node.destroy_node()
        rclpy.try_shutdown()
    return 0


if __name__ == '__main__':
    sys.exit(main())
