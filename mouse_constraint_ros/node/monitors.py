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
The node's monitors: markers and diagnostics on their own lower-rate timers.

Nothing here is on the per-tick path. The messages are built by the ``markers`` and
``diagnostics`` modules from the simulation's data; here are their timers and what they read.
"""

import math
import time
from typing import Callable

from diagnostic_msgs.msg import DiagnosticArray
from rclpy.clock import Clock
from rclpy.node import Node
from visualization_msgs.msg import MarkerArray

from .clock_ticks import ClockTicks
from .parameters import NodeConfig
from .simulator_controls import SimulatorControls
from .target_input import TargetInput
from .tick_loop import NodeClockTicks
from .tick_record import TickRecord
from .wrench_input import WrenchInput
from ..monitoring.diagnostics import (constraint_status, diagnostic_array, INITIAL_ANCHOR,
                                      NO_TARGET, Pacing, publishing_values, rate_status,
                                      simulator_status, Thresholds, TickWindow, USER_TARGET)
from ..monitoring.markers import marker_array, reference_force, wrench_reference
from ..physics import MouseSimulation
from ..physics.simulation import force_bound
from ..wire.interface import DIAGNOSTICS_TOPIC, MARKERS_TOPIC, MONITOR_DEPTH
from ..wire.messages import felt_force
from ..wire.state_publishers import StatePublishers


class Monitors:
    """
    The marker and diagnostics publishers and their timers.

    :param node: the node that owns publishers and timers, and names the statuses.
    :param config: the node's configuration (``configure`` replaces it).
    :param steady_clock: the clock of the diagnostics timer.
    :param now_ns: the node's time (ns).
    :param simulation: the body shown and judged.
    :param record: the ticks' record (counts, the latest stamp).
    :param target: the target input (kind and age of the target).
    :param wrench: the wrench input (the applied wrench's age).
    :param controls: the simulator controls (paused, resumed).
    :param node_clock_ticks: the node-clock driver (what its clock waits for).
    :param clock_ticks: the simulated-clock driver (on, pacing achieved).
    :param state_publishers: what is published (TF status, odometry topic).
    """

    def __init__(self, *, node: Node, config: NodeConfig, steady_clock: Clock,
                 now_ns: Callable[[], int], simulation: MouseSimulation, record: TickRecord,
                 target: TargetInput, wrench: WrenchInput, controls: SimulatorControls,
                 node_clock_ticks: NodeClockTicks, clock_ticks: ClockTicks,
                 state_publishers: StatePublishers) -> None:
        """Create the publishers and start the timers at the configured rates."""
        self._node = node
        self._steady_clock = steady_clock
        self._now_ns = now_ns
        self._simulation = simulation
        self._record = record
        self._target = target
        self._wrench = wrench
        self._controls = controls
        self._node_clock_ticks = node_clock_ticks
        self._clock_ticks = clock_ticks
        self._state_publishers = state_publishers
        self._marker_publisher = node.create_publisher(MarkerArray, MARKERS_TOPIC, MONITOR_DEPTH)
        self._diagnostics_publisher = node.create_publisher(
            DiagnosticArray, DIAGNOSTICS_TOPIC, MONITOR_DEPTH)
        # The first window opens at the first diagnostics call, once the node spins.
        self._tick_window = TickWindow()
        self._window_source = self._clock_source()
        self._window_resumes = controls.resumes
        self._timers = []
        self._rates = None
        self.configure(config)

    def configure(self, config: NodeConfig) -> None:
        """
        Take a new configuration; (re)create the timers when a rate changed (0 Hz: none).

        Markers show the latest tick and follow the node's clock. Diagnostics run on the steady
        clock: they must still come when a simulated clock has not started or stands still,
        which is when they have something to say.
        """
        self._config = config
        rates = (config.marker_rate_hz, config.diagnostics_rate_hz)
        if rates == self._rates:
            return
        self._rates = rates
        for timer in self._timers:
            self._node.destroy_timer(timer)
        self._timers = [
            self._node.create_timer(1.0 / rate, callback, clock=clock)
            for rate, callback, clock in (
                (config.marker_rate_hz, self.publish_markers, None),
                (config.diagnostics_rate_hz, self.publish_diagnostics, self._steady_clock))
            if rate > 0.0]

    def _clock_source(self):
        return (self._node.get_clock().ros_time_is_active, self._clock_ticks.on)

    def publish_markers(self) -> None:
        """Publish the markers of the latest tick, with its stamp."""
        simulation, config = self._simulation, self._config
        self._marker_publisher.publish(marker_array(
            frame_id=config.frame_id, stamp_ns=self._record.stamp_ns,
            box_size=config.box_size, state=simulation.state,
            anchor=simulation.anchor_position(), target=simulation.target,
            force=simulation.constraint_force, reference=reference_force(simulation.settings),
            wrench_force=simulation.wrench[0],
            wrench_reference=wrench_reference(simulation.settings),
            floor=simulation.settings.floor,
            contacts=[point for point, _ in simulation.contacts],
            felt_force=felt_force(simulation.tick_impulse) if config.publish_force else None))

    def publish_diagnostics(self) -> None:
        """
        Publish the rate status over the window since the last call and the constraint's.

        Stamped with the node's clock, which reads zero while a simulated clock has not started.
        The status names start with the fully qualified node name, unique in a ROS graph, as
        diagnostic_aggregator needs.
        """
        now = self._now_ns()
        config, simulation, controls = self._config, self._simulation, self._controls
        counters = self._record.counters()
        source = self._clock_source()
        if source != self._window_source or controls.resumes != self._window_resumes:
            # Another clock, or a pause in between: a window across it would measure nothing.
            self._window_source, self._window_resumes = source, controls.resumes
            self._tick_window = TickWindow()
        # Paused, the ticks stop on purpose: no rate to judge (the window restarts on resume).
        window = (None if controls.paused else
                  self._tick_window.sample(now, counters, config.rate_hz))
        thresholds = Thresholds(anchor_warn=config.diagnostics_anchor_warn,
                                anchor_error=config.diagnostics_anchor_error)
        error = simulation.anchor_error()
        target = self._target
        if target.user_target:
            kind = USER_TARGET
        else:
            kind = NO_TARGET if simulation.target is None else INITIAL_ANCHOR
        name = hardware_id = self._node.get_fully_qualified_name()
        waiting = None if self._clock_ticks.on else self._node_clock_ticks.waiting_for_clock()
        rate = rate_status(f'{name}: rate', hardware_id, rate_hz=config.rate_hz, window=window,
                           totals=counters, thresholds=thresholds,
                           drop_cause=self._record.drop_cause, waiting_for=waiting)
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
                              target_age=target.age(now), target_timeout=config.target_timeout,
                              thresholds=thresholds,
                              floor_contacts=(simulation.contact_count
                                              if config.settings.floor.enabled else None)),
            self._simulator_status(f'{name}: simulator', hardware_id, now),
        ]))

    def _simulator_status(self, name: str, hardware_id: str, now: int):
        config, clock_ticks = self._config, self._clock_ticks
        achieved, slipped = clock_ticks.pacing.sample(time.monotonic_ns(), clock_ticks.sim_clock)
        publishing = clock_ticks.on
        force, torque = self._simulation.wrench
        pacing = Pacing(publishing, self._controls.paused, config.real_time_factor,
                        achieved if publishing else None, slipped, now * 1e-9)
        return simulator_status(name, hardware_id, pacing=pacing, force=force, torque=torque,
                                wrench_age=self._wrench.age(now),
                                wrench_timeout=config.wrench_timeout)
