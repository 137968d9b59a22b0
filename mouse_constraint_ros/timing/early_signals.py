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
A console script's stop signals, before its program is imported and after it returned.

Importing a program of the package (rclpy, numpy, the message packages) and ``rclpy.init``
take some tenths of a second before the program's ``StopRequest`` (``spin``) takes Ctrl-C,
SIGTERM and SIGHUP; until then Python's defaults answer SIGINT with a KeyboardInterrupt
traceback and SIGTERM and SIGHUP with death by the signal. ``take_early`` has each of them end
the process at once instead, its output flushed, with the status (and the one line) the program
gives for a stop that came before it did anything; ``StopRequest`` puts these handlers back
when it is left, so that a signal during the program's teardown ends it so too.

``ignore`` is for after the program returned, torn down: for the interpreter's own exit, some
tenths of a second of finalization, Python puts back the default handler (death by the signal)
of every signal it handled, so that a second signal soon after the first would end a clean stop
with -2 or -15; an ignored signal stays ignored.

Standard library only: this module must load in no time.
"""

import os
import signal
import sys

STOP_SIGNALS = (signal.SIGINT, signal.SIGTERM, signal.SIGHUP)


def take_early(status: int, line: str = '') -> None:
    """
    Have each of STOP_SIGNALS end the process at once with ``status``.

    :param line: written to stderr first (with the signal's name for ``{signal}``), if any.
    """
    def stop(signum: int, _frame) -> None:
        if line:
            try:
                sys.stderr.write(line.format(signal=signal.Signals(signum).name) + '\n')
            except (OSError, ValueError):
                pass
        for stream in (sys.stdout, sys.stderr):
            try:
                stream.flush()
            except (OSError, ValueError):
                pass
        os._exit(status)

    for signum in STOP_SIGNALS:
        signal.signal(signum, stop)


def ignore() -> None:
    """Ignore STOP_SIGNALS from now on: the program has returned, nothing is left to stop."""
    for signum in STOP_SIGNALS:
        signal.signal(signum, signal.SIG_IGN)
