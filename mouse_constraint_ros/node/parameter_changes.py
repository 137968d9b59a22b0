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
The node's parameters: their declaration with ranges, and the changes ``ros2 param set`` makes.

``parameters`` validates a whole configuration; here each change is applied to the parts it
concerns (the gate, the state publishers, the tick timer, the simulated clock, the monitor
timers), and a change that ``node_config`` or ``clock_loop`` refuses changes nothing.
"""

from typing import List

from rcl_interfaces.msg import (FloatingPointRange, IntegerRange, ParameterDescriptor,
                                SetParametersResult)
from rclpy.exceptions import ParameterException
from rclpy.parameter import Parameter

from .parameters import node_config, PARAMETERS, ParameterSpec
from .startup import clock_loop, refusal_reason
from ..inputs.target_gate import TargetGate
from ..physics.validation import shown
from ..timing.publish_ticks import PublishTicks, ticks_per_callback


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


class ParameterChanges:
    """The parameter declaration and change handling of ``MouseConstraintNode``."""

    def _declare(self, parameter: ParameterSpec) -> None:
        try:
            self.declare_parameter(parameter.name, parameter.default, _descriptor(parameter))
        except ParameterException as error:
            given = self._parameter_overrides.get(parameter.name)
            raise ValueError(refusal_reason(parameter, error, None if given is None else (
                given.value, given.type_.name))) from None

    def _parameter_values(self, changes: List[Parameter] = ()) -> dict:
        values = {p.name: self.get_parameter(p.name).value for p in PARAMETERS}
        values.update((p.name, p.value) for p in changes)
        return values

    @staticmethod
    def _publishing(config) -> dict:
        return {'frame_id': config.frame_id, 'body_frame_id': config.body_frame_id,
                'publish_tf': config.publish_tf, 'publish_odometry': config.publish_odometry}

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
        self._simulation.configure(config.settings, config.initial_state)
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
        if self._setting_anchor:
            # A grab or a reset: one short line, at most every WARN_PERIOD (grabs can flood).
            anchor = config.settings.constraint.anchor
            self._notes('anchor', lambda: f'anchor {shown(anchor)} m (body frame), set by the '
                                          'node')
        else:
            self.get_logger().info('parameters changed: ' + self._describe())
        return SetParametersResult(successful=True)
