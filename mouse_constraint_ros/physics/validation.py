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
Checks shared by the physics settings: each raises ValueError naming the field and the value.

The settings are frozen dataclasses that validate in ``__post_init__``, so an invalid value is
rejected before anything holds it and a running simulation never sees half an update. Messages
are one line and show values as plain numbers, lists and tuples, whatever container they came in
(rclpy hands double arrays over as ``array.array``, numpy as ``ndarray``).
"""

from collections.abc import Mapping, Set as AbstractSet
import math
from typing import Any, Iterable, Optional, Tuple


def shown(value: Any) -> str:
    """
    Return ``value`` as a message shows it: numbers and tuples of numbers plainly, on one line.

    A tuple is shown as a tuple and any other sized iterable but a string (a list,
    ``array.array``, ``ndarray``) as the list of its elements, each of them shown likewise;
    anything else (strings, mappings and sets too) as its ``repr``, with line breaks escaped.
    """
    if isinstance(value, (str, bytes, Mapping, AbstractSet)) or not hasattr(value, '__len__') \
            or not hasattr(value, '__iter__'):
        if isinstance(value, float) or type(value).__name__.startswith('float'):
            text = repr(float(value))
        elif type(value).__name__.startswith(('int', 'uint')) and not isinstance(value, bool):
            text = repr(int(value))
        else:
            text = repr(value)
        return text.replace('\r', '\\r').replace('\n', '\\n')
    try:
        items = [shown(v) for v in value]
    except TypeError:
        return repr(value).replace('\r', '\\r').replace('\n', '\\n')
    if isinstance(value, tuple):
        return '(' + ', '.join(items) + (',)' if len(items) == 1 else ')')
    return '[' + ', '.join(items) + ']'


def finite_vector(name: str, value: Iterable[float], size: int = 3) -> Tuple[float, ...]:
    """Return ``value`` as a tuple of ``size`` finite floats, or raise ValueError."""
    try:
        values = tuple(float(v) for v in value)
    except (TypeError, ValueError):
        raise ValueError(f'{name} must be {size} numbers, got {shown(value)}') from None
    if len(values) != size:
        raise ValueError(f'{name} must have {size} elements, got {len(values)}: {shown(value)}')
    if not all(math.isfinite(v) for v in values):
        raise ValueError(f'{name} must be finite, got {shown(values)}')
    return values


def scalar(
    name: str,
    value: float,
    *,
    above: Optional[float] = None,
    at_least: Optional[float] = None,
    at_most: Optional[float] = None,
    allow_inf: bool = False,
) -> float:
    """
    Return ``value`` as a float within the given bounds, or raise ValueError.

    :param name: the field's name, for the message.
    :param value: the number to check.
    :param above: exclusive lower bound.
    :param at_least: inclusive lower bound.
    :param at_most: inclusive upper bound.
    :param allow_inf: accept +inf (e.g. "unlimited"); NaN is never accepted.
    """
    try:
        number = float(value)
    except (TypeError, ValueError):
        raise ValueError(f'{name} must be a number, got {shown(value)}') from None
    if math.isnan(number) or (math.isinf(number) and not (allow_inf and number > 0.0)):
        raise ValueError(f'{name} must be finite, got {number!r}')
    if above is not None and not number > above:
        raise ValueError(f'{name} must be > {above!r}, got {number!r}')
    if at_least is not None and not number >= at_least:
        raise ValueError(f'{name} must be >= {at_least!r}, got {number!r}')
    if at_most is not None and not number <= at_most:
        raise ValueError(f'{name} must be <= {at_most!r}, got {number!r}')
    return number


def norm(vector: Tuple[float, ...]) -> float:
    """Return the Euclidean norm of finite ``vector``, without overflow for huge components."""
    return math.hypot(*vector)
