"""
The ``mouse_constraint`` node: parameters, topics, services and timers, wired to pure parts.

It holds no physics and no policy of its own: a ``MouseSimulation`` does the stepping,
``TickGrid`` says which ticks are due on the node's clock and ``TickBudget`` which of them one
callback runs; with ``publish_clock`` ``SimulatedClock`` and ``ClockPacer`` pace them.
``PublishTicks`` says which ticks publish (``publish_rate_hz``), ``StatePublishers`` sends pose,
twist, TF and odometry (raw CDR), ``TargetGate`` and ``WrenchGate`` judge the input and
``input_timeouts`` when it expires, ``parameters`` validates the configuration, ``startup``
words the refusals, ``markers`` and ``diagnostics`` build the monitoring messages.

Start-up refuses what it cannot run with one FATAL line tagged with the node's real name and
exit 1 (``startup``); unknown keys in the parameters given to the node are warned about.
"""

import math
import sys
import time
from typing import Any, Callable, List, NoReturn, Optional

from diagnostic_msgs.msg import DiagnosticArray
from geometry_msgs.msg import PointStamped, WrenchStamped
from rcl_interfaces.msg import (FloatingPointRange, IntegerRange, ParameterDescriptor,
                                SetParametersResult)
import rclpy
from rclpy.clock import Clock, ClockType
from rclpy.exceptions import ParameterException
from rclpy.experimental import EventsExecutor
from rclpy.impl.implementation_singleton import rclpy_implementation as _rclpy
from rclpy.node import Node
from rclpy.parameter import Parameter
from rclpy.signals import SignalHandlerOptions
from rosgraph_msgs.msg import Clock as ClockMessage
from std_srvs.srv import SetBool, Trigger
from visualization_msgs.msg import MarkerArray

from .parameters import node_config, PARAMETERS, ParameterSpec
from .service_replies import (pause_reply, release_reply, reset_refusal, reset_reply, step_refusal,
                              step_reply)
# CLOCK_LOOP and StartupRefusal: importable from the node, where its refusals come from.
from .startup import (CLOCK_LOOP, clock_loop, describe, rcl_reason,  # noqa: F401
                      refusal_reason, requested_logger_name, StartupRefusal,
                      unknown_parameter_warnings)
from ..inputs.grab import grab
from ..inputs.input_timeouts import input_age, target_release_text, timed_out, wrench_removal_text
from ..inputs.target_gate import TargetGate
from ..inputs.target_stamps import TargetStamps
from ..inputs.throttle import Throttle
from ..inputs.wrench_gate import HeldWrench, NO_WRENCH, WrenchGate
from ..monitoring.diagnostics import (constraint_status, diagnostic_array, INITIAL_ANCHOR,
                                      NO_TARGET, Pacing, publishing_values, rate_status,
                                      simulator_status, Thresholds, TickCounters, TickWindow,
                                      USER_TARGET)
from ..monitoring.markers import marker_array, reference_force, wrench_reference
from ..physics import MouseSimulation
from ..physics.algebra import Vector3
from ..physics.simulation import force_bound
from ..physics.target_motion import STREAM_GAP
from ..timing.publish_ticks import PublishTicks, ticks_per_callback
from ..timing.sim_clock import ClockPacer, PacingMeter, SimulatedClock
from ..timing.spin import spin_until, StopRequest
from ..timing.tick_budget import TickBudget
from ..timing.tick_grid import (CATCH_UP_CAUSE, clock_change_text, clock_jump_text, core_time,
                                drop_text, MAX_CATCH_UP_SECONDS, scheduled_origin, TickGrid)
from ..wire.interface import (CLOCK_QOS, CLOCK_TOPIC, DIAGNOSTICS_TOPIC, GRAB_TOPIC, MARKERS_TOPIC,
                              MONITOR_DEPTH, NODE_NAME, PAUSE_SERVICE, RELEASE_SERVICE,
                              RESET_SERVICE, STEP_SERVICE, TARGET_QOS, TARGET_TOPIC, WRENCH_QOS,
                              WRENCH_TOPIC)
from ..wire.messages import point_from_message, set_stamp, stamp_nanoseconds
from ..wire.state_publishers import (BroadcasterFactory, DEFAULT_BROADCASTER, StatePublishers,
                                     TF_UNAVAILABLE)

# Throttle period of the warnings about bad input and missed rate (s).
WARN_PERIOD = 2.0
# Period (s, steady clock) of the check that a simulated clock has started.
CLOCK_WATCH_PERIOD = 1.0
# The node's transform_broadcaster when none is given: tf2_ros's, where importable.
_DEFAULT_BROADCASTER = object()


def _descriptor(parameter) -> ParameterDescriptor:
    descriptor = ParameterDescriptor(description=parameter.description)
    if parameter.bounds is not None:
        low, high = parameter.bounds
        if isinstance(parameter.default, int) and not isinstance(parameter.default, bool):
            descriptor.integer_range = [IntegerRange(from_value=low, to_value=high, step=0)]
        else:
            descriptor.floating_point_range = [
                FloatingPointRange(from_value=float(low), to_value=float(high), step=0.0)]
    return descriptor


class MouseConstraintNode(Node):
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
        self._stamps = TargetStamps(STREAM_GAP)
        # The anchor of the parameters (start or ros2 param set), which ~/reset restores.
        self._configured_anchor = self._config.settings.constraint.anchor
        # True while the node sets its own anchor parameter for a grab or a reset.
        self._setting_anchor = False
        self._throttle = Throttle(self.get_logger().warning, period=WARN_PERIOD)
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
        self.create_service(Trigger, RESET_SERVICE, self._on_reset)
        self.create_service(Trigger, RELEASE_SERVICE, self._on_release)
        self._timer = None
        self._start_timer()
        self._simulator_controls_setup()
        self._setup_monitors()
        self.create_timer(CLOCK_WATCH_PERIOD, self._watch_clock, clock=self._steady_clock)
        self.add_on_set_parameters_callback(self._on_set_parameters)
        self.get_logger().info(self._describe())
        if not self._state_publishers.tf_on:
            self.get_logger().info(f'TF {self._state_publishers.tf_status}')

    def _declare(self, parameter: ParameterSpec) -> None:
        try:
            self.declare_parameter(parameter.name, parameter.default, _descriptor(parameter))
        except ParameterException as error:
            given = self._parameter_overrides.get(parameter.name)
            raise ValueError(refusal_reason(parameter, error, None if given is None else (
                given.value, given.type_.name))) from None

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

    def _parameter_values(self, changes: List[Parameter] = ()) -> dict:
        values = {p.name: self.get_parameter(p.name).value for p in PARAMETERS}
        values.update((p.name, p.value) for p in changes)
        return values

    def _describe(self) -> str:
        return describe(self._config)

    @staticmethod
    def _publishing(config) -> dict:
        return {'frame_id': config.frame_id, 'body_frame_id': config.body_frame_id,
                'publish_tf': config.publish_tf, 'publish_odometry': config.publish_odometry}

    def _start_timer(self) -> None:
        if self._timer is not None:
            self.destroy_timer(self._timer)
        rate = self._config.rate_hz
        self._grid = TickGrid.for_rate(rate)
        self._publish_ticks = PublishTicks(rate, self._config.publish_rate_hz)
        self._dt = 1.0 / rate
        if self._config.publish_clock:
            self._timer = self._start_clock_timer()
        else:
            batch = ticks_per_callback(rate, self._config.publish_rate_hz)
            self._timer = self.create_timer(batch * self._dt, self._on_timer)

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
            self._simulation.set_target(point, time=core_time(
                stamp, tick_stamp_ns=self._stamp_ns, tick_core_time=arrival), stamped=True)
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
            self._warn('grab off body', lambda: (
                f'ignoring grab {point}: {landed.distance:.6g} m off the body, farther than '
                f'grab_margin {margin:g} m from its box'))
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

    def _on_timer(self) -> None:
        if self._paused:
            return
        clock = self.get_clock()
        now = clock.now().nanoseconds
        if clock.ros_time_is_active != self._grid_sim_time:
            # use_sim_time flipped: a new clock, not lost time. Restart the grid on it.
            self._grid_sim_time = clock.ros_time_is_active
            self._grid.restart(now)
            self.clock_restarts += 1
            self.get_logger().info(clock_change_text(self._grid_sim_time, now))
        elif not self._grid.started:
            self._grid.restart(scheduled_origin(now, self._timer.time_until_next_call(),
                                                self._timer.timer_period_ns))
        due = self._grid.due(now)
        if due.restarted:
            self.clock_restarts += 1
            self.get_logger().warning(clock_jump_text(now))
        first, count = due.first, due.count
        if due.dropped:
            self._drop(due.dropped, CATCH_UP_CAUSE)
        self._release_if_timed_out(now)
        if count:
            budget = self._budget
            ran = budget.run(self._tick, self._grid.stamp, first, count)
            if ran < count:
                self._drop(count - ran, budget.cause(self._config.settings.substeps))
            if ran > 1:
                self.late_ticks += ran - 1
            self.ticks_run += ran

    def _drop(self, count: int, cause: str) -> None:
        self.dropped_ticks += count
        self.drop_cause = cause
        self._warn('rate', lambda: drop_text(self._config.rate_hz, count, self.dropped_ticks,
                                             cause))

    def _tick(self, stamp: int, tick: Optional[int] = None) -> None:
        """
        Step once; publish /clock (if published) and, on a publishing tick, the state.

        :param stamp: the tick's time (ns): the stamp of /clock and of the state.
        :param tick: the tick's number on its grid, for ``PublishTicks``; None publishes (a
            single step asked for by ``~/step``).
        """
        if self._held_wrench.applied is not None and self._held_wrench.expired(
                stamp, self._config.wrench_timeout):
            self._simulation.wrench = NO_WRENCH
            self.get_logger().info(wrench_removal_text(self._config.wrench_timeout))
        state = self._simulation.step(self._dt)
        if self._clock_publisher is not None:
            set_stamp(self._clock_message.clock, stamp)
            self._clock_publisher.publish(self._clock_message)
        self._stamp_ns = stamp
        publish_ticks = self._publish_ticks
        if tick is None or publish_ticks.every_tick or publish_ticks.due(tick):
            self._state_publishers.publish(stamp, state)

    def waiting_for_clock(self) -> Optional[str]:
        """
        Return ``'/clock on <topic>'`` while use_sim_time is on and no clock message came.

        The node's clock reads zero until then and no timer on it fires: no tick, no pose.
        """
        clock = self.get_clock()
        if self._clock_publisher is None and clock.ros_time_is_active and \
                clock.now().nanoseconds == 0:
            return f'/clock on {self.resolve_topic_name("/clock")}'
        return None

    def _watch_clock(self) -> None:
        waiting = self.waiting_for_clock()
        if waiting is not None:
            self._warn('clock', lambda: (
                f'waiting for {waiting}: use_sim_time is true and no clock message has come; '
                'no tick runs until one does'))

    def _release_if_timed_out(self, now: int) -> None:
        timeout = self._config.target_timeout
        if self._user_target and timed_out(self._last_target_ns, now, timeout):
            self._simulation.target = None
            self._user_target = False
            self.get_logger().info(target_release_text(timeout))

    def _on_reset(self, _request: Trigger.Request, response: Trigger.Response):
        configured = self._configured_anchor
        if self._config.settings.constraint.anchor != configured:
            reason = self._set_anchor(configured)
            if reason is not None:
                response.success = False
                response.message = reset_refusal(configured, reason)
                return response
        self._simulation.reset()
        self._hold_initial_anchor()
        self._held_wrench.clear()
        self._simulation.wrench = NO_WRENCH
        response.success = True
        response.message = reset_reply(self._config.hold_initial_anchor)
        return response

    def _on_release(self, _request: Trigger.Request, response: Trigger.Response):
        had_target = self._simulation.target is not None
        self._simulation.target = None
        self._user_target = False
        response.success = True
        response.message = release_reply(had_target)
        return response

    def _on_set_parameters(self, changes: List[Parameter]) -> SetParametersResult:
        try:
            config = node_config(self._parameter_values(changes))
        except ValueError as error:
            return SetParametersResult(successful=False, reason=str(error))
        use_sim_time = next((p.value for p in changes if p.name == 'use_sim_time'),
                            self.get_parameter('use_sim_time').value)
        loop = clock_loop(config.publish_clock, use_sim_time)
        if loop is not None:
            return SetParametersResult(successful=False, reason=loop)
        previous, self._config = self._config, config
        if not self._setting_anchor and any(p.name == 'anchor' for p in changes):
            self._configured_anchor = config.settings.constraint.anchor
        self._simulation.settings = config.settings
        self._simulation.initial_state = config.initial_state
        if (config.frame_id, config.workspace_radius) != (
                previous.frame_id, previous.workspace_radius):
            self._gate = TargetGate(config.frame_id, config.workspace_radius)
        if self._publishing(config) != self._publishing(previous):
            tf_status = self._state_publishers.tf_status
            self._state_publishers.configure(**self._publishing(config))
            if self._state_publishers.tf_status != tf_status:
                self.get_logger().info(f'TF {self._state_publishers.tf_status}')
        if (config.rate_hz, config.publish_clock) != (previous.rate_hz, previous.publish_clock):
            self._switch_clock(previous)
        elif config.real_time_factor != previous.real_time_factor:
            self._sim_clock.set_real_time_factor(config.real_time_factor)
            self._retime_clock_timer()
        if config.rate_hz == previous.rate_hz and \
                config.publish_rate_hz != previous.publish_rate_hz:
            self._publish_ticks = PublishTicks(config.rate_hz, config.publish_rate_hz)
            if not config.publish_clock:
                # The same grid on a timer of the new batch: no restart, no tick lost.
                self.destroy_timer(self._timer)
                batch = ticks_per_callback(config.rate_hz, config.publish_rate_hz)
                self._timer = self.create_timer(batch * self._dt, self._on_timer)
        if (config.marker_rate_hz, config.diagnostics_rate_hz) != (
                previous.marker_rate_hz, previous.diagnostics_rate_hz):
            self._start_monitor_timers()
        self.get_logger().info('parameters changed: ' + self._describe())
        return SetParametersResult(successful=True)

    # Simulator controls: the node as the clock, pause and step, the external wrench. The pacing
    # is SimulatedClock's, the wrench policy WrenchGate's and HeldWrench's; here is the wiring.

    def _simulator_controls_init(self) -> None:
        """Create the state the tick timers read: pause, wrench, simulated clock."""
        self._paused = False
        self._held_wrench = HeldWrench()
        # Created once: turning publish_clock off and on goes on from the simulated time reached.
        self._sim_clock = SimulatedClock(self._config.rate_hz, self._config.real_time_factor,
                                         max_lag=MAX_CATCH_UP_SECONDS)
        self._clock_message = ClockMessage()
        self._clock_publisher = None
        if self._config.publish_clock:
            self._clock_publisher = self.create_publisher(ClockMessage, CLOCK_TOPIC, CLOCK_QOS)
        # What the pacing achieved between two diagnostics calls.
        self._pacing = PacingMeter()

    def _simulator_controls_setup(self) -> None:
        self.create_subscription(WrenchStamped, WRENCH_TOPIC, self._on_wrench, WRENCH_QOS)
        self.create_service(SetBool, PAUSE_SERVICE, self._on_pause)
        self.create_service(Trigger, STEP_SERVICE, self._on_step)

    def _now_ns(self) -> int:
        """Return the node's time: the simulated clock with publish_clock, else its clock."""
        if self._clock_publisher is not None:
            return self._sim_clock.now_ns
        return self.get_clock().now().nanoseconds

    def _start_clock_timer(self):
        """Return the tick timer of publish_clock, on the steady clock (``ClockPacer``)."""
        self._pacer = ClockPacer(self._config.rate_hz, self._config.real_time_factor)
        return self.create_timer(self._pacer.period, self._on_clock_timer,
                                 clock=self._steady_clock)

    def _on_clock_timer(self) -> None:
        pacer = self._pacer
        started = pacer.start()
        if started is None:
            # Clears the events queued while one tick outlasted the period (many substeps).
            return
        clock = self._sim_clock
        due = clock.due(time.monotonic_ns())
        if due == 0:
            return
        self._release_if_timed_out(clock.now_ns)
        self.ticks_run += pacer.run(clock, self._tick, due, started)

    def _switch_clock(self, previous) -> None:
        """Start the tick timer again for a new rate or clock source, re-basing input ages."""
        config = self._config
        if config.publish_clock and self._clock_publisher is None:
            self._clock_publisher = self.create_publisher(ClockMessage, CLOCK_TOPIC, CLOCK_QOS)
        elif not config.publish_clock and self._clock_publisher is not None:
            self.destroy_publisher(self._clock_publisher)
            self._clock_publisher = None
        self._sim_clock.set_rate(config.rate_hz)
        self._sim_clock.set_real_time_factor(config.real_time_factor)
        self._start_timer()
        if config.publish_clock != previous.publish_clock:
            # Another time base: the ages of target and wrench start again in it.
            now = self._now_ns()
            if self._user_target:
                self._last_target_ns = now
            applied = self._held_wrench.applied
            if applied is not None:
                self._held_wrench.applied = applied._replace(since_ns=now)

    def _retime_clock_timer(self) -> None:
        if self._clock_publisher is not None:
            self.destroy_timer(self._timer)
            self._timer = self._start_clock_timer()

    def _on_pause(self, request: SetBool.Request, response: SetBool.Response):
        """
        Pause (true) or resume (false) the physics.

        Resuming catches nothing up: the simulated clock paces on from where it stood, the
        node-clock grid starts again at the next timer call.
        """
        pause = bool(request.data)
        response.success = True
        response.message = pause_reply(pause, self._paused, self._now_ns())
        if pause == self._paused:
            return response
        self._paused = pause
        if pause:
            self._sim_clock.pause()
            return response
        self._sim_clock.resume()
        self._grid = TickGrid.for_rate(self._config.rate_hz)
        self._tick_window = TickWindow()
        return response

    def _on_step(self, _request: Trigger.Request, response: Trigger.Response):
        """While paused: run exactly one tick and publish it; refused while running."""
        refusal = step_refusal(self._paused, self.waiting_for_clock())
        if refusal is not None:
            response.success = False
            response.message = refusal
            return response
        if self._clock_publisher is not None:
            stamp = self._sim_clock.advance()
        else:
            stamp = self.get_clock().now().nanoseconds
        self._release_if_timed_out(stamp)
        self._tick(stamp)
        self.ticks_run += 1
        response.success = True
        response.message = step_reply(self._dt, stamp)
        return response

    def _on_wrench(self, message: WrenchStamped) -> None:
        f, t = message.wrench.force, message.wrench.torque
        force, torque = (f.x, f.y, f.z), (t.x, t.y, t.z)
        config = self._config
        refusal = WrenchGate(config.frame_id, config.max_wrench_force,
                             config.max_wrench_torque).refusal(
                                 message.header.frame_id, force, torque)
        if refusal is not None:
            self._warn(refusal.key, lambda: f'ignoring wrench {refusal.reason}')
            return
        if force == torque == (0.0, 0.0, 0.0):
            self._held_wrench.clear()  # a zero wrench ends a push: nothing left to time out
        else:
            self._held_wrench.take(force, torque, self._now_ns())
        self._simulation.wrench = self._held_wrench.wrench

    def _simulator_status(self, name: str, hardware_id: str, now: int):
        config = self._config
        achieved, slipped = self._pacing.sample(time.monotonic_ns(), self._sim_clock)
        publishing = self._clock_publisher is not None
        applied = self._held_wrench.applied
        force, torque = self._simulation.wrench
        age = None if applied is None else input_age(applied.since_ns, now)
        pacing = Pacing(publishing, self._paused, config.real_time_factor,
                        achieved if publishing else None, slipped, now * 1e-9)
        return simulator_status(name, hardware_id, pacing=pacing, force=force, torque=torque,
                                wrench_age=age, wrench_timeout=config.wrench_timeout)

    # Markers and diagnostics: their own lower-rate timers, nothing on the per-tick path. The
    # messages are built by the markers and diagnostics modules from the simulation's data.

    def _setup_monitors(self) -> None:
        self._marker_publisher = self.create_publisher(MarkerArray, MARKERS_TOPIC, MONITOR_DEPTH)
        self._diagnostics_publisher = self.create_publisher(
            DiagnosticArray, DIAGNOSTICS_TOPIC, MONITOR_DEPTH)
        # The first window opens at the first diagnostics call, once the node spins.
        self._tick_window = TickWindow()
        self._window_sim_time = (self.get_clock().ros_time_is_active,
                                 self._clock_publisher is not None)
        self._monitor_timers = []
        self._start_monitor_timers()

    def _start_monitor_timers(self) -> None:
        """
        (Re)create the marker and diagnostics timers at their rates; 0 Hz means none.

        Markers show the latest tick and follow the node's clock. Diagnostics run on the steady
        clock: they must still come when a simulated clock has not started or stands still,
        which is when they have something to say.
        """
        for timer in self._monitor_timers:
            self.destroy_timer(timer)
        self._monitor_timers = [
            self.create_timer(1.0 / rate, callback, clock=clock)
            for rate, callback, clock in (
                (self._config.marker_rate_hz, self._publish_markers, None),
                (self._config.diagnostics_rate_hz, self._publish_diagnostics,
                 self._steady_clock))
            if rate > 0.0]

    def _tick_counters(self) -> TickCounters:
        return TickCounters(self.ticks_run, self.late_ticks, self.dropped_ticks,
                            self.clock_restarts)

    def _publish_markers(self) -> None:
        """Publish the markers of the latest tick, with its stamp."""
        simulation = self._simulation
        self._marker_publisher.publish(marker_array(
            frame_id=self._config.frame_id, stamp_ns=self._stamp_ns,
            box_size=self._config.box_size, state=simulation.state,
            anchor=simulation.anchor_position(), target=simulation.target,
            force=simulation.constraint_force, reference=reference_force(simulation.settings),
            wrench_force=simulation.wrench[0],
            wrench_reference=wrench_reference(simulation.settings)))

    def _publish_diagnostics(self) -> None:
        """
        Publish the rate status over the window since the last call and the constraint's.

        Stamped with the node's clock, which reads zero while a simulated clock has not started.
        The status names start with the fully qualified node name, unique in a ROS graph, as
        diagnostic_aggregator needs.
        """
        clock = self.get_clock()
        now = self._now_ns()
        config, simulation = self._config, self._simulation
        counters = self._tick_counters()
        source = (clock.ros_time_is_active, self._clock_publisher is not None)
        if source != self._window_sim_time:
            # Another clock: a window across the change would measure nothing real.
            self._window_sim_time = source
            self._tick_window = TickWindow()
        # Paused, the ticks stop on purpose: no rate to judge (the window restarts on resume).
        window = (None if self._paused else
                  self._tick_window.sample(now, counters, config.rate_hz))
        thresholds = Thresholds(anchor_warn=config.diagnostics_anchor_warn,
                                anchor_error=config.diagnostics_anchor_error)
        error = simulation.anchor_error()
        if self._user_target:
            kind, age = USER_TARGET, input_age(self._last_target_ns, now)
        else:
            kind, age = (NO_TARGET if simulation.target is None else INITIAL_ANCHOR), None
        name = hardware_id = self.get_fully_qualified_name()
        rate = rate_status(f'{name}: rate', hardware_id, rate_hz=config.rate_hz, window=window,
                           totals=counters, thresholds=thresholds, drop_cause=self.drop_cause,
                           waiting_for=self.waiting_for_clock())
        publishers = self._state_publishers
        rate.values.extend(publishing_values(
            config.publish_rate_hz, publishers.tf_status,
            None if publishers.odometry_publisher is None
            else publishers.odometry_publisher.topic_name))
        self._diagnostics_publisher.publish(diagnostic_array(now, [
            rate,
            constraint_status(f'{name}: constraint', hardware_id, target_kind=kind,
                              target=simulation.target,
                              anchor_error=None if error is None else math.hypot(*error),
                              force=simulation.constraint_force,
                              force_bound=force_bound(config.settings),
                              target_age=age, target_timeout=config.target_timeout,
                              thresholds=thresholds),
            self._simulator_status(f'{name}: simulator', hardware_id, now),
        ]))


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
