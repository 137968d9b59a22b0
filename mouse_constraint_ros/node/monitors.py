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
from typing import Optional

from diagnostic_msgs.msg import DiagnosticArray
from rclpy.node import Node
from visualization_msgs.msg import MarkerArray

from .parameters import NodeConfig
from .target_input import TargetInput
from .ticker import Ticker
from .wrench_input import WrenchInput
from ..inputs.throttle import RefusalLog
from ..monitoring.body_markers import drawn_pieces
from ..monitoring.diagnostics import (constraint_status, diagnostic_array, INITIAL_ANCHOR,
                                      NO_TARGET, Pacing, publishing_values, rate_status,
                                      simulator_status, Thresholds, USER_TARGET)
from ..monitoring.input_diagnostics import input_status, InputReport
from ..monitoring.markers import BODY_COLOR, marker_array, reference_force, wrench_reference
from ..monitoring.tick_window import TickWindow
from ..physics import MouseSimulation
from ..physics.settings import force_bound
from ..wire.interface import (DIAGNOSTICS_TOPIC, MARKERS_TOPIC, MONITOR_DEPTH,
                              SIMULATOR_STATUS_SUFFIX)
from ..wire.messages import felt_force
from ..wire.state_publishers import StatePublishers


class Monitors:
    """
    The marker and diagnostics publishers and their timers; idle until ``configure``.

    :param node: the node that owns publishers and timers, and names the statuses.
    :param ticker: the owner of time: the node's time, the ticks' record, pause and pacing.
    :param simulation: the body shown and judged.
    :param target: the target input (kind and age of the target; its device's state).
    :param wrench: the wrench input (the applied wrench's age).
    :param state_publishers: what is published (TF status, odometry topic).
    :param refusals: the inputs refused so far, for the inputs status.
    """

    def __init__(self, *, node: Node, ticker: Ticker, simulation: MouseSimulation,
                 target: TargetInput, wrench: WrenchInput, state_publishers: StatePublishers,
                 refusals: RefusalLog) -> None:
        """Create the publishers; the timers start with the first configuration."""
        self._node = node
        self._ticker = ticker
        self._record = ticker.record
        self._simulation = simulation
        self._target = target
        self._wrench = wrench
        self._state_publishers = state_publishers
        self._refusals = refusals
        self._reported_refusals = 0
        self._reported_lost = 0
        self._marker_publisher = node.create_publisher(MarkerArray, MARKERS_TOPIC, MONITOR_DEPTH)
        self._diagnostics_publisher = node.create_publisher(
            DiagnosticArray, DIAGNOSTICS_TOPIC, MONITOR_DEPTH)
        # The first window opens at the first diagnostics call, once the node spins.
        self._tick_window = TickWindow()
        self._window_source = self._clock_source()
        self._window_resumes = ticker.resumes
        self._timers = []
        self._rates = None
        self._config: Optional[NodeConfig] = None
        # The body's pieces as drawn, of the geometry they were made from; how many went last.
        self._drawn = (None, ())
        self._pieces_sent = 0

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
                (config.diagnostics_rate_hz, self.publish_diagnostics, self._ticker.steady_clock))
            if rate > 0.0]

    def _clock_source(self):
        return (self._node.get_clock().ros_time_is_active, self._ticker.is_clock)

    def publish_markers(self) -> None:
        """
        Publish the markers of the latest tick, with its stamp, while anything subscribes.

        With no subscription the array is not built: DDS would send it nowhere, and building
        and converting it costs more than a tick of the physics (docs/benchmarks.md). The body
        is its link's pieces at the link pose (the box's one CUBE at the COM pose).
        """
        publisher = self._marker_publisher
        if publisher.get_subscription_count() == 0:
            return
        simulation, config = self._simulation, self._config
        geometry, state = config.geometry, simulation.state
        if self._drawn[0] is not geometry:
            self._drawn = (geometry, drawn_pieces(geometry, BODY_COLOR))
        pieces = self._drawn[1]
        publisher.publish(marker_array(
            frame_id=config.frame_id, stamp_ns=self._record.stamp_ns,
            box_size=geometry.extents, state=state,
            anchor=simulation.anchor_position(), target=simulation.target,
            force=simulation.constraint_force, reference=reference_force(simulation.settings),
            wrench_force=simulation.wrench[0],
            wrench_reference=wrench_reference(simulation.settings),
            floor=simulation.settings.floor,
            contacts=[point for point, _ in simulation.contacts],
            felt_force=felt_force(simulation.tick_impulse) if config.publish_force else None,
            pieces=pieces, link_pose=config.body_frame.link_state(state),
            previous_pieces=self._pieces_sent))
        self._pieces_sent = len(pieces)

    def publish_diagnostics(self) -> None:
        """
        Publish the rate status over the window since the last call and the constraint's.

        Stamped with the node's clock, which reads zero while a simulated clock has not started.
        The status names start with the fully qualified node name, unique in a ROS graph, as
        diagnostic_aggregator needs.
        """
        now = self._ticker.now_ns()
        config, simulation, ticker = self._config, self._simulation, self._ticker
        counters = self._record.counters()
        source = self._clock_source()
        if source != self._window_source or ticker.resumes != self._window_resumes:
            # Another clock, or a pause in between: a window across it would measure nothing.
            self._window_source, self._window_resumes = source, ticker.resumes
            self._tick_window = TickWindow()
        # Paused, the ticks stop on purpose: no rate to judge (the window restarts on resume).
        window = (None if ticker.paused else
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
        rate = rate_status(f'{name}: rate', hardware_id, rate_hz=config.rate_hz, window=window,
                           totals=counters, thresholds=thresholds,
                           drop_cause=self._record.drop_cause,
                           waiting_for=ticker.waiting_for_clock())
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
            self._simulator_status(name + SIMULATOR_STATUS_SUFFIX, hardware_id, now),
            self._input_status(f'{name}: inputs', hardware_id, now),
        ]))

    def _input_status(self, name: str, hardware_id: str, now: int):
        refusals, clock = self._refusals, self._ticker.device_clock
        new, self._reported_refusals = (refusals.count - self._reported_refusals,
                                        refusals.count)
        device = self._target.device
        lost = device.lost
        new_lost, self._reported_lost = (0, 0) if lost is None else (
            lost - self._reported_lost, lost)
        return input_status(name, hardware_id, InputReport(
            refused=refusals.count, by_key=dict(refusals.by_key), last_line=refusals.last_line,
            new_refusals=new, device_age=device.age(now),
            device_silent=device.silent(now), device_timeout=self._config.device.timeout,
            device_ticks=(clock.ticks, clock.early, clock.late) if clock.on else None,
            device_lost=lost, new_lost=new_lost))

    def _simulator_status(self, name: str, hardware_id: str, now: int):
        config, ticker = self._config, self._ticker
        achieved, slipped = ticker.pacing()
        force, torque = self._simulation.wrench
        pacing = Pacing(ticker.is_clock, ticker.paused, config.real_time_factor, achieved,
                        slipped, now * 1e-9)
        return simulator_status(name, hardware_id, pacing=pacing, force=force, torque=torque,
                                wrench_age=self._wrench.age(now),
                                wrench_timeout=config.wrench_timeout)
