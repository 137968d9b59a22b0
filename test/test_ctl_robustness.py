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
``mouse_ctl`` where things go wrong: a slow answer, a silent topic, an early Ctrl-C.

A step slow to answer is served once; an echo that gets nothing says why (no node, a topic
nothing publishes or switched off, a paused node); Ctrl-C while the command starts is exit 130
with nothing said. In lockstep where the node takes part, as a process for the command line.
"""

from pathlib import Path
import signal
import subprocess
import sys
import threading
import time

import pytest
import rclpy
from rclpy.executors import SingleThreadedExecutor
from rclpy.node import Node
from std_srvs.srv import Trigger

from mouse_constraint_ros.cli import ctl
from mouse_constraint_ros.cli.echo import ECHOES, Graph, silence
from mouse_constraint_ros.timing.spin import StopRequest
from test_support.ctl_calls import options, run_call

BIN = Path(sys.executable).parent
# The installed script where the venv has it, else the module it runs.
COMMAND = ([str(BIN / 'mouse_ctl')] if (BIN / 'mouse_ctl').is_file()
           else [sys.executable, '-m', 'mouse_constraint_ros.cli.console'])


@pytest.fixture
def slow_node():
    """
    Yield a node ``mouse_constraint`` of another context whose ``~/step`` answers 1.5 s late.

    Its executor spins in a thread of its own, as the node would in its own process; what it
    served is the list ``served``.
    """
    context = rclpy.Context()
    rclpy.init(context=context)
    node = Node('mouse_constraint', context=context)
    node.served = []

    def step(_request, response):
        node.served.append(None)
        time.sleep(1.5)  # not a wait: the late answer under test
        response.success = True
        response.message = f'step {len(node.served)}'
        return response
    node.create_service(Trigger, '~/step', step)
    executor = SingleThreadedExecutor(context=context)
    executor.add_node(node)
    thread = threading.Thread(target=executor.spin, daemon=True)
    thread.start()
    yield node
    executor.shutdown()
    thread.join(timeout=10.0)
    node.destroy_node()
    rclpy.try_shutdown(context=context)


def test_a_step_slow_to_answer_is_served_once(ros, slow_node, capsys):
    """
    Step 2 on a node whose every answer takes 1.5 s: two steps served, each reply printed.

    Longer than a request of another command goes unanswered before it is sent again; a step
    sent again would be a step more.
    """
    with StopRequest() as stop:
        status = ctl.call(ros.probe, ros.executor, stop, options('step', ticks=2))
    out, err = capsys.readouterr()
    assert (status, out, err) == (0, 'step 1\nstep 2\n', '')
    assert len(slow_node.served) == 2


def run_echo(body, caller, what: str, capsys, timeout: float):
    """Run the command's ``echo`` of ``what`` on the body's executor; return (status, stderr)."""
    with StopRequest() as stop:
        status = ctl.echo(caller, body.executor, stop, options('echo', what=what,
                                                               timeout=timeout))
    return status, capsys.readouterr().err


def test_echo_says_why_nothing_came(simulated_body_factory, capsys):
    """
    A paused node: paused, as its /diagnostics say; force with publish_force false: off.

    Off as the node's parameter says, whether its publisher was never made or stays silent.
    Neither is "is the node running?": the node is there, the graph and /diagnostics say so.
    """
    body = simulated_body_factory(diagnostics_rate_hz=20.0)
    caller = body.add_node(Node('mouse_ctl', context=body.context))
    body.step(3)
    assert run_call(body, caller, 'pause', capsys)[0] == 0
    assert run_echo(body, caller, 'pose', capsys, 1.0) == (1, (
        'mouse_ctl: no message on /pose after 1 s: /mouse_constraint is paused: it publishes '
        '/pose again once resumed (mouse_ctl resume) or stepped (mouse_ctl step)\n'))
    off = ('mouse_ctl: no message on /force after 0.5 s: /mouse_constraint has publish_force '
           'false: it publishes /force once it is true\n')
    assert run_echo(body, caller, 'force', capsys, 0.5) == (1, off)
    body.set_parameters(publish_force=True)
    body.set_parameters(publish_force=False)  # its publisher stays, silent
    assert run_echo(body, caller, 'force', capsys, 0.5) == (1, off)


@pytest.mark.parametrize('what, graph, reason', [
    ('pose', Graph('/robot/mouse_constraint', False, 0),
     'no node /robot/mouse_constraint: is the node running (same ROS_DOMAIN_ID and namespace, '
     '--node)?'),
    ('pose', Graph('/mouse_constraint', True, 1, False),
     '/pose has 1 publisher, none sent a message: its clock may stand still (use_sim_time: no '
     '/clock)'),
    ('pose', Graph('/mouse_constraint', True, 2),
     '/pose has 2 publishers, none sent a message: /mouse_constraint may be paused (mouse_ctl '
     'resume), or its clock stand still (use_sim_time: no /clock)'),
    ('wrench', Graph('/mouse_constraint', False, 0),
     "nothing publishes /pose (the node's wrench input: mouse_wrench or another client "
     'publishes it)'),
    ('wrench', Graph('/mouse_constraint', True, 1, True),
     '/pose has 1 publisher, none sent a message'),
    ('force', Graph('/mouse_constraint', True, 0, False, True),
     '/mouse_constraint is running, but nothing publishes /pose (the node publishes it with '
     'publish_force true)'),
])
def test_why_no_message_came_as_the_graph_says(what, graph, reason):
    """The reason for each state of the graph; a node's pause says nothing of its input."""
    assert silence(ECHOES[what], '/pose', 2.0, graph) == (
        'no message on /pose after 2 s: ' + reason)


def mapped(pid: int, name: str) -> bool:
    """Return whether the process ``pid`` has mapped a file whose path holds ``name``."""
    return name in Path(f'/proc/{pid}/maps').read_text()


@pytest.mark.system
@pytest.mark.parametrize('delay', [0.0, 0.1, 0.3])
def test_ctrl_c_while_the_command_starts_is_exit_130_without_a_traceback(delay):
    """
    Ctrl-C once the command imports rclpy, and 0.1 and 0.3 s after: exit 130, nothing said.

    The command then has not taken the signals itself yet (its imports, rclpy's start), which
    gave a KeyboardInterrupt traceback; it ends as a call stopped before its answer. No node:
    a command that got so far waits for the service.
    """
    process = subprocess.Popen([*COMMAND, '--timeout', '60', 'release'],
                               stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    try:
        deadline = time.monotonic() + 20.0
        while not mapped(process.pid, '_rclpy_pybind11'):
            assert time.monotonic() < deadline and process.poll() is None
            time.sleep(0.001)
        time.sleep(delay)  # not a wait: the moment of start-up under test
        process.send_signal(signal.SIGINT)
        status = process.wait(timeout=20.0)
    finally:
        if process.poll() is None:
            process.kill()
    out, err = process.communicate()
    assert (status, out, err) == (130, '', '')
