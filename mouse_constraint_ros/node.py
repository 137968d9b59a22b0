"""
The ``mouse_constraint`` node: parameters, topics, services and the fixed-rate timer.

It holds no physics: a ``MouseSimulation`` does the stepping, ``TickGrid`` says which ticks are
due, ``configuration`` validates parameters and ``conversions`` fills the messages.

Start-up refuses what it cannot run with one FATAL line tagged with the node's real name and
exit 1: a parameter of the wrong type or out of its declared range, a configuration that is not
valid as a whole, or a params file rcl cannot read. Unknown keys in the parameters given to the
node are not an error (one file may serve several nodes) but are warned about, with the nearest
known name.
"""

import difflib
import math
import re
import sys
import time
from typing import Any, Callable, Dict, List, NoReturn, Optional, Sequence, Tuple

from diagnostic_msgs.msg import DiagnosticArray
from geometry_msgs.msg import PointStamped, PoseStamped, TwistStamped
from rcl_interfaces.msg import (FloatingPointRange, IntegerRange, ParameterDescriptor,
                                SetParametersResult)
import rclpy
from rclpy.clock import Clock, ClockType
from rclpy.exceptions import ParameterException
from rclpy.executors import ExternalShutdownException
from rclpy.experimental import EventsExecutor
from rclpy.impl.implementation_singleton import rclpy_implementation as _rclpy
from rclpy.node import Node
from rclpy.parameter import Parameter
from rclpy.signals import SignalHandlerOptions
from std_srvs.srv import Trigger
from visualization_msgs.msg import MarkerArray

from .diagnostics import (constraint_status, diagnostic_array, INITIAL_ANCHOR, NO_TARGET,
                          rate_status, Thresholds, TickCounters, TickWindow, USER_TARGET)
from .interface import (DIAGNOSTICS_TOPIC, MARKERS_TOPIC, MONITOR_DEPTH, NODE_NAME,
                        POSE_TOPIC, RELEASE_SERVICE, RESET_SERVICE, STATE_QOS, TARGET_QOS,
                        TARGET_TOPIC, TWIST_TOPIC)
from .markers import marker_array, reference_force
from .messages import fill_pose, fill_twist, point_from_message, set_stamp, stamp_nanoseconds
from .parameters import node_config, PARAMETERS, ParameterSpec
from .physics import MouseSimulation
from .spin import StopRequest
from .tick_grid import TickGrid

# Catch up on at most this much missed time in one timer callback; older ticks are dropped.
MAX_CATCH_UP_SECONDS = 0.1
# Run ticks for at most this much wall time in one timer callback; the rest of the due ticks are
# dropped. The executor is single-threaded: this bounds how long a service or parameter call
# waits behind the physics, whatever one tick costs (substeps). A callback that reaches the
# budget is followed by as long a rest, in which due ticks are dropped at once: the physics
# then has at most half of the wall time, and the timer events that queued up meanwhile are
# cleared in microseconds instead of each running ticks in turn.
CALLBACK_BUDGET_SECONDS = 0.05
# Weight of the newest callback in the running estimate of one tick's wall time.
TICK_COST_WEIGHT = 0.25
# Throttle period of the warnings about bad input and missed rate (s).
WARN_PERIOD = 2.0
# Period (s, steady clock) of the check that a simulated clock has started.
CLOCK_WATCH_PERIOD = 1.0
# Parameters rclpy declares or reads by itself; not unknown keys.
RCLPY_PARAMETER_PREFIXES = ('use_sim_time', 'start_type_description_service', 'qos_overrides.')


class StartupRefusal(ValueError):
    """
    The node cannot start with what it was given; the message says what and why.

    :param logger_name: the logger of the node that refuses, with its real (remapped) name.
    :param reason: one line naming the parameter and the reason.
    """

    def __init__(self, logger_name: str, reason: str) -> None:
        """Keep the logger name next to the reason."""
        super().__init__(reason)
        self.logger_name = logger_name


_TYPE_NAMES = {
    Parameter.Type.BOOL: 'a bool',
    Parameter.Type.INTEGER: 'an integer',
    Parameter.Type.DOUBLE: 'a double',
    Parameter.Type.STRING: 'a string',
    Parameter.Type.BYTE_ARRAY: 'a list of bytes',
    Parameter.Type.BOOL_ARRAY: 'a list of bools',
    Parameter.Type.INTEGER_ARRAY: 'a list of integers',
    Parameter.Type.DOUBLE_ARRAY: 'a list of doubles',
    Parameter.Type.STRING_ARRAY: 'a list of strings',
}


def _yaml(value: Any) -> str:
    """Return ``value`` as YAML writes it (true, 2.0, [1.0, 2.0], .nan)."""
    if isinstance(value, bool):
        return 'true' if value else 'false'
    if isinstance(value, float) and not math.isfinite(value):
        return '.nan' if math.isnan(value) else ('-.inf' if value < 0 else '.inf')
    if isinstance(value, (list, tuple)) or type(value).__name__ == 'array':
        return '[' + ', '.join(_yaml(v) for v in value) + ']'
    return repr(value)


def _type_hint(value: Any, expected: Parameter.Type) -> Optional[str]:
    """Return how to write ``value`` as the ``expected`` type, where that is plain."""
    if expected == Parameter.Type.DOUBLE and type(value) is int:
        return _yaml(float(value))
    if expected == Parameter.Type.DOUBLE_ARRAY and isinstance(value, Sequence):
        if all(type(v) in (int, float) for v in value):
            return _yaml([float(v) for v in value])
    if expected == Parameter.Type.INTEGER and isinstance(value, float) and value.is_integer():
        return str(int(value))
    if expected == Parameter.Type.BOOL and type(value) is int and value in (0, 1):
        return _yaml(bool(value))
    return None


def refusal_reason(declaration: ParameterSpec, given: Optional[Parameter],
                   error: ParameterException) -> str:
    """
    Return one line saying why ``given`` cannot be ``declaration``'s value.

    rclpy refuses an override of another type than the default's (a YAML ``2`` is an integer,
    never a double: ``ros2 param set`` refuses it the same way, so the node does not convert it
    at start either) or outside the declared range; its exception texts name neither the
    parameter first nor the fix.

    :param declaration: the parameter as the node declares it.
    :param given: the override the node was started with, or None.
    :param error: what rclpy raised.
    """
    name = declaration.name
    if given is None:
        return f'{name}: {error}'
    expected = Parameter.Type.from_parameter_value(declaration.default)
    value = given.value
    if given.type_ != expected:
        reason = (f'{name}: {_yaml(value)} is {_TYPE_NAMES.get(given.type_, given.type_.name)}, '
                  f'{name} takes {_TYPE_NAMES.get(expected, expected.name)}')
        hint = _type_hint(value, expected)
        return reason + (f': write {hint}' if hint else '')
    if declaration.bounds is not None:
        low, high = declaration.bounds
        bounds = f'its range [{_yaml(low)}, {_yaml(high)}]'
        if isinstance(value, float) and math.isnan(value):
            return f'{name}: .nan is not a number, so not within {bounds}'
        return f'{name}: {_yaml(value)} is outside {bounds}'
    return f'{name}: {error}'


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
        """
        Declare parameters and build the simulation.

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
        # Why ticks were last dropped, for /diagnostics; None while none were.
        self.drop_cause: Optional[str] = None
        # Running estimate of one tick's wall time (s), 0 before the first tick.
        self._tick_seconds = 0.0
        # perf_counter() until which due ticks are dropped, after a callback over its budget.
        self._rest_until = -math.inf
        # Which clock the grid runs on: simulated (True) or system time.
        self._grid_sim_time = self.get_clock().ros_time_is_active
        # Timers that must run while a simulated clock stands still or has not started.
        self._steady_clock = Clock(clock_type=ClockType.STEADY_TIME)

        self._pose = PoseStamped()
        self._twist = TwistStamped()
        self._set_frame(self._config.frame_id)
        self._pose_publisher = self.create_publisher(PoseStamped, POSE_TOPIC, STATE_QOS)
        self._twist_publisher = self.create_publisher(TwistStamped, TWIST_TOPIC, STATE_QOS)
        self.create_subscription(PointStamped, TARGET_TOPIC, self._on_target, TARGET_QOS)
        self.create_service(Trigger, RESET_SERVICE, self._on_reset)
        self.create_service(Trigger, RELEASE_SERVICE, self._on_release)
        self._timer = None
        self._start_timer()
        self._setup_monitors()
        self.create_timer(CLOCK_WATCH_PERIOD, self._watch_clock, clock=self._steady_clock)
        self.add_on_set_parameters_callback(self._on_set_parameters)
        self.get_logger().info(self._describe())

    def _declare(self, parameter: ParameterSpec) -> None:
        try:
            self.declare_parameter(parameter.name, parameter.default, _descriptor(parameter))
        except ParameterException as error:
            raise ValueError(refusal_reason(
                parameter, self._parameter_overrides.get(parameter.name), error)) from None

    def _refuse(self, reason: str) -> NoReturn:
        """Destroy the half-built node and raise StartupRefusal with its logger's name."""
        logger_name = self.get_logger().name
        self.destroy_node()
        raise StartupRefusal(logger_name, reason) from None

    def _warn_about_unknown_parameters(self) -> None:
        """Warn once for each given parameter the node does not have, with the nearest name."""
        known = [p.name for p in PARAMETERS]
        for name in sorted(set(self._parameter_overrides) - set(self._parameters)):
            if name.startswith(RCLPY_PARAMETER_PREFIXES):
                continue
            nearest = difflib.get_close_matches(name, known, n=1)
            self.get_logger().warning(
                f'ignoring unknown parameter {name!r}'
                + (f': did you mean {nearest[0]!r}?' if nearest else ''))

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
        self._simulation.set_target(point, time=self._simulation.time)
        self._user_target = True
        self._last_target_ns = self.get_clock().now().nanoseconds

    def _on_timer(self) -> None:
        clock = self.get_clock()
        now = clock.now().nanoseconds
        if clock.ros_time_is_active != self._grid_sim_time:
            # use_sim_time flipped: a new clock, not lost time. Restart the grid on it.
            self._grid_sim_time = clock.ros_time_is_active
            self._grid.restart(now)
            self.clock_restarts += 1
            self.get_logger().info(
                f'clock changed to {"simulated" if self._grid_sim_time else "system"} time: '
                f'restarting the tick grid at {now * 1e-9:.9f} s without catching up')
        elif not self._grid.started:
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
        first, count = due.first, due.count
        if due.dropped:
            self._drop(due.dropped, f'more than the {MAX_CATCH_UP_SECONDS:g} s catch-up bound '
                       'was missed')
        self._release_if_timed_out(now)
        if count and time.perf_counter() < self._rest_until:
            # Resting after a callback that spent its budget: the executor's queue (timer
            # events keep coming at the rate while ticks run) drains, services get their turn.
            self._drop(count, self._budget_cause(self._tick_seconds))
            return
        # What fits in the wall budget at the estimated cost runs; the oldest of the rest are
        # dropped, so that the newest state is the one published.
        over_budget = False
        if self._tick_seconds > 0.0:
            fits = max(1, int(CALLBACK_BUDGET_SECONDS / self._tick_seconds))
            if count > fits:
                over_budget = True
                self._drop(count - fits, self._budget_cause(self._tick_seconds))
                first, count = first + count - fits, fits
        started = time.perf_counter()
        ran = self._run_ticks(first, count)
        if ran < count:
            over_budget = True
            self._drop(count - ran, self._budget_cause(self._tick_seconds))
        if over_budget:
            # The physics cannot keep the rate: it gets at most half of the wall time.
            finished = time.perf_counter()
            self._rest_until = finished + (finished - started)
        if ran > 1:
            self.late_ticks += ran - 1
        self.ticks_run += ran

    def _budget_cause(self, tick_seconds: float) -> str:
        return (f'one tick takes {tick_seconds * 1e3:.3g} ms of wall time '
                f'({self._config.settings.substeps} substeps) and a timer callback stops after '
                f'{CALLBACK_BUDGET_SECONDS * 1e3:g} ms so that services and parameters answer')

    def _drop(self, count: int, cause: str) -> None:
        self.dropped_ticks += count
        self.drop_cause = cause
        self._warn('rate', lambda: (
            f'cannot keep {self._config.rate_hz:g} Hz: dropped {count} ticks '
            f'({self.dropped_ticks} in all): {cause}; simulated time falls behind'))

    def _run_ticks(self, first: int, count: int) -> int:
        """
        Step and publish ticks ``first`` on, until ``count`` ran or the wall budget is spent.

        :returns: how many ran (at least one when ``count`` > 0).
        """
        simulation, dt = self._simulation, self._dt
        started = time.perf_counter()
        ran = 0
        for tick in range(first, first + count):
            state = simulation.step(dt)
            stamp = self._grid.stamp(tick)
            set_stamp(self._pose.header.stamp, stamp)
            set_stamp(self._twist.header.stamp, stamp)
            fill_pose(self._pose, state)
            fill_twist(self._twist, state)
            self._pose_publisher.publish(self._pose)
            self._twist_publisher.publish(self._twist)
            ran += 1
            if time.perf_counter() - started > CALLBACK_BUDGET_SECONDS:
                break
        if ran:
            cost = (time.perf_counter() - started) / ran
            self._tick_seconds = (cost if self._tick_seconds == 0.0 else
                                  self._tick_seconds + TICK_COST_WEIGHT * (
                                      cost - self._tick_seconds))
        return ran

    def waiting_for_clock(self) -> Optional[str]:
        """
        Return ``'/clock on <topic>'`` while use_sim_time is on and no clock message came.

        The node's clock reads zero until then and no timer on it fires: no tick, no pose.
        """
        clock = self.get_clock()
        if clock.ros_time_is_active and clock.now().nanoseconds == 0:
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
            config = node_config(self._parameter_values(changes))
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
        self._marker_publisher = self.create_publisher(MarkerArray, MARKERS_TOPIC, MONITOR_DEPTH)
        self._diagnostics_publisher = self.create_publisher(
            DiagnosticArray, DIAGNOSTICS_TOPIC, MONITOR_DEPTH)
        # The first window opens at the first diagnostics call, once the node spins.
        self._tick_window = TickWindow()
        self._window_sim_time = self.get_clock().ros_time_is_active
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
        """Publish the markers of the latest tick, stamped as its pose."""
        simulation = self._simulation
        self._marker_publisher.publish(marker_array(
            self._config.frame_id, stamp_nanoseconds(self._pose.header.stamp),
            self._config.box_size, simulation.state, simulation.anchor_position(),
            simulation.target, simulation.constraint_force, reference_force(simulation.settings)))

    def _publish_diagnostics(self) -> None:
        """
        Publish the rate status over the window since the last call and the constraint's.

        Stamped with the node's clock, which reads zero while a simulated clock has not started.
        The status names start with the fully qualified node name, unique in a ROS graph, as
        diagnostic_aggregator needs.
        """
        clock = self.get_clock()
        now = clock.now().nanoseconds
        config, simulation = self._config, self._simulation
        counters = self._tick_counters()
        if clock.ros_time_is_active != self._window_sim_time:
            # Another clock: a window across the change would measure nothing real.
            self._window_sim_time = clock.ros_time_is_active
            self._tick_window = TickWindow()
        window = self._tick_window.sample(now, counters, config.rate_hz)
        thresholds = Thresholds(anchor_warn=config.diagnostics_anchor_warn,
                                anchor_error=config.diagnostics_anchor_error)
        error = simulation.anchor_error()
        if self._user_target:
            kind, age = USER_TARGET, max(0.0, (now - self._last_target_ns) * 1e-9)
        else:
            kind, age = (NO_TARGET if simulation.target is None else INITIAL_ANCHOR), None
        name = hardware_id = self.get_fully_qualified_name()
        self._diagnostics_publisher.publish(diagnostic_array(now, [
            rate_status(f'{name}: rate', hardware_id, config.rate_hz, window, counters,
                        thresholds, drop_cause=self.drop_cause,
                        waiting_for=self.waiting_for_clock()),
            constraint_status(f'{name}: constraint', hardware_id, kind, simulation.target,
                              None if error is None else math.hypot(*error),
                              simulation.constraint_force, config.settings.constraint.max_force,
                              age, config.target_timeout, thresholds),
        ]))


def requested_logger_name(args: Sequence[str]) -> str:
    """
    Return the node's logger name as the command line's remaps make it, without rcl.

    For the one case where rcl cannot start (an unreadable params file) and so cannot say:
    ``-r __node:=other`` (or ``__name``) and ``-r __ns:=/a/b`` give ``a.b.other``.
    """
    name, namespace = NODE_NAME, ''
    for argument in args:
        match = re.fullmatch(r'(?:[^:=]+:)?__(node|name|ns):=(.+)', argument)
        if match and match.group(1) == 'ns':
            namespace = match.group(2)
        elif match:
            name = match.group(2)
    return '.'.join(part for part in namespace.split('/') + [name] if part)


def rcl_reason(error: Exception) -> str:
    """Return rcl's start-up error as one line: its sentence, without rcl's source locations."""
    text = re.sub(r', at \S+:\d+', '', str(error)).strip()
    text = re.sub(r'^failed to initialize rcl: ', '', text)
    if 'Sequence should be of same type' in text:
        text += (' (a list holds one type: write every number of a list of doubles with a '
                 'decimal point, e.g. [0.2, 0.0, 0.05])')
    elif 'Error opening YAML file' in text:
        text += ' (no such file, or not readable)'
    return text


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
        rclpy.logging.get_logger(requested_logger_name(
            sys.argv if args is None else args)).fatal(f'cannot start: {rcl_reason(error)}')
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
            # Not executor.spin(): in this rclpy (7.1.6) the EventsExecutor's spin() busy-waits
            # at a full core and never returns to Python. Nor spin_until_future_complete, which
            # saves a little CPU but leaks 32 B per call here (bench/spin_leak.py). spin_once
            # with a timeout does neither and lets the loop see the stop flag.
            while not stop and node.context.ok():
                executor.spin_once(timeout_sec=0.1)
    except ExternalShutdownException:
        pass
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
