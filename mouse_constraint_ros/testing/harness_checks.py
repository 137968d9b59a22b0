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
What ``SimulatedBody`` refuses before it acts, each with one error that says why.

A context another harness uses (two harnesses in one context would read each other's topics
and take each other's inputs); a context that is not initialized or is shut down; an executor
other than a ``SingleThreadedExecutor`` of its context (the drain runs the callbacks it
finds ready, one by one, which an ``EventsExecutor`` has no way to do); a watchdog time that
is not a finite number of seconds > 0 (``nan`` would switch it off); a number of ticks that is
not a whole number >= 0 (``2.9`` is neither 2 nor 3); a stamp a ``builtin_interfaces/Time``
cannot hold (its seconds are an int32: 2^31 s and later would wrap); and any use of a closed
harness (``HarnessClosed``). ``predicate_text`` words a condition that never held.
"""

import inspect
import math
from numbers import Integral, Real
from typing import Callable
import weakref

from rclpy.context import Context
from rclpy.executors import SingleThreadedExecutor

# Stamps are from 0 up to this (s): the seconds of a builtin_interfaces/Time are an int32.
MAX_STAMP = float(2 ** 31)

# The contexts harnesses use, each with its harness.
_CLAIMS: 'weakref.WeakKeyDictionary' = weakref.WeakKeyDictionary()


def claim_context(context, harness) -> None:
    """
    Note that ``harness`` uses ``context``.

    :raises ValueError: another harness that is not closed uses it.
    """
    owner = _CLAIMS.get(context)
    if owner is not None and owner() is not None and owner() is not harness:
        raise ValueError('this context is already used by another SimulatedBody: two in one '
                         "context would read each other's pose and take each other's inputs; "
                         'close that one first, or give each its own context')
    _CLAIMS[context] = weakref.ref(harness)


def release_context(context, harness) -> None:
    """Note that ``harness`` no longer uses ``context`` (nothing if it did not claim it)."""
    owner = _CLAIMS.get(context)
    if owner is not None and owner() in (harness, None):
        del _CLAIMS[context]


def check_context(context) -> None:
    """
    Refuse what is not an initialized rclpy context.

    :raises TypeError: not an ``rclpy.context.Context``.
    :raises ValueError: not initialized, or shut down.
    """
    if not isinstance(context, Context):
        raise TypeError(f'context must be an rclpy Context, got {type(context).__name__}')
    if not context.ok():
        raise ValueError('context is not initialized or is shut down: call '
                         'rclpy.init(context=context) first, or give no context')


def check_executor(executor, context) -> None:
    """
    Refuse an executor the harness cannot drain, or one of another context.

    :raises TypeError: not a ``SingleThreadedExecutor``.
    :raises ValueError: its context is not ``context``.
    """
    if not isinstance(executor, SingleThreadedExecutor):
        raise TypeError('executor must be a SingleThreadedExecutor (the harness runs the '
                        f'callbacks it finds ready one by one), got {type(executor).__name__}')
    if executor.context is not context:
        raise ValueError("executor is of another context than the harness's: create it with "
                         'SingleThreadedExecutor(context=context)')


def checked_seconds(name: str, value) -> float:
    """
    Return a watchdog's wall seconds as a float.

    :raises TypeError: not a real number.
    :raises ValueError: not finite, or not > 0.
    """
    if isinstance(value, bool) or not isinstance(value, Real):
        raise TypeError(f'{name} must be a number of seconds, got {value!r}')
    if not math.isfinite(value) or value <= 0.0:
        raise ValueError(f'{name} must be finite and > 0 s, got {value!r}')
    return float(value)


def checked_ticks(name: str, value) -> int:
    """
    Return a number of ticks as an int.

    :raises TypeError: not a whole number (a float, a string, a bool).
    :raises ValueError: below 0.
    """
    if isinstance(value, bool) or not isinstance(value, Integral):
        raise TypeError(f'{name} must be a whole number of ticks, got {value!r}')
    if value < 0:
        raise ValueError(f'{name} must be >= 0, got {value!r}')
    return int(value)


def checked_stamp_ns(stamp) -> int:
    """
    Return a stamp given in simulated seconds as nanoseconds; None is 0 (no stamp).

    :raises TypeError: not a real number.
    :raises ValueError: not finite, below 0, or from ``MAX_STAMP`` on.
    """
    if stamp is None:
        return 0
    if isinstance(stamp, bool) or not isinstance(stamp, Real):
        raise TypeError(f'stamp must be a time in seconds, got {stamp!r}')
    if not math.isfinite(stamp) or not 0.0 <= stamp < MAX_STAMP:
        raise ValueError(f'stamp must be a finite time >= 0 s and below 2^31 s (a message '
                         f'stamp holds no more), got {stamp!r}')
    return min(round(stamp * 1e9), round(MAX_STAMP * 1e9) - 1)


def predicate_text(predicate: Callable) -> str:
    """Return the source of ``predicate`` on one line (at most 120 characters), or its name."""
    try:
        text = ' '.join(inspect.getsource(predicate).split())
    except (OSError, TypeError):
        text = getattr(predicate, '__qualname__', repr(predicate))
    return text if len(text) <= 120 else text[:117] + '...'
