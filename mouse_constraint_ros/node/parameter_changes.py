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
The node's parameters in rclpy: their declaration with ranges, and the state publishers' share.

``parameters`` validates a whole configuration; here each parameter is declared with its
description and range (``declare``); ``publishing`` is what the state publishers are
configured with, so that the node gives them a change only when their share changed.
"""

from typing import Iterable

from rcl_interfaces.msg import FloatingPointRange, IntegerRange, ParameterDescriptor
from rclpy.exceptions import ParameterException
from rclpy.node import Node

from .parameters import NodeConfig, ParameterSpec
from .startup import refusal_reason


def descriptor(parameter: ParameterSpec) -> ParameterDescriptor:
    """Return the descriptor of ``parameter``: its description and range, if any."""
    result = ParameterDescriptor(description=parameter.description)
    if parameter.bounds is not None:
        low, high = parameter.bounds
        if isinstance(parameter.default, int) and not isinstance(parameter.default, bool):
            result.integer_range = [IntegerRange(from_value=low, to_value=high, step=0)]
        else:
            result.floating_point_range = [
                FloatingPointRange(from_value=float(low), to_value=float(high), step=0.0)]
    return result


def declare(node: Node, parameters: Iterable[ParameterSpec]) -> None:
    """
    Declare ``parameters`` on ``node``.

    :raises ValueError: one line naming the parameter whose given value rclpy refuses.
    """
    for parameter in parameters:
        try:
            node.declare_parameter(parameter.name, parameter.default, descriptor(parameter))
        except ParameterException as error:
            # rclpy keeps the given values there; it has no public getter for them.
            given = node._parameter_overrides.get(parameter.name)
            raise ValueError(refusal_reason(parameter, error, None if given is None else (
                given.value, given.type_.name))) from None


def publishing(config: NodeConfig) -> dict:
    """Return what the state publishers are configured with."""
    return {'frame_id': config.frame_id, 'body_frame_id': config.body_frame_id,
            'publish_tf': config.publish_tf, 'publish_odometry': config.publish_odometry,
            'publish_force': config.publish_force}
