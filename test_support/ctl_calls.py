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

"""``mouse_ctl``'s commands called in-process, on a simulated body's executor."""

from mouse_constraint_ros.cli import ctl
from mouse_constraint_ros.timing.spin import StopRequest


def options(command: str, **values):
    """Return the parsed options of ``mouse_ctl COMMAND``, with ``values`` set."""
    parsed = ctl.parse_arguments([command])
    for name, value in values.items():
        setattr(parsed, name, value)
    return parsed


def run_call(body, caller, command: str, capsys, **values):
    """Run the command's ``call`` on the body's executor; return (status, stdout, stderr)."""
    with StopRequest() as stop:
        status = ctl.call(caller, body.executor, stop, options(command, **values))
    out, err = capsys.readouterr()
    return status, out, err
