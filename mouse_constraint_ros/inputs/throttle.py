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
Throttled warnings: at most one line per period for each reason, counting the ones held back.

The node logs a warning for each bad input it ignores and for each missed rate; a flood of
them must neither flood the log nor cost the node its rate. ``Throttle`` logs the first
warning of a reason, then holds back the others of that reason for ``period`` seconds and says
how many it held back in the next line it logs. The message is a callable, built only when it
is logged. Pure Python: it takes the log function and the clock, so it runs without rclpy.

``RefusalLog`` warns about each refused input through a throttle and keeps the count, the count
of each reason's key and the last refusal with its line, for a caller in the same process that
wants to know why an input changed nothing (``mouse_constraint_ros.testing`` raises with it) and
for /diagnostics, which says it to whoever sends the input.

Throttled here rather than by rclpy's ``throttle_duration_sec``, which inspects the caller's
frame on every call (some 100 us: a flood of bad targets then cost the node its rate) and
shares one throttle between all the warnings of one call site.
"""

import math
import time
from typing import Callable, Dict, Optional, Tuple

from .target_gate import Refusal


class Throttle:
    """
    Log at most once per ``period`` for each reason, and count what was held back.

    :param log: takes one line and logs it (e.g. the node logger's ``warning``).
    :param period: the least time (s, of ``clock``) between two lines of one reason.
    :param clock: returns the time in seconds; monotonic, so that clock jumps do not matter.
    """

    def __init__(self, log: Callable[[str], object], *, period: float,
                 clock: Callable[[], float] = time.monotonic) -> None:
        """Start with nothing logged for any reason."""
        self._log = log
        self._period = period
        self._clock = clock
        # Per reason: when it was last logged and how many were held back since.
        self._last: Dict[str, Tuple[float, int]] = {}

    def __call__(self, reason: str, message: Callable[[], str]) -> bool:
        """
        Log ``message()`` unless ``reason`` was logged less than ``period`` ago.

        A line that follows held-back ones ends with ``(N more since the last one)``.

        :param reason: the key of the throttle; each reason has its own.
        :param message: returns the line; called only when it is logged.
        :returns: whether it was logged.
        """
        now = self._clock()
        last, held_back = self._last.get(reason, (-math.inf, 0))
        if now - last < self._period:
            self._last[reason] = (last, held_back + 1)
            return False
        more = f' ({held_back} more since the last one)' if held_back else ''
        self._log(message() + more)
        self._last[reason] = (now, 0)
        return True


class RefusalLog:
    """
    The inputs refused: how many, and the last one; each is warned about under its key.

    :param warn: ``warn(key, message)`` with ``message()`` the line, e.g. a ``Throttle``.
    """

    def __init__(self, warn: Callable[[str, Callable[[], str]], object]) -> None:
        """Start with none refused."""
        self._warn = warn
        self.count = 0
        self.last: Optional[Refusal] = None
        self.last_line = ''
        self.by_key: Dict[str, int] = {}

    def __call__(self, refusal: Refusal, line: str) -> None:
        """Count ``refusal`` and warn ``line`` (throttled under ``refusal.key``)."""
        self.count += 1
        self.last, self.last_line = refusal, line
        self.by_key[refusal.key] = self.by_key.get(refusal.key, 0) + 1
        self._warn(refusal.key, lambda: line)
