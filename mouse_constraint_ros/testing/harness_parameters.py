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

"""The node's parameters as ``SimulatedBody`` takes them, as keywords, and their change."""

from typing import Any

import numpy as np
from rclpy.parameter import Parameter

from ..node.parameters import DEFAULTS, PARAMETERS
from ..node.startup import unknown_parameter_warnings

# The harness is the node's clock: these values would take that from it.
HARNESS_OWNS = {'publish_clock': False, 'use_sim_time': True}
# Wall seconds a new robot_description may take to load (the node loads it off the tick).
LOAD_TIMEOUT = 300.0


def parameter_value(name: str, value: Any) -> Any:
    """
    Return ``value`` as the node's parameter ``name`` takes it: ints as floats for doubles.

    Python writes ``2`` where YAML must write ``2.0``; here the intent is plain. Sequences
    (tuples, numpy arrays) become lists.

    :raises TypeError: ``name`` is none of the node's parameters or rclpy's (with the nearest
        one).
    """
    if name not in DEFAULTS:
        for warning in unknown_parameter_warnings([name], [], [p.name for p in PARAMETERS]):
            raise TypeError(warning.replace('ignoring unknown', 'unknown'))
        return value  # one of rclpy's own (use_sim_time ...)
    default = DEFAULTS[name]

    def number(item: Any) -> Any:
        if isinstance(item, (bool, np.bool_)):
            return bool(item)
        if isinstance(item, (int, float, np.integer, np.floating)):
            return float(item)
        return item

    if isinstance(default, float):
        return number(value)
    if isinstance(default, list) and isinstance(value, (list, tuple, np.ndarray)):
        return [number(item) for item in value]
    if isinstance(default, int) and not isinstance(default, bool) and isinstance(
            value, np.integer):
        return int(value)
    return value


def checked_parameters(parameters: dict) -> dict:
    """
    Return the parameters as the node takes them (``parameter_value``).

    :raises TypeError: an unknown name.
    :raises ValueError: a value that would take the clock from the harness.
    """
    values = {name: parameter_value(name, value) for name, value in parameters.items()}
    for name, taken in HARNESS_OWNS.items():
        if name in values and values[name] == taken:
            raise ValueError(f'{name}: {values[name]} would take the clock from the '
                             'harness, which steps the node on its simulated time')
    return values


def set_parameters(node, values: dict) -> None:
    """
    Change the parameters ``values`` of ``node`` all or none; a new body is loaded before return.

    The node loads a new body (``robot_description``, ``body_link``, ``density``) off its tick
    (``node.body_loads``); here it is waited for, at most ``LOAD_TIMEOUT`` wall seconds, and
    swapped in or refused, so that the harness's next step runs with it.

    :raises TypeError: an unknown name.
    :raises ValueError: the node refused the change (or the body), with its reason; a value that
        would take the clock from the harness.
    :raises TimeoutError: the body did not load in time.
    """
    checked = checked_parameters(values)
    result = node.set_parameters_atomically(
        [Parameter(name, value=value) for name, value in checked.items()])
    if not result.successful:
        raise ValueError(result.reason)
    loads = node.body_loads
    if not loads.wait(LOAD_TIMEOUT):
        raise TimeoutError(f'the body did not load within {LOAD_TIMEOUT:g} s')
    reason = loads.finish()
    if reason is not None:
        raise ValueError(reason)
