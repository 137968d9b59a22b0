"""
Checks shared by the physics settings: each raises ValueError naming the field and the value.

The settings are frozen dataclasses that validate in ``__post_init__``, so an invalid value is
rejected before anything holds it and a running simulation never sees half an update.
"""

import math
from typing import Iterable, Optional, Tuple


def finite_vector(name: str, value: Iterable[float], size: int = 3) -> Tuple[float, ...]:
    """Return ``value`` as a tuple of ``size`` finite floats, or raise ValueError."""
    try:
        values = tuple(float(v) for v in value)
    except (TypeError, ValueError):
        raise ValueError(f'{name} must be {size} numbers, got {value!r}') from None
    if len(values) != size:
        raise ValueError(f'{name} must have {size} elements, got {len(values)}: {value!r}')
    if not all(math.isfinite(v) for v in values):
        raise ValueError(f'{name} must be finite, got {values!r}')
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
        raise ValueError(f'{name} must be a number, got {value!r}') from None
    if math.isnan(number) or (math.isinf(number) and not (allow_inf and number > 0.0)):
        raise ValueError(f'{name} must be finite, got {number!r}')
    if above is not None and not number > above:
        raise ValueError(f'{name} must be > {above}, got {number!r}')
    if at_least is not None and not number >= at_least:
        raise ValueError(f'{name} must be >= {at_least}, got {number!r}')
    if at_most is not None and not number <= at_most:
        raise ValueError(f'{name} must be <= {at_most}, got {number!r}')
    return number
