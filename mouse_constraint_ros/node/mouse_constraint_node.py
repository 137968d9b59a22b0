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
stepping; ``Tick`` is one tick (inputs applied, physics stepped, outputs sent); ``Ticker`` owns
time: which driver runs the ticks (the node's clock, the simulated clock, or a caller stepping
the node), paused or running, the rates. ``TargetInput`` and ``WrenchInput`` take the input,
``SimulatorControls`` answers pause, step, reset and release, ``Monitors`` publishes markers and
/diagnostics, ``AnchorParameter`` sets the node's own anchor for a grab or a reset,
``parameters`` validates the configuration and ``parameter_changes`` declares it; ``startup``
words the refusals. A change of parameters goes whole to every part it concerns (a new body
once ``body_loads`` has loaded it off the tick). Start-up refuses what it cannot run with one
FATAL line and exit 1 (``startup``); unknown keys given to the node are warned about.
"""

import sys
from typing import Any, List, NoReturn, Optional, Tuple

from geometry_msgs.msg import PointStamped, PoseStamped, WrenchStamped
from rcl_interfaces.msg import SetParametersResult
import rclpy
from rclpy.event_handler import PublisherEventCallbacks, SubscriptionEventCallbacks
from rclpy.impl.implementation_singleton import rclpy_implementation as _rclpy
from rclpy.node import Node
from rclpy.parameter import Parameter
from rclpy.publisher import Publisher
from rclpy.service_introspection import ServiceIntrospectionState
from rclpy.signals import SignalHandlerOptions
from rclpy.subscription import Subscription
from std_msgs.msg import String
from std_srvs.srv import SetBool, Trigger

from .anchor_parameter import AnchorParameter
from .body_loads import BodyLoads
from .body_simulation import robot_change_refusal, simulation_for
from .device_watch import DeviceWatch
from .grab_input import GrabInput
from .monitors import Monitors
from .parameter_changes import declare, publishing
from .parameters import node_config, NodeConfig, PARAMETERS
from .simulator_controls import SimulatorControls
# CLOCK_LOOP and StartupRefusal: importable from the node, where its refusals come from.
from .startup import (CLOCK_LOOP, clock_loop, describe, hold_here,  # noqa: F401
                      override_refusal, rcl_reason, requested_logger_name,
                      StartupRefusal, unknown_parameter_warnings)
from .target_input import TargetInput
from .tick import Tick
from .tick_record import TickRecord
from .ticker import Ticker
from .usage import asks_for_help, refuse_unknown_arguments, usage_text
from .wrench_input import WrenchInput
from ..description.relative_meshes import described
from ..description.xml_declaration import version_note
from ..inputs.target_gate import Refusal
from ..inputs.throttle import RefusalLog, Throttle
from ..physics import MouseSimulation
from ..timing.guarded_time_source import guard_time_source
from ..timing.spin import NodeRun
from ..wire.interface import (DESCRIPTION_QOS, DESCRIPTION_TOPIC, GRAB_TOPIC, NODE_NAME,
                              PAUSE_SERVICE, RELEASE_SERVICE, RESET_SERVICE, SERVICE_EVENT_QOS,
                              STEP_SERVICE, TARGET_POSE_QOS, TARGET_POSE_TOPIC, TARGET_QOS,
                              TARGET_TOPIC, WRENCH_QOS, WRENCH_TOPIC)
from ..wire.robot_outputs import RobotOutputs
from ..wire.state_publishers import (BroadcasterFactory, DEFAULT_BROADCASTER, StatePublishers,
                                     TF_UNAVAILABLE)

# Throttle period of the warnings about bad input and missed rate (s).
WARN_PERIOD = 2.0
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
    With ``robot_description`` (a URDF link as the body) it offers the URDF, latched, on
    ``robot_description`` for RViz's RobotModel.

    A point on ``grab`` (PointStamped) that lies on the body's shape (``grab`` module) becomes the
    anchor and the target: the node sets its own ``anchor`` parameter to it, so that the
    configuration, ``ros2 param get`` and the markers all show the grabbed point. Targets then
    drag that point, ``~/release`` lets go of it, ``~/reset`` restores the configured anchor:
    the one the node started with or was last given through its parameters.
    """

    def __init__(self, *, transform_broadcaster: Optional[BroadcasterFactory] = (
            _DEFAULT_BROADCASTER), stepped: bool = False, loop_ticks: bool = False,
                 qos_events: bool = True, **kwargs: Any) -> None:
        """
        Declare parameters, build the parts and start ticking.

        :param transform_broadcaster: makes the TF broadcaster from the node (anything with
            ``sendTransform(TransformStamped)`` that sends before it returns); by default
            ``tf2_ros.TransformBroadcaster``, or none when tf2_ros is not importable; None: no
            TF.
        :param stepped: no timer runs the ticks: each ``ticker.step()`` call runs one tick of
            the simulated clock, which the node publishes on /clock (``publish_clock`` must be
            true). ``mouse_constraint_ros.testing`` steps the node so.
        :param loop_ticks: on system time the ticks are the spin loop's to run, not a
            timer's: whoever spins the node calls ``ticker.run_due`` between events
            (``NodeRun.serve`` with it as ``pace``, as ``main`` does); that saves the
            executor's timer thread and its wake per tick. Off (an rclpy timer) for a node
            added to an executor that its application spins.
        :param qos_events: the publishers and subscriptions warn, as rclpy's do by default, of
            a peer with incompatible QoS or type. Off, they have no event handlers: two entities
            fewer per topic in each wait of an executor. ``mouse_constraint_ros.testing`` builds
            its node so; it names the endpoints that do not match, and why, itself.
        :param kwargs: passed to ``rclpy.node.Node``.
        :raises StartupRefusal: (a ValueError) a parameter or the configuration is invalid; the
            node is destroyed then.
        """
        # Before Node.__init__, which creates the parameter events' publisher.
        self._qos_events = qos_events
        super().__init__(NODE_NAME, **kwargs)
        self._throttle = Throttle(self.get_logger().warning, period=WARN_PERIOD)
        # Through a function of its own: rclpy keys a log call's severity by its caller, and the
        # warnings are logged from the same line of Throttle.
        self._notes = Throttle(lambda text: self.get_logger().info(text), period=WARN_PERIOD)
        guard_time_source(self, lambda text: self._throttle('clock ignored', lambda: text))
        self._stepped = stepped
        self._loop_ticks = loop_ticks
        self.body_loads = BodyLoads(self, self._apply)
        try:
            declare(self, PARAMETERS)
            self._read_description_file()
            config = node_config(self._parameter_values(), load=self.body_loads.now)
        except ValueError as error:
            self._refuse(str(error))
        self._warn_about_unknown_parameters()
        refusal = self._clock_refusal(config, self.get_parameter('use_sim_time').value)
        if refusal is not None:
            self._refuse(refusal)
        self._config = config
        self._anchor = AnchorParameter(self, config.anchor)
        self._build(config, transform_broadcaster)
        self._wire()
        self.add_on_set_parameters_callback(self._on_set_parameters)
        self.get_logger().info(describe(config))
        if config.publish_force:
            self.get_logger().info(hold_here(config))
        if not self._state_publishers.tf_on:
            self.get_logger().info(f'TF {self._state_publishers.tf_status}')

    def _build(self, config: NodeConfig, transform_broadcaster) -> None:
        """Make the parts, each given what it reads and writes, and start the ticks."""
        simulation = self._simulation = simulation_for(config)
        record = TickRecord()
        ticker = self.ticker = Ticker(self, config=config, record=record, stepped=self._stepped,
                                      warn=self._throttle, loop=self._loop_ticks)
        if transform_broadcaster is _DEFAULT_BROADCASTER:
            factory, unavailable = DEFAULT_BROADCASTER, TF_UNAVAILABLE
        else:
            factory, unavailable = transform_broadcaster, None
        self._state_publishers = StatePublishers(
            self, broadcaster_factory=factory, unavailable=unavailable, simulation=simulation,
            **publishing(config))
        refusals = self._refusals = RefusalLog(self._throttle)
        log = self.get_logger().info
        device = DeviceWatch(config=config, now_ns=ticker.now_ns, log=log,
                             clock=ticker.device_clock, pose_tick=ticker.device_tick)
        self._target = TargetInput(simulation=simulation, config=config, record=record,
                                   now_ns=ticker.now_ns, refuse=refusals, log=log, device=device)
        self._grab = GrabInput(simulation=simulation, config=config, target=self._target,
                               set_anchor=self._anchor.set_to, refuse=refusals)
        self._wrench = WrenchInput(simulation=simulation, config=config, now_ns=ticker.now_ns,
                                   refuse=refusals, log=log)
        tick = Tick(simulation=simulation, target=self._target, wrench=self._wrench,
                    state_publishers=self._state_publishers, record=record)
        if config.robot is not None:
            tick.robot_outputs = RobotOutputs(
                self, joint_names=[joint.name for joint in config.robot.robot.model.joints],
                frame_id=config.frame_id, tracked_link=config.robot.tracked_link,
                send_transform=self._state_publishers.send_transform)
        ticker.start(tick)
        self._controls = SimulatorControls(
            ticker=ticker, simulation=simulation, target=self._target, wrench=self._wrench,
            restore_anchor=lambda: self._anchor.restore(self._config.anchor),
            hold_initial_anchor=lambda: self._config.hold_initial_anchor)
        self._monitors = Monitors(node=self, ticker=ticker, simulation=simulation,
                                  target=self._target, wrench=self._wrench,
                                  state_publishers=self._state_publishers, refusals=refusals)
        self._monitors.configure(config)
        self._description = self.create_publisher(String, DESCRIPTION_TOPIC, DESCRIPTION_QOS)
        self._publish_description(self.get_parameter('robot_description').value)

    def _read_description_file(self) -> None:
        """Make robot_description the URDF of robot_description_file, its meshes resolved."""
        values = self._parameter_values()
        if values['robot_description_file']:
            self.set_parameters([Parameter('robot_description', value=described(
                values['robot_description'], values['robot_description_file']))])

    def _publish_description(self, text: str) -> None:
        """Offer ``robot_description`` on its topic (latched) when it is set, as RViz reads it."""
        if text and version_note(text):
            self.get_logger().warning(version_note(text))
        if text:
            self._description.publish(String(data=text))

    def _wire(self) -> None:
        """Create the subscriptions and services, each calling its part."""
        self.create_subscription(PointStamped, TARGET_TOPIC, self._target.on_target, TARGET_QOS)
        self.create_subscription(PoseStamped, TARGET_POSE_TOPIC, self._target.on_target_pose,
                                 TARGET_POSE_QOS)
        self.create_subscription(PointStamped, GRAB_TOPIC, self._grab.on_grab, TARGET_QOS)
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

    def create_publisher(self, *args: Any, **kwargs: Any) -> Publisher:
        """Create a publisher as ``Node`` does, without event handlers if ``qos_events`` is off."""
        if not self._qos_events:
            kwargs.setdefault('event_callbacks',
                              PublisherEventCallbacks(use_default_callbacks=False))
        return super().create_publisher(*args, **kwargs)

    def create_subscription(self, *args: Any, **kwargs: Any) -> Subscription:
        """Create a subscription as ``Node`` does, without event handlers if ``qos_events`` off."""
        if not self._qos_events:
            kwargs.setdefault('event_callbacks',
                              SubscriptionEventCallbacks(use_default_callbacks=False))
        return super().create_subscription(*args, **kwargs)

    def _clock_refusal(self, config: NodeConfig, use_sim_time: bool) -> Optional[str]:
        """Return why the node cannot keep time so, or None."""
        refusal = clock_loop(config.publish_clock, use_sim_time)
        if refusal is None and self._stepped and not config.publish_clock:
            refusal = STEPPED_NEEDS_CLOCK
        return refusal

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
    def refusals(self) -> Tuple[int, Optional[Refusal]]:
        """Return how many targets, grabs and wrenches were refused, and the last refusal."""
        return self._refusals.count, self._refusals.last

    def _on_set_parameters(self, changes: List[Parameter]) -> SetParametersResult:
        """Apply a set of changes whole to every part it concerns, or refuse it whole."""
        values = self._parameter_values(changes)
        if any(change.name == 'robot_description_file' and change.value
               != self.get_parameter('robot_description_file').value for change in changes):
            return SetParametersResult(successful=False, reason=(
                'robot_description_file is read at start: set robot_description (meshes named '
                'package://, file:// or by absolute paths) to change the body'))
        # A robot is not swapped at run time (refused before anything loads); a robot's other
        # changes take the robot loaded at start.
        refusal = None
        if not self.body_loads.reverting:
            refusal = robot_change_refusal(self._config, values)
        if refusal is None and self._config.robot is None:
            refusal = self.body_loads.refusal(values, changes)  # a new body loads off the tick
        if refusal is None:
            try:
                refusal = self._apply(node_config(values, load=self.body_loads.now), changes)
            except ValueError as error:
                refusal = str(error)
        return SetParametersResult(successful=not refusal, reason=refusal or '')

    def _apply(self, config: NodeConfig, changes: List[Parameter]) -> Optional[str]:
        """Apply ``config`` of ``changes`` to every part; return why the clock refuses it."""
        use_sim_time = next((p.value for p in changes if p.name == 'use_sim_time'),
                            self.get_parameter('use_sim_time').value)
        refusal = self._clock_refusal(config, use_sim_time)
        if refusal is not None:
            return refusal
        previous, self._config = self._config, config
        anchor = config.anchor
        self._anchor.changed(changes, anchor)
        self._simulation.configure(config.settings, config.initial_state)
        self._target.configure(config)
        self._grab.configure(config)
        self._wrench.configure(config)
        if publishing(config) != publishing(previous):
            self._configure_publishers(config)
        if self.ticker.configure(config):
            # Another time base: the ages of target and wrench start again in it.
            now = self.ticker.now_ns()
            self._target.restart_age(now)
            self._wrench.restart_age(now)
        self._monitors.configure(config)
        for change in changes:
            if change.name == 'robot_description':
                self._publish_description(change.value)
        if self._anchor.setting:
            # A grab or a reset: one short line, at most every WARN_PERIOD (grabs can flood).
            # Six digits: the line stays short with the count of the lines it stands for.
            self._notes('anchor', lambda: 'anchor ({:.6g}, {:.6g}, {:.6g}) m (body frame), set '
                                          'by the node'.format(*anchor))
        else:
            self.get_logger().info('parameters changed: ' + describe(config))
        return None

    def _configure_publishers(self, config: NodeConfig) -> None:
        """Give the state publishers their part of ``config``; say when TF turns on or off."""
        publishers = self._state_publishers
        tf_status = publishers.tf_status
        publishers.configure(**publishing(config))
        if publishers.tf_status != tf_status:
            self.get_logger().info(f'TF {publishers.tf_status}')


def main(args: Optional[List[str]] = None) -> int:
    """
    Run the node until Ctrl-C, SIGTERM or SIGHUP; exit 0 then, 1 when it cannot start.

    Arguments outside ``--ros-args`` (which rclpy would ignore) end it with exit 2 and a line
    that shows the ``--ros-args -p`` form.
    """
    refuse_unknown_arguments(sys.argv if args is None else args)
    if asks_for_help(sys.argv if args is None else args):
        print(usage_text())
        return 0
    refusal = override_refusal(sys.argv if args is None else args)
    if refusal is not None:
        name = requested_logger_name(sys.argv if args is None else args, NODE_NAME)
        rclpy.logging.get_logger(name).fatal(f'cannot start: {refusal}')
        return 1
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
    with NodeRun() as run:
        try:
            run.node = MouseConstraintNode(loop_ticks=True)
            return run.serve(pace=run.node.ticker.run_due)
        except StartupRefusal as error:
            rclpy.logging.get_logger(error.logger_name).fatal(f'invalid parameters: {error}')
            return 1


if __name__ == '__main__':
    sys.exit(main())
