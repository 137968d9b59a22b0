"""
Ctrl-C, SIGTERM and SIGHUP as a request to stop, for the executables' spin loops.

rclpy's own handlers shut the context down from the signal, while a timer callback may be
publishing: the publish then raises with a traceback. Here the signal only sets a flag; the
spin loop sees it within one ``spin_once`` timeout and the node is torn down in order. SIGHUP
(the terminal closed) ends the node like SIGTERM: Python's default for it kills the process with
no clean-up.
"""

import signal
from types import FrameType
from typing import Optional

STOP_SIGNALS = (signal.SIGINT, signal.SIGTERM, signal.SIGHUP)


class StopRequest:
    """Install handlers for STOP_SIGNALS that record the request; restore them on exit."""

    def __init__(self) -> None:
        """Create the request, not yet installed."""
        self.signal: Optional[int] = None
        self._previous = {}

    def __bool__(self) -> bool:
        """Return whether a stop was requested."""
        return self.signal is not None

    def _handle(self, signum: int, _frame: Optional[FrameType]) -> None:
        self.signal = signum

    def __enter__(self) -> 'StopRequest':
        """Install the handlers."""
        for signum in STOP_SIGNALS:
            self._previous[signum] = signal.signal(signum, self._handle)
        return self

    def __exit__(self, *_exception) -> None:
        """Restore the previous handlers."""
        for signum, handler in self._previous.items():
            signal.signal(signum, handler)
