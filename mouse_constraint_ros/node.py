"""
The ``mouse_constraint`` node: parameters, topics, services and the fixed-rate timer.

It holds no physics: a ``MouseSimulation`` does the stepping, ``TickGrid`` says which ticks are
due, ``configuration`` validates parameters and ``conversions`` fills the messages.
"""

import math
import sys
import time
from typing import Any, Callable, Dict, List, Optional, Tuple

from diagnostic_msgs.msg import DiagnosticArray
from geometry_msgs.msg import PointStamped, PoseStamped, TwistStamped
from rcl_interfaces.msg import (FloatingPointRange, IntegerRange, ParameterDescriptor,
                                SetParametersResult)
import rclpy
from rclpy.executors import ExternalShutdownException
from rclpy.experimental import EventsExecutor
from rclpy.node import Node
from rclpy.parameter import Parameter
from rclpy.qos import HistoryPolicy, QoSProfile, ReliabilityPolicy
from rclpy.signals import SignalHandlerOptions
from std_srvs.srv import Trigger
from visualization_msgs.msg import MarkerArray

from .configuration import configuration_from, PARAMETERS
from .conversions import (fill_pose, fill_twist, point_from_message, set_stamp,
                          stamp_nanoseconds)
from .diagnostics import (constraint_status, diagnostic_array, INITIAL_ANCHOR, NO_TARGET,
                          rate_status, Thresholds, TickCounters, TickWindow, USER_TARGET)
from .markers import marker_array, reference_force
from .physics import MouseSimulation
from .signals import StopRequest
from .tick_grid import TickGrid

NODE_NAME = 'mouse_constraint'
# Catch up on at most this much missed time in one timer callback; older ticks are dropped.
MAX_CATCH_UP_SECONDS = 0.1
# Throttle period of the warnings about bad input and missed rate (s).
WARN_PERIOD = 2.0

# The target subscription: RELIABLE so that `ros2 topic pub`, RViz's Publish Point tool and
# `mouse_target` (all RELIABLE) connect and a one-shot target is acknowledged; depth 1 because
# only the newest target matters. Pose and twist are RELIABLE, which any subscriber, RELIABLE or
# BEST_EFFORT, can match, with depth 100 so that a catch-up burst (up to 0.1 s of ticks at
# 1 kHz) is not overwritten in the writer's history before a reliable reader has it.
TARGET_QOS = QoSProfile(history=HistoryPolicy.KEEP_LAST, depth=1,
                        reliability=ReliabilityPolicy.RELIABLE)
STATE_QOS = QoSProfile(history=HistoryPolicy.KEEP_LAST, depth=100,
                       reliability=ReliabilityPolicy.RELIABLE)


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
    (TwistStamped) every tick, offers ``~/reset`` and ``~/release`` (Trigger).
    """

    def __init__(self, **kwargs: Any) -> None:
        """Declare parameters and build the simulation; raise ValueError if they are invalid."""
        super().__init__(NODE_NAME, **kwargs)
        for parameter in PARAMETERS:
            self.declare_parameter(parameter.name, parameter.default, _descriptor(parameter))
        self._config = configuration_from(self._parameter_values())
        self._simulation = MouseSimulation(self._config.settings, self._config.initial_state)
        self._user_target = False
        self._last_target_ns: Optional[int] = None
        # Per warning reason: when it was last logged (monotonic s) and how many were not since.
        self._warnings: Dict[str, Tuple[float, int]] = {}
        self._hold_initial_anchor()
        self.ticks_run = 0
        self.late_ticks = 0
        self.dropped_ticks = 0
        self.clock_restarts = 0

        self._pose = PoseStamped()
        self._twist = TwistStamped()
        self._set_frame(self._config.frame_id)
        self._pose_publisher = self.create_publisher(PoseStamped, 'pose', STATE_QOS)
        self._twist_publisher = self.create_publisher(TwistStamped, 'twist', STATE_QOS)
        self.create_subscription(PointStamped, 'target', self._on_target, TARGET_QOS)
        self.create_service(Trigger, '~/reset', self._on_reset)
        self.create_service(Trigger, '~/release', self._on_release)
        self._timer = None
        self._start_timer()
        self._setup_monitors()
        self.add_on_set_parameters_callback(self._on_set_parameters)
        self.get_logger().info(self._describe())

    @property
    def simulation(self) -> MouseSimulation:
        """Return the body's simulation, for tests and tools running in the same process."""
        return self._simulation

    def _parameter_values(self, changes: List[Parameter] = ()) -> dict:
        values = {p.name: self.get_parameter(p.name).value for p in PARAMETERS}
        values.update((p.name, p.value) for p in changes)
        return values

    def _describe(self) -> str:
        c = self._config
        s = c.settings
        constraint = s.constraint
        if constraint.rigid:
            mode = f'rigid, baumgarte {constraint.baumgarte:g}'
        else:
            mode = (f'soft, {constraint.frequency_hz:g} Hz, '
                    f'damping ratio {constraint.damping_ratio:g}')
        return (f'{c.rate_hz:g} Hz x {s.substeps} substeps in frame {c.frame_id!r}: '
                f'mass {s.body.mass:g} kg, inertia {s.body.inertia}, anchor {s.constraint.anchor},'
                f' {mode}, max force {s.constraint.max_force:g} N, gravity {s.gravity}, damping '
                f'{s.linear_damping:g}/{s.angular_damping:g} 1/s, target timeout '
                f'{c.target_timeout:g} s')

    def _set_frame(self, frame_id: str) -> None:
        self._pose.header.frame_id = frame_id
        self._twist.header.frame_id = frame_id

    def _start_timer(self) -> None:
        if self._timer is not None:
            self.destroy_timer(self._timer)
        rate = self._config.rate_hz
        self._grid = TickGrid(rate, math.ceil(MAX_CATCH_UP_SECONDS * rate))
        self._dt = 1.0 / rate
        self._timer = self.create_timer(self._dt, self._on_timer)

    def _hold_initial_anchor(self) -> None:
        self._user_target = False
        self._simulation.target = (self._config.initial_anchor()
                                   if self._config.hold_initial_anchor else None)

    def _warn(self, reason: str, message: Callable[[], str]) -> None:
        """
        Log ``message()`` at most once per WARN_PERIOD for each ``reason``, counting the rest.

        Throttled here rather than by rclpy's ``throttle_duration_sec``, which inspects the
        caller's frame on every call (some 100 us: a flood of bad targets then cost the node its
        rate) and shares one throttle between all the warnings of one call site.
        """
        now = time.monotonic()
        last, suppressed = self._warnings.get(reason, (-math.inf, 0))
        if now - last < WARN_PERIOD:
            self._warnings[reason] = (last, suppressed + 1)
            return
        more = f' ({suppressed} more since the last one)' if suppressed else ''
        self.get_logger().warning(message() + more)
        self._warnings[reason] = (now, 0)

    def _on_target(self, message: PointStamped) -> None:
        frame = message.header.frame_id
        if frame and frame != self._config.frame_id:
            self._warn('frame', lambda: (
                f'ignoring target in frame {frame!r}: this node works in '
                f'{self._config.frame_id!r} (no tf lookup is made)'))
            return
        point = point_from_message(message)
        if not all(math.isfinite(c) for c in point):
            self._warn('finite', lambda: f'ignoring non-finite target {point}')
            return
        if math.hypot(*point) > self._config.workspace_radius:
            self._warn('workspace', lambda: (
                f'ignoring target {point}: farther than workspace_radius '
                f'{self._config.workspace_radius:g} m from the origin of '
                f'{self._config.frame_id!r}'))
            return
        self._simulation.target = point
        self._user_target = True
        self._last_target_ns = self.get_clock().now().nanoseconds

    def _on_timer(self) -> None:
        now = self.get_clock().now().nanoseconds
        if not self._grid.started:
            # Put t0 where the timer scheduled this first call, not where it ran: each later
            # call then finds exactly its own tick due, however late (up to a period) it runs,
            # instead of only when its jitter beats the first call's.
            left = self._timer.time_until_next_call()
            period = self._timer.timer_period_ns
            self._grid.restart(now + left - period if left is not None and 0 <= left <= period
                               else now)
        due = self._grid.due(now)
        if due.restarted:
            self.clock_restarts += 1
            self.get_logger().warning('clock jumped backwards: restarting the tick grid at '
                                      f'{now * 1e-9:.9f} s without catching up')
        if due.dropped:
            self.dropped_ticks += due.dropped
            self._warn('rate', lambda: (
                f'cannot keep {self._config.rate_hz:g} Hz: dropped {due.dropped} ticks '
                f'({self.dropped_ticks} in all); simulated time falls behind'))
        if due.count > 1:
            self.late_ticks += due.count - 1
        self.ticks_run += due.count
        self._release_if_timed_out(now)
        simulation, dt = self._simulation, self._dt
        for tick in range(due.first, due.first + due.count):
            state = simulation.step(dt)
            stamp = self._grid.stamp(tick)
            set_stamp(self._pose.header.stamp, stamp)
            set_stamp(self._twist.header.stamp, stamp)
            fill_pose(self._pose, state)
            fill_twist(self._twist, state)
            self._pose_publisher.publish(self._pose)
            self._twist_publisher.publish(self._twist)

    def _release_if_timed_out(self, now: int) -> None:
        timeout = self._config.target_timeout
        if (timeout > 0.0 and self._user_target
                and now - self._last_target_ns > timeout * 1e9):
            self._simulation.target = None
            self._user_target = False
            self.get_logger().info(f'no target for {timeout:g} s: releasing the body')

    def _on_reset(self, _request: Trigger.Request, response: Trigger.Response):
        self._simulation.reset()
        self._hold_initial_anchor()
        response.success = True
        response.message = 'back to the initial state' + (
            ', anchor held where it starts' if self._config.hold_initial_anchor else
            ', no target')
        return response

    def _on_release(self, _request: Trigger.Request, response: Trigger.Response):
        had_target = self._simulation.target is not None
        self._simulation.target = None
        self._user_target = False
        response.success = True
        response.message = 'released' if had_target else 'already free'
        return response

    def _on_set_parameters(self, changes: List[Parameter]) -> SetParametersResult:
        try:
            config = configuration_from(self._parameter_values(changes))
        except ValueError as error:
            return SetParametersResult(successful=False, reason=str(error))
        previous, self._config = self._config, config
        self._simulation.settings = config.settings
        self._simulation.initial_state = config.initial_state
        if config.frame_id != previous.frame_id:
            self._set_frame(config.frame_id)
        if config.rate_hz != previous.rate_hz:
            self._start_timer()
        if (config.marker_rate_hz, config.diagnostics_rate_hz) != (
                previous.marker_rate_hz, previous.diagnostics_rate_hz):
            self._start_monitor_timers()
        self.get_logger().info('parameters changed: ' + self._describe())
        return SetParametersResult(successful=True)

    # Markers and diagnostics: their own lower-rate timers, nothing on the per-tick path. The
    # messages are built by the markers and diagnostics modules from the simulation's data.

    def _setup_monitors(self) -> None:
        self._marker_publisher = self.create_publisher(MarkerArray, '~/markers', 10)
        self._diagnostics_publisher = self.create_publisher(DiagnosticArray, '/diagnostics', 10)
        # The first window opens at the first diagnostics call, once the node spins.
        self._tick_window = TickWindow()
        self._monitor_timers = []
        self._start_monitor_timers()

    def _start_monitor_timers(self) -> None:
        """(Re)create the marker and diagnostics timers at their rates; 0 Hz means none."""
        for timer in self._monitor_timers:
            self.destroy_timer(timer)
        self._monitor_timers = [
            self.create_timer(1.0 / rate, callback)
            for rate, callback in ((self._config.marker_rate_hz, self._publish_markers),
                                   (self._config.diagnostics_rate_hz, self._publish_diagnostics))
            if rate > 0.0]

    def _tick_counters(self) -> TickCounters:
        return TickCounters(self.ticks_run, self.late_ticks, self.dropped_ticks,
                            self.clock_restarts)

    def _publish_markers(self) -> None:
        """Publish the markers of the latest tick, stamped as its pose."""
        simulation = self._simulation
        self._marker_publisher.publish(marker_array(
            self._config.frame_id, stamp_nanoseconds(self._pose.header.stamp),
            self._config.box_size, simulation.state, simulation.anchor_position(),
            simulation.target, simulation.constraint_force, reference_force(simulation.settings)))

    def _publish_diagnostics(self) -> None:
        """Publish the rate status over the window since the last call and the constraint's."""
        now = self.get_clock().now().nanoseconds
        config, simulation = self._config, self._simulation
        counters = self._tick_counters()
        window = self._tick_window.sample(now, counters, config.rate_hz)
        thresholds = Thresholds(anchor_warn=config.diagnostics_anchor_warn,
                                anchor_error=config.diagnostics_anchor_error)
        error = simulation.anchor_error()
        if self._user_target:
            kind, age = USER_TARGET, max(0.0, (now - self._last_target_ns) * 1e-9)
        else:
            kind, age = (NO_TARGET if simulation.target is None else INITIAL_ANCHOR), None
        name, hardware_id = self.get_name(), self.get_fully_qualified_name()
        self._diagnostics_publisher.publish(diagnostic_array(now, [
            rate_status(f'{name}: rate', hardware_id, config.rate_hz, window, counters,
                        thresholds),
            constraint_status(f'{name}: constraint', hardware_id, kind, simulation.target,
                              None if error is None else math.hypot(*error),
                              simulation.constraint_force, config.settings.constraint.max_force,
                              age, config.target_timeout, thresholds),
        ]))


def main(args: Optional[List[str]] = None) -> int:
    """Run the node until Ctrl-C or SIGTERM; exit 0 then, 1 for invalid parameters."""
    rclpy.init(args=args, signal_handler_options=SignalHandlerOptions.NO)
    node = None
    try:
        with StopRequest() as stop:
            node = MouseConstraintNode()
            executor = EventsExecutor(context=node.context)
            executor.add_node(node)
            # Not executor.spin(): in this rclpy (7.1.6) the EventsExecutor's spin() busy-waits
            # at a full core and never returns to Python. Nor spin_until_future_complete, which
            # saves a little CPU but leaks 32 B per call here (bench/spin_leak.py). spin_once
            # with a timeout does neither and lets the loop see the stop flag.
            while not stop and node.context.ok():
                executor.spin_once(timeout_sec=0.1)
    except ExternalShutdownException:
        pass
    except ValueError as error:
        rclpy.logging.get_logger(NODE_NAME).fatal(f'invalid parameters: {error}')
        return 1
    finally:
        if node is not None:
            node.destroy_node()
        rclpy.try_shutdown()
    return 0


if __name__ == '__main__':
    sys.exit(main())
