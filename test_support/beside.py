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
Run a command with another beside it: a core the first leaves unused put to work.

``python -m test_support.beside --beside 'COMMAND' -- MAIN ...`` starts ``--beside`` (split as a
shell splits it) with its output in a temporary file, runs the main command in the foreground,
waits for both and prints the other's output after the main one's. Both run at the same
priority: beside a process of lower priority (nice 5 to 19, or SCHED_IDLE) this machine's kernel
let a waking 1 kHz loop wait about 100 ms for a core one to three times in 15 s, against at most
6 ms beside busy processes of its own priority. The exit status is the main command's, or if that
is 0 the other's. Ctrl-C reaches both (they stay in the terminal's process group); each ends its
own way, and this exits 130. ``make test`` runs the unit tier beside the tests marked alone with
it, in one process: one core kept busy, as ``make test-loaded`` keeps one.
"""

import argparse
import shlex
import subprocess
import sys
import tempfile
from typing import List

# Seconds each command has to end after Ctrl-C before it is killed.
GRACE = 30.0


def finish(process: subprocess.Popen) -> int:
    """Wait for ``process`` to end after Ctrl-C, killing it after GRACE; return its status."""
    try:
        return process.wait(timeout=GRACE)
    except subprocess.TimeoutExpired:
        process.kill()
        return process.wait()


def main(argv: List[str] = None) -> int:
    """Run the two commands; return the main command's status, or else the other's."""
    parser = argparse.ArgumentParser(description=__doc__.split('\n\n')[1])
    parser.add_argument('--beside', required=True,
                        help='the command run beside, as one string (shell quoting)')
    parser.add_argument('command', nargs=argparse.REMAINDER, help='the main command, after --')
    options = parser.parse_args(argv)
    command = options.command[1:] if options.command[:1] == ['--'] else options.command
    beside_command = shlex.split(options.beside)
    if not command or not beside_command:
        parser.error('both commands are needed: --beside COMMAND -- MAIN ...')
    with tempfile.TemporaryFile() as log:
        beside = subprocess.Popen(beside_command, stdin=subprocess.DEVNULL, stdout=log,
                                  stderr=subprocess.STDOUT)
        main_process = None
        try:
            main_process = subprocess.Popen(command)
            status = main_process.wait()
            other = beside.wait()
        except KeyboardInterrupt:
            for process in (main_process, beside):
                if process is not None:
                    finish(process)
            status = other = 130
        finally:
            if beside.poll() is None:
                beside.kill()
                beside.wait()
            sys.stdout.flush()
            log.seek(0)
            sys.stdout.buffer.write(log.read())
            sys.stdout.flush()
    return status or other


if __name__ == '__main__':
    sys.exit(main())
