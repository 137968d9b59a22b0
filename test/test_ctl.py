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
``mouse_ctl``: the node's services and output from the venv's command line.

In lockstep (a ``SimulatedBody``), the command's own calls and echo against the node: replies,
state, and lines with their exact stamps, values and rates. As a process, the command line
itself: its exit statuses, its output, a service that is not there, usage errors.
"""

from pathlib import Path
import re
import signal
import subprocess
import sys

from geometry_msgs.msg import PoseStamped
import numpy as np
import pytest
from rclpy.node import Node
from rclpy.parameter import Parameter

from mouse_constraint_ros.cli import ctl
from mouse_constraint_ros.cli.echo import ECHOES, EchoPrinter, RateMeter, vector
from mouse_constraint_ros.node.mouse_constraint_node import MouseConstraintNode
from test_support.ctl_calls import run_call

ROOT = Path(__file__).resolve().parent.parent
BIN = Path(sys.executable).parent
# The installed script where the venv has it, else the module it runs.
COMMAND = ([str(BIN / 'mouse_ctl')] if (BIN / 'mouse_ctl').is_file()
           else [sys.executable, '-m', 'mouse_constraint_ros.cli.ctl'])


def test_setup_installs_the_command_beside_the_others():
    """A console script of setup.py, which setup.cfg installs under lib/<package> for colcon."""
    source = (ROOT / 'setup.py').read_text()
    assert "'mouse_ctl = mouse_constraint_ros.cli.console:ctl'," in source
    assert 'install_scripts=$base/lib/mouse_constraint_ros' in (ROOT / 'setup.cfg').read_text()


def test_node_and_timeout_go_before_the_command_or_after_it():
    """--node and --timeout are taken on either side of the command; their defaults otherwise."""
    assert vars(ctl.parse_arguments(['reset'])) == {
        'node': 'mouse_constraint', 'timeout': 10.0, 'command': 'reset'}
    assert ctl.parse_arguments(['--timeout', '3', 'step', '2']).timeout == 3.0
    after = ctl.parse_arguments(['echo', 'twist', '--node', 'arm', '--timeout', '4'])
    assert (after.node, after.timeout, after.what) == ('arm', 4.0, 'twist')


@pytest.fixture
def client_node(simulated_body):
    """Return a node in the body's context, its client of each service matched."""
    node = Node('mouse_ctl', context=simulated_body.context, start_parameter_services=False)
    node.clients_by_action = {action: ctl.create_client(node, action) for action in ctl.ACTIONS}
    return simulated_body.add_node(node)


def test_pause_step_resume_in_lockstep(simulated_body, client_node, capsys):
    """Each call prints the node's reply; step advances a paused node tick by tick."""
    body = simulated_body
    body.step(5)
    assert run_call(body, client_node, 'pause', capsys) == (
        0, 'paused at 0.005000 s simulated\n', '')
    assert body.node.ticker.paused
    status, out, _ = run_call(body, client_node, 'step', capsys, ticks=3)
    assert status == 0 and out.splitlines() == [
        f'one tick of 0.001 s, to 0.00{n}000 s simulated' for n in (6, 7, 8)]
    assert body.time == pytest.approx(0.008, abs=1e-12)
    assert run_call(body, client_node, 'pause', capsys)[1] == 'already paused\n'
    assert run_call(body, client_node, 'resume', capsys)[1] == (
        'running from 0.008000 s simulated\n')
    assert not body.node.ticker.paused
    status, out, err = run_call(body, client_node, 'step', capsys)
    assert (status, out) == (1, '') and err.startswith('mouse_ctl: step: running: ~/step ')


def test_reset_and_release_in_lockstep(simulated_body, client_node, capsys):
    """Release lets the body fall; reset brings it back, held where it starts."""
    body = simulated_body
    body.step(10)
    assert run_call(body, client_node, 'release', capsys) == (0, 'released\n', '')
    assert run_call(body, client_node, 'release', capsys)[1] == 'already free\n'
    body.step(100)
    assert body.pose.position[2] < 1.0 - 0.04
    assert run_call(body, client_node, 'reset', capsys)[1] == (
        'back to the initial state, anchor held where it starts\n')
    body.step(1)
    assert np.allclose(body.anchor, (0.2, 0.1, 1.05), atol=1e-6)


def test_a_service_that_is_not_there_is_said_with_exit_1(simulated_body, capsys):
    """Another node name: no service within --timeout."""
    node = simulated_body.add_node(Node('mouse_ctl', context=simulated_body.context))
    status, out, err = run_call(simulated_body, node, 'reset', capsys, node='nobody',
                                timeout=0.2)
    assert (status, out) == (1, '')
    assert err == ('mouse_ctl: no service /nobody/reset after 0.2 s: is the node running (same '
                   'ROS_DOMAIN_ID and namespace, --node)?\n')


def test_echo_pose_prints_at_its_print_rate_with_the_rate_of_the_stamps(simulated_body):
    """10 lines a second of the node's clock, each with the pose of its tick and 1000 Hz."""
    body = simulated_body
    node = Node('mouse_ctl', context=body.context)
    lines = []
    printer = ctl.create_echo(node, 'pose', lines.append, print_rate=10.0)
    body.add_node(node)
    poses = {}
    body.add_tick_callback(lambda b: poses.setdefault(round(b.time * 1000), b.pose))
    body.step(1000)
    assert printer.received == 1000 and printer.printed == len(lines) == 10
    assert lines[0].startswith('0.001000 s  position ') and lines[0].endswith('rate -')
    for index, line in enumerate(lines[1:], 1):
        pose = poses[1 + 100 * index]
        assert line == (f'{pose.time:.6f} s  position {vector(pose.position)} m  orientation '
                        f'{vector(pose.orientation)} (x, y, z, w)  rate 1000.0 Hz')


def test_echo_twist_and_wrench(simulated_body):
    """Every message at print rate 0; wrench is the wrench input, as the node receives it."""
    body = simulated_body
    node = Node('mouse_ctl', context=body.context)
    twists, wrenches = [], []
    ctl.create_echo(node, 'twist', twists.append, print_rate=0.0)
    ctl.create_echo(node, 'wrench', wrenches.append, print_rate=0.0)
    body.add_node(node)
    body.step(3)
    assert len(twists) == 3 and twists[2].endswith('rad/s  rate 1000.0 Hz')
    assert twists[2].startswith(f'0.003000 s  linear {vector(body.twist.linear)} m/s  angular ')
    body.wrench((0.0, 0.0, 30.0), (0.0, 0.0, 0.5), stamp=0.004)
    assert wrenches == ['0.004000 s  force (0.000000, 0.000000, 30.000000) N  torque '
                        '(0.000000, 0.000000, 0.500000) N m  rate -']


def test_echo_force_is_the_force_the_pointer_feels(simulated_body_factory):
    """With publish_force, force echoes the felt force: the weight of a body held at its COM."""
    body = simulated_body_factory(publish_force=True, anchor=[0.0, 0.0, 0.0], mass=2.0)
    node = Node('mouse_ctl', context=body.context)
    forces = []
    ctl.create_echo(node, 'force', forces.append, print_rate=0.0)
    body.add_node(node)
    body.step(2)
    assert forces[-1] == ('0.002000 s  force (0.000000, 0.000000, -19.613300) N  torque '
                          '(0.000000, 0.000000, 0.000000) N m  rate 1000.0 Hz')


def test_the_rate_is_that_of_the_last_second_of_stamps():
    """A window of 1 s of stamps; a stamp that goes back starts it again; bad bytes counted."""
    meter = RateMeter()
    assert meter.rate() is None
    for n in range(3001):
        meter.add(n * 2_000_000)  # 500 Hz for 6 s
    assert meter.rate() == pytest.approx(500.0)
    meter.add(0)
    assert meter.rate() is None
    printer = EchoPrinter(ECHOES['pose'], print)
    printer.take(b'\x00\x01\x00\x00')
    assert (printer.unreadable, printer.received) == (1, 0)


def run_command(ros, arguments, timeout=30.0):
    """Run ``mouse_ctl ARGUMENTS`` to completion while ``ros`` spins; return its result."""
    process = subprocess.Popen([*COMMAND, *arguments], stdout=subprocess.PIPE,
                               stderr=subprocess.PIPE, text=True)
    try:
        assert ros.spin_until(lambda: process.poll() is not None, timeout=timeout), arguments
    finally:
        if process.poll() is None:
            process.kill()
    out, err = process.communicate()
    return process.returncode, out, err


@pytest.fixture
def node(ros):
    """Start the node at 100 Hz in-process, with its timers: the command reaches it over DDS."""
    return ros.add(MouseConstraintNode(context=ros.context, parameter_overrides=[
        Parameter('rate_hz', value=100.0), Parameter('marker_rate_hz', value=0.0),
        Parameter('diagnostics_rate_hz', value=0.0)]))


@pytest.mark.system
def test_the_command_line_calls_and_echoes_the_node(ros, node):
    """pause, step 2, step while running, echo --count 3: statuses and output as promised."""
    status, out, err = run_command(ros, ['pause'])
    assert status == 0 and re.fullmatch(r'paused at \d+\.\d{6} s simulated\n', out), err
    assert node.ticker.paused
    status, out, _ = run_command(ros, ['step', '2'])
    assert status == 0 and len(re.findall(r'^one tick of 0\.01 s, to ', out, re.M)) == 2
    assert run_command(ros, ['resume'])[0] == 0 and not node.ticker.paused
    status, out, err = run_command(ros, ['step'])
    assert (status, out) == (1, '') and 'pause it first' in err
    status, out, err = run_command(ros, ['echo', 'pose', '--count', '3', '--print-rate', '0'])
    lines = out.splitlines()
    assert status == 0 and len(lines) == 3, err
    assert all(re.fullmatch(r'\d+\.\d{6} s  position \(.*\) m  orientation \(.*\) '
                            r'\(x, y, z, w\)  rate (-|\d+\.\d Hz)', line) for line in lines)
    # Each line's rate is that of the stamps received so far: two 10 ms ticks over the first
    # three, 100 Hz, unless the node, spun in this process beside other tests, dropped a tick
    # between them (the rate of its ticks is held by the tests marked alone).
    # The stamps are printed to the microsecond from a double: 1 us either way.
    stamps = [int(line.split(' s ', 1)[0].replace('.', '')) for line in lines]
    ticks = [round((b - a) / 10_000) for a, b in zip(stamps, stamps[1:])]
    assert all(k >= 1 and abs(b - a - 10_000 * k) <= 2
               for k, a, b in zip(ticks, stamps, stamps[1:])), stamps
    assert lines[2].endswith(f'rate {2 / (0.01 * sum(ticks)):.1f} Hz')


@pytest.mark.system
def test_the_command_line_says_what_is_wrong(ros):
    """No node: exit 1 naming the service; bad arguments: usage, exit 2; Ctrl-C ends echo, 0."""
    status, _, err = run_command(ros, ['--timeout', '0.5', 'release'])
    assert status == 1 and 'no service /mouse_constraint/release after 0.5 s' in err
    for arguments in (['step', '0'], ['step', '2.5'], ['echo', '--count', '-1'], ['jump'],
                      ['echo', 'odom']):
        status, _, err = run_command(ros, arguments)
        assert status == 2 and err.startswith('usage: mouse_ctl'), arguments
    publisher = ros.probe.create_publisher(PoseStamped, 'pose', 10)
    process = subprocess.Popen([*COMMAND, '--timeout', '60', 'echo'], stdout=subprocess.PIPE,
                               stderr=subprocess.PIPE, text=True)
    assert ros.spin_until(lambda: publisher.get_subscription_count() > 0, timeout=30.0)
    process.send_signal(signal.SIGINT)
    assert process.wait(timeout=10) == 0 and 'Traceback' not in process.communicate()[1]
