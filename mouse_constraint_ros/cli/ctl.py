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
The ``mouse_ctl`` command: the node's services and output from the venv's command line.

``ros2 service call`` and ``ros2 topic echo`` need ros2cli, which is not on PyPI; ``mouse_ctl``
does what a user needs of them with the node, from the venv alone:

- ``mouse_ctl pause`` / ``resume``: ``~/pause`` with true / false;
- ``mouse_ctl step [N]``: ``~/step`` N times (default 1), while paused; each request is sent
  once and its answer waited for (``--timeout``), never sent again: a slow answer is not a
  second step;
- ``mouse_ctl reset`` / ``release``: ``~/reset`` / ``~/release``;
- ``mouse_ctl echo [pose|twist|force|wrench|inputs]``: a line per message (at most
  ``--print-rate`` a second of the node's clock), with the rate the messages come at; ``force``
  is the force the pointer feels (with ``publish_force``), ``wrench`` the pushes on the node's
  ``wrench`` input, ``inputs`` the node's inputs status on /diagnostics (the inputs it refused,
  by reason, the last one's line, and whether a device on ``target_pose`` is heard or silent).
  Until Ctrl-C, or ``--count`` lines.

A call prints the node's reply and exits 0; a reply that says the node could not (``step``
while running, a ``reset`` it could not make) goes to stderr with exit status 1, as does no
service or no message within ``--timeout``; an echo that got none says why, as the graph tells
it (no node, a topic nothing publishes, a node paused). The node is ``--node`` (default
``mouse_constraint``) in this command's namespace: ``--ros-args -r __ns:=/robot`` reaches one
in ``/robot``. Ctrl-C ends an echo with exit status 0, a call before its answer with 130, and
any command with 130 before it started (its imports, rclpy's start: ``console``, the console
script).
"""

import argparse
import math
import sys
import time
from typing import Callable, List, NamedTuple, Optional

from diagnostic_msgs.msg import DiagnosticArray
from rcl_interfaces.msg import ParameterType
from rcl_interfaces.srv import ListParameters
from rclpy.executors import ExternalShutdownException
from rclpy.node import Node
from rclpy.utilities import remove_ros_args
from std_srvs.srv import SetBool, Trigger

from .command_node import command_node, SHUTDOWN_STATUS
from .echo import ECHOES, EchoPrinter, Graph, paused_in, silence
from .echo_inputs import InputsPrinter
from .exit_status import INTERRUPTED_STATUS
from .help_text import plain_text
from ..timing.spin import (call_once, call_until_answered, Interrupted, spin_until, StopRequest,
                           wait_until)
from ..wire.interface import (DIAGNOSTICS_TOPIC, MONITOR_DEPTH, NODE_NAME, node_name,
                              PAUSE_SERVICE, RELEASE_SERVICE, RESET_SERVICE, STATE_QOS,
                              STEP_SERVICE)
from ..wire.remote_parameters import fetch_parameters

# The most steps one command makes.
MAX_STEPS = 1_000_000
# The longest (s) an echo that got no message waits for the node to say whether it is on.
SWITCH_TIMEOUT = 2.0


class Action(NamedTuple):
    """
    A call of one of the node's services: its type, its name (``~/...``) and request.

    ``once``: a request served twice does twice what was asked (a step), so it is sent once
    and waited for, never sent again while it goes unanswered.
    """

    service_type: type
    service: str
    request: Callable[[], object]
    once: bool = False


ACTIONS = {
    'pause': Action(SetBool, PAUSE_SERVICE, lambda: SetBool.Request(data=True)),
    'resume': Action(SetBool, PAUSE_SERVICE, lambda: SetBool.Request(data=False)),
    'step': Action(Trigger, STEP_SERVICE, Trigger.Request, once=True),
    'reset': Action(Trigger, RESET_SERVICE, Trigger.Request),
    'release': Action(Trigger, RELEASE_SERVICE, Trigger.Request),
}


def service_name(target_node: str, action: str) -> str:
    """Return the name of ``action``'s service of ``target_node`` (relative: namespaces apply)."""
    return f'{target_node}/{ACTIONS[action].service.removeprefix("~/")}'


def create_client(node: Node, action: str, target_node: str = NODE_NAME):
    """Return a client of ``node`` for ``action``'s service of ``target_node``."""
    return node.create_client(ACTIONS[action].service_type, service_name(target_node, action))


def create_echo(node: Node, what: str, write: Callable[[str], None], *, print_rate: float,
                target_node: str = NODE_NAME) -> EchoPrinter:
    """
    Return the printer of ``what`` (``ECHOES``), its raw subscription made on ``node``.

    ``inputs`` prints the inputs status of ``target_node`` (in ``node``'s namespace) from
    /diagnostics, a line per report.
    """
    if what == 'inputs':
        inputs = InputsPrinter(node_name(node.get_namespace(), target_node), write)
        inputs.topic = node.create_subscription(DiagnosticArray, DIAGNOSTICS_TOPIC, inputs.take,
                                                STATE_QOS).topic_name
        return inputs
    echo = ECHOES[what]
    printer = EchoPrinter(echo, write, print_rate=print_rate)
    printer.topic = node.create_subscription(echo.message_type, echo.topic, printer.take,
                                             STATE_QOS, raw=True).topic_name
    return printer


def _positive(name: str, allow_zero: bool = False):
    def parse(text: str) -> float:
        value = float(text)
        if not math.isfinite(value) or value < 0.0 or (value == 0.0 and not allow_zero):
            raise argparse.ArgumentTypeError(
                f'{name} must be finite and {">=" if allow_zero else ">"} 0, got {text}')
        return value
    return parse


def _steps(text: str) -> int:
    if not text.isdigit() or not 1 <= int(text) <= MAX_STEPS:
        raise argparse.ArgumentTypeError(f'N must be a whole number in [1, {MAX_STEPS}], '
                                         f'got {text}')
    return int(text)


def build_parser() -> argparse.ArgumentParser:
    """Return the command's argument parser; every option's help names its default."""
    parser = argparse.ArgumentParser(
        prog='mouse_ctl', description=plain_text(__doc__.split('\n\n')[0]),
        epilog='examples: mouse_ctl pause | mouse_ctl step 10 | mouse_ctl echo pose --count 5'
               ' | add --ros-args -r __ns:=/robot for a namespaced node')
    # --node and --timeout before the command or after it: the command's copy has no default,
    # so that it leaves the one given before alone.
    common = argparse.ArgumentParser(add_help=False)
    for target, node, timeout in ((parser, NODE_NAME, 10.0),
                                  (common, argparse.SUPPRESS, argparse.SUPPRESS)):
        target.add_argument('--node', default=node,
                            help=f'the node to call and follow (default: {NODE_NAME}, in this '
                                 'namespace)')
        target.add_argument('--timeout', type=_positive('--timeout'), default=timeout,
                            help='seconds to wait for the service and each answer, or for the '
                                 'first message (default: 10)')
    commands = parser.add_subparsers(dest='command', required=True, metavar='COMMAND')
    commands.add_parser('pause', parents=[common], help='pause the physics (~/pause true)')
    commands.add_parser('resume', parents=[common],
                        help='resume it, without catching up (~/pause false)')
    step = commands.add_parser('step', parents=[common],
                               help='advance a paused node N ticks (~/step)')
    step.add_argument('ticks', nargs='?', type=_steps, default=1, metavar='N',
                      help='ticks to advance (default: %(default)s)')
    commands.add_parser('reset', parents=[common], help='back to the initial state (~/reset)')
    commands.add_parser('release', parents=[common],
                        help='drop the target: the body flies free (~/release)')
    echo = commands.add_parser('echo', parents=[common],
                               help='print pose, twist, force or wrench with their rate')
    echo.add_argument('what', nargs='?', choices=sorted([*ECHOES, 'inputs']), default='pose',
                      help='what to print (default: %(default)s; force: the force the pointer '
                           'feels, with publish_force; wrench: the wrench input; inputs: the '
                           "inputs refused and the device's state, from /diagnostics)")
    echo.add_argument('--count', type=int, default=0,
                      help='lines to print before exiting (default: 0, until Ctrl-C)')
    echo.add_argument('--print-rate', type=_positive('--print-rate', True), default=10.0,
                      help="most lines a second of the node's clock; 0: every message "
                           '(default: %(default)g)')
    return parser


def parse_arguments(argv: List[str]) -> argparse.Namespace:
    """Return the command's options from ``argv`` (ROS arguments already removed)."""
    parser = build_parser()
    options = parser.parse_args(argv)
    if options.command == 'echo' and options.count < 0:
        parser.error(f'--count must be >= 0, got {options.count}')
    return options


def node_answers(node: Node, executor, stop: StopRequest, options: argparse.Namespace) -> bool:
    """
    Return whether the node answered its ``list_parameters``, asked again while unanswered.

    Made after the action's client: a node that answered has matched that client's endpoints
    too (``timing.spin``), and a request sent once on it reaches the node.
    """
    client = node.create_client(ListParameters, f'{options.node}/list_parameters')
    try:
        return call_until_answered(client, ListParameters.Request(depth=1), executor, stop,
                                   deadline=time.monotonic() + options.timeout) is not None
    finally:
        node.destroy_client(client)


def switched_on(node: Node, executor, stop: StopRequest, options: argparse.Namespace,
                target: str) -> Optional[bool]:
    """Return the value of the echo's ``switch`` parameter on ``target``; None: not known."""
    switch = ECHOES[options.what].switch
    if switch is None:
        return None
    try:
        return fetch_parameters(node, executor, stop, target_node=target, timeout=SWITCH_TIMEOUT,
                                types={switch: ParameterType.PARAMETER_BOOL})[switch]
    except RuntimeError:
        return None


def call(node: Node, executor, stop: StopRequest, options: argparse.Namespace) -> int:
    """Call the node's service ``options.command`` (``step``: N times); return the exit status."""
    client = create_client(node, options.command, options.node)
    name = node.resolve_service_name(client.srv_name)
    if not wait_until(executor, stop, client.service_is_ready,
                      deadline=time.monotonic() + options.timeout):
        print(f'mouse_ctl: no service {name} after {options.timeout:g} s: is the '
              'node running (same ROS_DOMAIN_ID and namespace, --node)?', file=sys.stderr)
        return 1
    action = ACTIONS[options.command]
    if action.once and not node_answers(node, executor, stop, options):
        print(f'mouse_ctl: {options.node} did not answer in {options.timeout:g} s',
              file=sys.stderr)
        return 1
    send = call_once if action.once else call_until_answered
    for _ in range(getattr(options, 'ticks', 1)):
        response = send(client, action.request(), executor, stop,
                        deadline=time.monotonic() + options.timeout)
        if response is None:
            print(f'mouse_ctl: {name} did not answer in {options.timeout:g} s'
                  + (': the request was sent once, it may have been served' if action.once
                     else ''), file=sys.stderr)
            return 1
        if not response.success:
            print(f'mouse_ctl: {options.command}: {response.message}', file=sys.stderr)
            return 1
        print(response.message, flush=True)
    return 0


def echo(node: Node, executor, stop: StopRequest, options: argparse.Namespace) -> int:
    """Print the messages until Ctrl-C or ``--count`` lines; return the exit status."""
    printer = create_echo(node, options.what, lambda line: print(line, flush=True),
                          print_rate=options.print_rate, target_node=options.node)
    topic = printer.topic
    target = options.node if options.node.startswith('/') else node_name(
        node.get_namespace(), options.node)
    # Whether the node is paused, as its /diagnostics said last while the echo waited.
    paused: List[Optional[bool]] = [None]

    def on_diagnostics(array: DiagnosticArray) -> None:
        said = paused_in(array, target)
        if said is not None:
            paused[0] = said
    diagnostics = node.create_subscription(DiagnosticArray, DIAGNOSTICS_TOPIC, on_diagnostics,
                                           MONITOR_DEPTH)
    try:
        if not wait_until(executor, stop, lambda: printer.received > 0,
                          deadline=time.monotonic() + options.timeout):
            found = target in (node_name(namespace, name) for name, namespace in
                               node.get_node_names_and_namespaces())
            graph = Graph(target, found, node.count_publishers(topic), paused[0],
                          switched_on(node, executor, stop, options, target) if found else None)
            print('mouse_ctl: ' + silence(ECHOES[options.what], topic, options.timeout, graph),
                  file=sys.stderr)
            return 1
    except Interrupted:
        return 0
    node.destroy_subscription(diagnostics)
    count = options.count
    spin_until(executor, stop, condition=lambda: 0 < count <= printer.printed)
    if printer.unreadable:
        print(f'mouse_ctl: {printer.unreadable} messages on {topic} were not readable',
              file=sys.stderr)
    return 0


def main(args: Optional[List[str]] = None) -> int:
    """Run one command; return its exit status (see the module)."""
    argv = sys.argv if args is None else args
    options = parse_arguments(remove_ros_args(argv)[1:])
    try:
        with command_node('mouse_ctl', argv, start_parameter_services=False) as (
                node, executor), StopRequest() as stop:
            if options.command == 'echo':
                return echo(node, executor, stop, options)
            return call(node, executor, stop, options)
    except Interrupted:
        return INTERRUPTED_STATUS
    except ExternalShutdownException:
        return SHUTDOWN_STATUS


if __name__ == '__main__':
    sys.exit(main())
