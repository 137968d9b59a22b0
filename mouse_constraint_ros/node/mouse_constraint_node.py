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
The ``mouse_constraint`` node: parameters, topics, services and timers, wired to its parts.

It holds no physics, no policy and no loop of its own. A ``MouseSimulation`` does the
stepping; ``Tick`` is one tick (inputs applied, physics stepped, outputs sent), which three
drivers run: ``NodeClockTicks`` on the node's own clock, ``ClockTicks`` on the simulated clock
with ``publish_clock``, and a caller that steps the node itself (``stepped``, ``step``).
``TargetInput`` and ``WrenchInput`` take the input, ``SimulatorControls`` answers pause, step,
reset and release, ``Monitors`` publishes markers and /diagnostics, ``parameters`` validates the
configuration and ``parameter_changes`` declares it; ``startup`` words the refusals.

Start-up refuses what it cannot run with one FATAL line tagged with the node's real name and
exit 1 (``startup``); unknown keys in the parameters given to the node are warned about.
"""

import sys
from typing import Any, List, NoReturn, Optional, Tuple

from geometry_msgs.msg import PointStamped, PoseStamped, WrenchStamped
from rcl_interfaces.msg import SetParametersResult
import rclpy
from rclpy.clock import Clock, ClockType
from rclpy.experimental import EventsExecutor
from rclpy.impl.implementation_singleton import rclpy_implementation as _rclpy
from rclpy.node import Node
from rclpy.parameter import Parameter
from rclpy.service_introspection import ServiceIntrospectionState
from rclpy.signals import SignalHandlerOptions
from std_srvs.srv import SetBool, Trigger

from .clock_ticks import ClockTicks
from .monitors import Monitors
from .parameter_changes import changed, declare, publishing
from .parameters import node_config, NodeConfig, PARAMETERS
from .simulator_controls import SimulatorControls
# CLOCK_LOOP and StartupRefusal: importable from the node, where its refusals come from.
from .startup import (CLOCK_LOOP, clock_loop, describe, rcl_reason,  # noqa: F401
                      requested_logger_name, StartupRefusal, unknown_parameter_warnings)
from .target_input import TargetInput
from .tick import Tick
from .tick_loop import NodeClockTicks
from .tick_record import TickRecord
from .usage import asks_for_help, usage_text
from .wrench_input import WrenchInput
from ..inputs.target_gate import Refusal
from ..inputs.throttle import RefusalLog, Throttle
from ..physics import MouseSimulation
from ..physics.algebra import Vector3
from ..physics.validation import shown
from ..timing.guarded_time_source import guard_time_source
from ..timing.spin import spin_until, StopRequest
from ..wire.interface import (GRAB_TOPIC, NODE_NAME, PAUSE_SERVICE, RELEASE_SERVICE,
                              RESET_SERVICE, SERVICE_EVENT_QOS, STEP_SERVICE, TARGET_POSE_TOPIC,
                              TARGET_QOS, TARGET_TOPIC, WRENCH_QOS, WRENCH_TOPIC)
from ..wire.state_publishers import (BroadcasterFactory, DEFAULT_BROADCASTER, StatePublishers,
                                     TF_UNAVAILABLE)

# Throttle period of the warnings about bad input and missed rate (s).
WARN_PERIOD = 2.0
# Period (s, steady clock) of the check that a simulated clock has started.
CLOCK_WATCH_PERIOD = 1.0
# The node's transform_broadcaster when none is given: tf2_ros's, where importable.
_DEFAULT_BROADCASTER = object()
# Why a node stepped by its caller must be the clock.
STEPPED_NEEDS_CLOCK = ('publish_clock: a node stepped by its caller is the clock: it needs '
                       'publish_clock true')


class MouseConstraintNode(Node):
    """
    Serves one rigid body dragged by the mouse constraint.

    Subscribes ``target`` (PointStamped), publishes ``pose`` (PoseStamped) and ``twist``
    (TwistStamped) at the publish rate (every tick by default), TF and ``odom`` (Odometry) when
    on, offers ``~/reset`` and ``~/release`` (Trigger), ``~/pause`` (SetBool) and ``~/step``.

    A point on ``grab`` (PointStamped) that lies on the body's box (``grab`` module) becomes the
    anchor and the target: the node sets its own ``anchor`` parameter to it, so that the
    configuration, ``ros2 param get`` and the markers all show the grabbed point. Targets then
    drag that point, ``~/release`` lets go of it, ``~/reset`` restores the configured anchor:
    the one the node started with or was last given through its parameters.
    """

    def __init__(self, *, transform_broadcaster: Optional[BroadcasterFactory] = (
            _DEFAULT_BROADCASTER), stepped: bool = False, **kwargs: Any) -> None:
        """
        Declare parameters, build the parts and start ticking.

        :param transform_broadcaster: makes the TF broadcaster from the node (anything with
            ``sendTransform(TransformStamped)`` that sends before it returns); by default
            ``tf2_ros.TransformBroadcaster``, or none when tf2_ros is not importable; None: no
            TF.
        :param stepped: no timer runs the ticks: each ``step`` call runs one tick of the
            simulated clock, which the node publishes on /clock (``publish_clock`` must be
            true). ``mouse_constraint_ros.testing`` steps the node so.
        :param kwargs: passed to ``rclpy.node.Node``.
        :raises StartupRefusal: (a ValueError) a parameter or the configuration is invalid; the
            node is destroyed then.
        """
        super().__init__(NODE_NAME, **kwargs)
        self._throttle = Throttle(self.get_logger().warning, period=WARN_PERIOD)
        # Through a function of its own: rclpy keys a log call's severity by its caller, and the
        # warnings are logged from the same line of Throttle.
        self._notes = Throttle(lambda text: self.get_logger().info(text), period=WARN_PERIOD)
        guard_time_source(self, lambda text: self._throttle('clock ignored', lambda: text))
        try:
            declare(self, PARAMETERS)
            config = node_config(self._parameter_values())
        except ValueError as error:
            self._refuse(str(error))
        self._warn_about_unknown_parameters()
        loop = clock_loop(config.publish_clock, self.get_parameter('use_sim_time').value)
        if loop is not None:
            self._refuse(loop)
        if stepped and not config.publish_clock:
            self._refuse(STEPPED_NEEDS_CLOCK)
        self._config = config
        self._stepped = stepped
        # The anchor of the parameters (start or ros2 param set), which ~/reset restores.
        self._configured_anchor = config.settings.constraint.anchor
        # True while the node sets its own anchor parameter for a grab or a reset.
        self._setting_anchor = False
        self._build(config, transform_broadcaster)
        self._wire()
        self.add_on_set_parameters_callback(self._on_set_parameters)
        self.get_logger().info(describe(config))
        if not self._state_publishers.tf_on:
            self.get_logger().info(f'TF {self._state_publishers.tf_status}')

    def _build(self, config: NodeConfig, transform_broadcaster) -> None:
        """Make the parts, each given what it reads and writes."""
        simulation = self._simulation = MouseSimulation(config.settings, config.initial_state)
        record = self._record = TickRecord()
        # Timers that must run while a simulated clock stands still or has not started.
        steady_clock = Clock(clock_type=ClockType.STEADY_TIME)
        if transform_broadcaster is _DEFAULT_BROADCASTER:
            factory, unavailable = DEFAULT_BROADCASTER, TF_UNAVAILABLE
        else:
            factory, unavailable = transform_broadcaster, None
        self._state_publishers = StatePublishers(
            self, broadcaster_factory=factory, unavailable=unavailable, simulation=simulation,
            **publishing(config))
        refusals = self._refusals = RefusalLog(self._throttle)
        log = self.get_logger().info
        self._target = TargetInput(simulation=simulation, config=config, record=record,
                                   now_ns=self._now_ns, set_anchor=self._set_anchor,
                                   refuse=refusals, log=log)
        self._wrench = WrenchInput(simulation=simulation, config=config, now_ns=self._now_ns,
                                   refuse=refusals, log=log)
        tick = self._tick = Tick(simulation=simulation, target=self._target, wrench=self._wrench,
                                 state_publishers=self._state_publishers, record=record)
        tick.configure(rate_hz=config.rate_hz, publish_rate_hz=config.publish_rate_hz)
        self._node_clock_ticks = NodeClockTicks(
            self, tick, record, paused=lambda: self._controls.paused,
            substeps=lambda: self._config.settings.substeps, warn=self._throttle)
        self._clock_ticks = ClockTicks(self, tick, steady_clock=steady_clock,
                                       rate_hz=config.rate_hz,
                                       real_time_factor=config.real_time_factor,
                                       stepped=self._stepped)
        self._controls = SimulatorControls(
            simulation=simulation, tick=tick, record=record,
            node_clock_ticks=self._node_clock_ticks, clock_ticks=self._clock_ticks,
            target=self._target, wrench=self._wrench, now_ns=self._now_ns,
            restore_anchor=self._restore_anchor,
            hold_initial_anchor=lambda: self._config.hold_initial_anchor)
        self._start_ticks(config)
        self._monitors = Monitors(
            node=self, config=config, steady_clock=steady_clock, now_ns=self._now_ns,
            simulation=simulation, record=record, target=self._target, wrench=self._wrench,
            controls=self._controls, node_clock_ticks=self._node_clock_ticks,
            clock_ticks=self._clock_ticks, state_publishers=self._state_publishers)
        self.create_timer(CLOCK_WATCH_PERIOD, self._watch_clock, clock=steady_clock)

    def _wire(self) -> None:
        """Create the subscriptions and services, each calling its part."""
        self.create_subscription(PointStamped, TARGET_TOPIC, self._target.on_target, TARGET_QOS)
        self.create_subscription(PoseStamped, TARGET_POSE_TOPIC, self._target.on_target_pose,
                                 TARGET_QOS)
        self.create_subscription(PointStamped, GRAB_TOPIC, self._target.on_grab, TARGET_QOS)
        self.create_subscription(WrenchStamped, WRENCH_TOPIC, self._wrench.on_wrench,
                                 WRENCH_QOS)
        controls = self._controls
        for name, callback in ((RESET_SERVICE, controls.on_reset),
                               (RELEASE_SERVICE, controls.on_release)):
            # Their calls set the target: published as service events (mouse_record follows).
            self.create_service(Trigger, name, callback).configure_introspection(
                self.get_clock(), SERVICE_EVENT_QOS, ServiceIntrospectionState.CONTENTS)
        self.create_service(SetBool, PAUSE_SERVICE, controls.on_pause)
        self.create_service(Trigger, STEP_SERVICE, controls.on_step)

    def _start_ticks(self, config: NodeConfig) -> None:
        """Run the ticks on the simulated clock (publish_clock) or on the node's clock."""
        if config.publish_clock:
            self._node_clock_ticks.stop()
            self._clock_ticks.start()
        else:
            self._clock_ticks.stop()
            self._node_clock_ticks.start(config.rate_hz, config.publish_rate_hz)

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

    def _parameter_values(self, changes: List[Parameter] = ()) -> dict:
        values = {p.name: self.get_parameter(p.name).value for p in PARAMETERS}
        values.update((p.name, p.value) for p in changes)
        return values

    @property
    def simulation(self) -> MouseSimulation:
        """Return the body's simulation, for tests and tools running in the same process."""
        return self._simulation

    @property
    def ticks_run(self) -> int:
        """Return how many ticks ran since start."""
        return self._record.ticks_run

    @property
    def late_ticks(self) -> int:
        """Return how many ticks ran late (in a catch-up) since start."""
        return self._record.late_ticks

    @property
    def dropped_ticks(self) -> int:
        """Return how many ticks were dropped since start."""
        return self._record.dropped_ticks

    @property
    def clock_restarts(self) -> int:
        """Return how many times the tick grid restarted on a new or jumping clock."""
        return self._record.clock_restarts

    @property
    def time_ns(self) -> int:
        """Return the node's time (ns): the simulated clock's with publish_clock, else its own."""
        return self._now_ns()

    @property
    def paused(self) -> bool:
        """Return whether the physics is paused by ``~/pause``."""
        return self._controls.paused

    @property
    def refusals(self) -> Tuple[int, Optional[Refusal]]:
        """Return how many targets, grabs and wrenches were refused, and the last refusal."""
        return self._refusals.count, self._refusals.last

    @property
    def tick_timer(self):
        """Return the timer that runs the ticks now, or None for a node stepped by its caller."""
        if self._clock_ticks.on:
            return self._clock_ticks.timer
        return self._node_clock_ticks.timer

    def step(self) -> bool:
        """
        Run one tick of the simulated clock now, unless paused; return whether it ran.

        Only a node made with ``stepped=True``: nothing else runs its ticks.

        :raises RuntimeError: the node runs its own ticks.
        """
        if not self._stepped:
            raise RuntimeError('step() runs the ticks of a node made with stepped=True; this '
                               'one runs them on a timer of its own')
        if self._controls.paused:
            return False
        self._clock_ticks.step()
        return True

    def _now_ns(self) -> int:
        """Return the node's time: the simulated clock with publish_clock, else its clock."""
        clock_ticks = self._clock_ticks
        if clock_ticks.on:
            return clock_ticks.now_ns
        return self.get_clock().now().nanoseconds

    def waiting_for_clock(self) -> Optional[str]:
        """
        Return ``'/clock on <topic>'`` while use_sim_time is on and no clock message came.

        The node's clock reads zero until then and no timer on it fires: no tick, no pose.
        """
        if self._clock_ticks.on:
            return None
        return self._node_clock_ticks.waiting_for_clock()

    def _watch_clock(self) -> None:
        waiting = self.waiting_for_clock()
        if waiting is not None:
            self._throttle('clock', lambda: (
                f'waiting for {waiting}: use_sim_time is true and no clock message has come; '
                'no tick runs until one does'))

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

    def _restore_anchor(self) -> Optional[Tuple[Vector3, str]]:
        """Set the configured anchor again; None, or (that anchor, why it could not be)."""
        configured = self._configured_anchor
        if self._config.settings.constraint.anchor == configured:
            return None
        reason = self._set_anchor(configured)
        return None if reason is None else (configured, reason)

    def _on_set_parameters(self, changes: List[Parameter]) -> SetParametersResult:
        """Apply a set of changes whole to every part it concerns, or refuse it whole."""
        try:
            config = node_config(self._parameter_values(changes))
        except ValueError as error:
            return SetParametersResult(successful=False, reason=str(error))
        use_sim_time = next((p.value for p in changes if p.name == 'use_sim_time'),
                            self.get_parameter('use_sim_time').value)
        refusal = clock_loop(config.publish_clock, use_sim_time)
        if refusal is None and self._stepped and not config.publish_clock:
            refusal = STEPPED_NEEDS_CLOCK
        if refusal is not None:
            return SetParametersResult(successful=False, reason=refusal)
        previous, self._config = self._config, config
        if not self._setting_anchor and any(p.name == 'anchor' for p in changes):
            self._configured_anchor = config.settings.constraint.anchor
        self._simulation.configure(config.settings, config.initial_state)
        self._target.configure(config)
        self._wrench.configure(config)
        self._apply_timing(previous, config)
        self._monitors.configure(config)
        if self._setting_anchor:
            # A grab or a reset: one short line, at most every WARN_PERIOD (grabs can flood).
            anchor = config.settings.constraint.anchor
            self._notes('anchor', lambda: f'anchor {shown(anchor)} m (body frame), set by the '
                                          'node')
        else:
            self.get_logger().info('parameters changed: ' + describe(config))
        return SetParametersResult(successful=True)

    def _apply_timing(self, previous: NodeConfig, config: NodeConfig) -> None:
        """Apply what changed of the publishers, the rates and the clock."""
        what = changed(previous, config)
        if what.publishing:
            publishers = self._state_publishers
            tf_status = publishers.tf_status
            publishers.configure(**publishing(config))
            if publishers.tf_status != tf_status:
                self.get_logger().info(f'TF {publishers.tf_status}')
        self._tick.configure(rate_hz=config.rate_hz, publish_rate_hz=config.publish_rate_hz)
        clock_ticks = self._clock_ticks
        if what.clock:
            clock_ticks.sim_clock.set_rate(config.rate_hz)
            clock_ticks.sim_clock.set_real_time_factor(config.real_time_factor)
            self._start_ticks(config)
            if config.publish_clock != previous.publish_clock:
                # Another time base: the ages of target and wrench start again in it.
                now = self._now_ns()
                self._target.restart_age(now)
                self._wrench.restart_age(now)
        elif what.real_time_factor:
            clock_ticks.set_real_time_factor(config.real_time_factor)
        elif what.publish_rate and not config.publish_clock:
            # The same grid on a timer of the new batch: no restart, no tick lost.
            self._node_clock_ticks.retime(config.publish_rate_hz)


def main(args: Optional[List[str]] = None) -> int:
    """Run the node until Ctrl-C, SIGTERM or SIGHUP; exit 0 then, 1 when it cannot start."""
    if asks_for_help(sys.argv if args is None else args):
        print(usage_text())
        return 0
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
