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

rclpy checks a change against the declared type and range before the node's own callback sees
it, and refuses it in its words ("Wrong parameter type, expected 'Type.INTEGER'", "out of range
Min: 0.0, Max: 1.797e308"). ``declare`` has such refusals say the node's reason instead, the
one start-up gives for the same value (``refusal_reason``): one wording for every way in.
"""

from typing import Iterable, Optional

from rcl_interfaces.msg import FloatingPointRange, IntegerRange, ParameterDescriptor
from rclpy.exceptions import ParameterException
from rclpy.node import Node
from rclpy.parameter import Parameter

from .parameters import NodeConfig, ParameterSpec
from .startup import refusal_reason, value_type


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
    Declare ``parameters`` on ``node``; a change rclpy refuses is then refused in its words.

    :raises ValueError: one line naming the parameter whose given value rclpy refuses.
    """
    parameters = tuple(parameters)
    for parameter in parameters:
        try:
            node.declare_parameter(parameter.name, parameter.default, descriptor(parameter))
        except ParameterException as error:
            # rclpy keeps the given values there; it has no public getter for them.
            given = node._parameter_overrides.get(parameter.name)
            raise ValueError(refusal_reason(parameter, error, None if given is None else (
                given.value, given.type_.name))) from None
    _reword_refusals(node, {parameter.name: parameter for parameter in parameters})


def _reword_refusals(node: Node, declared: dict) -> None:
    """Give rclpy's refusals of a type or a range the node's reason (see the module)."""
    check = getattr(node, '_apply_descriptor', None)
    if check is None:  # Another rclpy: its own words stay.
        return

    def checked(parameter: Parameter, *args, **kwargs):
        result = check(parameter, *args, **kwargs)
        if not result.successful:
            reason = _reason(node, declared, parameter)
            if reason is not None:
                result.reason = reason
        return result
    node._apply_descriptor = checked


def _reason(node: Node, declared: dict, parameter: Parameter) -> Optional[str]:
    """Return the node's reason to refuse ``parameter``'s type or range, None for another."""
    declaration = declared.get(parameter.name)
    kind = parameter.type_.name
    if declaration is None or kind == 'NOT_SET':
        return None
    value = parameter.value
    if kind == value_type(declaration.default):
        if declaration.bounds is None:
            return None
        low, high = declaration.bounds
        if not isinstance(value, (int, float)) or low <= value <= high:
            return None  # In range: refused for another reason, said by rclpy.
    values = {name: node.get_parameter(name).value for name in declared
              if node.has_parameter(name)}
    return refusal_reason(declaration, '', (value, kind), values)


def publishing(config: NodeConfig) -> dict:
    """Return what the state publishers are configured with."""
    return {'frame_id': config.frame_id, 'body_frame_id': config.body_frame_id,
            'publish_tf': config.publish_tf, 'publish_odometry': config.publish_odometry,
            'publish_force': config.publish_force, 'body_frame': config.body_frame,
            'force_output': config.device.force_output, 'force_frame_id': config.device.frame_id,
            'device_map': config.device.mapping}
