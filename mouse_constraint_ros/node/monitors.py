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
``diagnostics`` modules from the simulation's data; here are their timers and inputs.
"""

import math
import time

from diagnostic_msgs.msg import DiagnosticArray
from visualization_msgs.msg import MarkerArray

from ..inputs.input_timeouts import input_age
from ..monitoring.diagnostics import (constraint_status, diagnostic_array, INITIAL_ANCHOR,
                                      NO_TARGET, Pacing, publishing_values, rate_status,
                                      simulator_status, Thresholds, TickCounters, TickWindow,
                                      USER_TARGET)
from ..monitoring.markers import marker_array, reference_force, wrench_reference
from ..physics.simulation import force_bound
from ..wire.interface import DIAGNOSTICS_TOPIC, MARKERS_TOPIC, MONITOR_DEPTH


class Monitors:
    """The marker and diagnostics timers of ``MouseConstraintNode``."""

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

    def _publish_markers(self) -> None:
        """Publish the markers of the latest tick, with its stamp."""
        simulation = self._simulation
        self._marker_publisher.publish(marker_array(
            frame_id=self._config.frame_id, stamp_ns=self._stamp_ns,
            box_size=self._config.box_size, state=simulation.state,
            anchor=simulation.anchor_position(), target=simulation.target,
            force=simulation.constraint_force, reference=reference_force(simulation.settings),
            wrench_force=simulation.wrench[0],
            wrench_reference=wrench_reference(simulation.settings),
            floor=simulation.settings.floor,
            contacts=[point for point, _ in simulation.contacts]))

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
                              thresholds=thresholds,
                              floor_contacts=(simulation.contact_count
                                              if config.settings.floor.enabled else None)),
            self._simulator_status(f'{name}: simulator', hardware_id, now),
        ]))
