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
Separate processes: the target CLI against the node, signals, bad parameters, and packaging.

The executables are the ones the pip route installs next to this interpreter
(``.venv/bin/``); the packaging test builds the package with colcon and starts what
``ros2 run`` would start.
"""

import math
import os
from pathlib import Path
import shutil
import signal
import subprocess
import sys
import time

from geometry_msgs.msg import PointStamped, PoseStamped
import numpy as np
import pytest
from rosgraph_msgs.msg import Clock

from mouse_constraint_ros.node.mouse_constraint_node import MouseConstraintNode
from mouse_constraint_ros.wire.messages import point_from_message

ROOT = Path(__file__).resolve().parent.parent
BIN = Path(sys.executable).parent
PARAMS = ROOT / 'config' / 'params.yaml'


def run_while_spinning(ros, command, timeout=20.0) -> subprocess.CompletedProcess:
    """Run ``command`` to completion while the in-process nodes spin; return its result."""
    process = subprocess.Popen(command, stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                               text=True)
    assert ros.spin_until(lambda: process.poll() is not None, timeout=timeout), command
    stdout, stderr = process.communicate()
    return subprocess.CompletedProcess(command, process.returncode, stdout, stderr)


def values(status) -> dict:
    """Return a diagnostic status's key-value pairs as a dict."""
    return {kv.key: kv.value for kv in status.values}


def start_node(ros, *ros_arguments: str) -> MouseConstraintNode:
    """Start the node in-process with command-line style ROS arguments."""
    return ros.add(MouseConstraintNode(
        context=ros.context, cli_args=['--ros-args', '-p', 'rate_hz:=200.0', *ros_arguments]))


@pytest.mark.parametrize('remap', [
    (),
    ('-r', 'target:=/clicked_point'),
    ('-r', '__ns:=/robot'),
])
def test_one_shot_target_reaches_the_node(ros, remap):
    """`mouse_target X Y Z` exits 0 once the node has the target, under remaps and namespaces."""
    node = start_node(ros, *remap)
    command = [str(BIN / 'mouse_target'), '0.3', '0.1', '1.1', '--ros-args', *remap]
    result = run_while_spinning(ros, command)
    assert result.returncode == 0, result.stderr
    assert 'received on' in result.stderr
    assert node.simulation.target == (0.3, 0.1, 1.1)


def test_circle_mode_moves_the_target_around_the_circle(ros):
    """`mouse_target --circle` streams targets on the circle until its duration ends."""
    node = start_node(ros)
    messages = ros.collect(PointStamped, 'target')
    command = [str(BIN / 'mouse_target'), '--circle', '--center', '0.0', '0.5', '1.0',
               '--radius', '0.3', '--period', '1.0', '--rate', '50', '--duration', '1.5']
    result = run_while_spinning(ros, command)
    assert result.returncode == 0, result.stderr
    points = np.array([point_from_message(m) for m in messages])
    assert node.simulation.target == point_from_message(messages[-1])
    assert len(points) > 40
    np.testing.assert_allclose(np.linalg.norm(points[:, :2] - [0.0, 0.5], axis=1), 0.3)
    np.testing.assert_allclose(points[:, 2], 1.0)
    angles = np.unwrap(np.arctan2(points[:, 1] - 0.5, points[:, 0]))
    assert np.ptp(angles) > 1.5 * math.pi


def test_target_cli_fails_clearly_without_a_subscriber():
    """No node: exit 1 after the timeout, with an error that says what to check."""
    result = subprocess.run([str(BIN / 'mouse_target'), '1', '2', '3', '--timeout', '0.5'],
                            capture_output=True, text=True, timeout=20)
    assert result.returncode == 1
    assert 'no subscriber on /target' in result.stderr
    assert 'Traceback' not in result.stderr


def test_target_cli_rejects_bad_arguments():
    """Wrong arity or non-finite numbers: a usage error (exit 2), nothing published."""
    for arguments in (['1', '2'], ['1', '2', 'nan'], [], ['--circle', '--radius', '-1']):
        result = subprocess.run([str(BIN / 'mouse_target'), *arguments], capture_output=True,
                                text=True, timeout=20)
        assert result.returncode == 2, arguments
        assert 'usage: mouse_target' in result.stderr


@pytest.mark.parametrize('signum', [signal.SIGINT, signal.SIGTERM, signal.SIGHUP])
def test_node_exits_cleanly_on_signals(ros, signum):
    """SIGINT, SIGTERM and SIGHUP (terminal closed) end the node in 1 s: exit 0, no traceback."""
    poses = ros.collect(PoseStamped, 'pose')
    process = subprocess.Popen(
        [str(BIN / 'mouse_constraint_node'), '--ros-args', '--params-file', str(PARAMS)],
        stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    try:
        assert ros.spin_until(lambda: len(poses) > 10, timeout=15.0)
        started = time.monotonic()
        process.send_signal(signum)
        returncode = process.wait(timeout=5.0)
        elapsed = time.monotonic() - started
    finally:
        process.kill()
    _, stderr = process.communicate()
    assert returncode == 0, stderr
    assert elapsed < 1.0
    assert 'Traceback' not in stderr and 'Error' not in stderr, stderr


def test_node_refuses_invalid_parameters_with_a_reason():
    """A params file or override with an invalid value: exit 1, a one-line reason."""
    result = subprocess.run(
        [str(BIN / 'mouse_constraint_node'), '--ros-args', '--params-file', str(PARAMS),
         '-p', 'inertia:=[1.0, 0.0, 0.0, 1.0, 0.0, 3.0]'],
        capture_output=True, text=True, timeout=20)
    assert result.returncode == 1
    assert 'invalid parameters' in result.stderr and 'triangle' in result.stderr
    assert 'Traceback' not in result.stderr


def test_node_process_follows_sim_time(ros):
    """The installed node (EventsExecutor) with use_sim_time ticks on /clock, on the grid."""
    poses = ros.collect(PoseStamped, 'pose')
    clock = ros.probe.create_publisher(Clock, '/clock', 10)
    process = subprocess.Popen(
        [str(BIN / 'mouse_constraint_node'), '--ros-args', '--params-file', str(PARAMS),
         '-p', 'rate_hz:=100.0', '-p', 'use_sim_time:=true'],
        stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    try:
        assert ros.spin_until(lambda: clock.get_subscription_count() > 0, timeout=15.0)
        start = 5_000_000_000
        for k in range(200):
            message = Clock()
            message.clock.sec, message.clock.nanosec = divmod(start + k * 10_000_000,
                                                              1_000_000_000)
            clock.publish(message)
            ros.spin_for(0.01)
        ros.spin_for(0.5)
    finally:
        process.send_signal(signal.SIGINT)
        process.wait(timeout=5.0)
    stamps = np.array([p.header.stamp.sec * 1_000_000_000 + p.header.stamp.nanosec
                       for p in poses])
    assert len(stamps) > 100
    assert stamps.min() >= start and stamps.max() <= start + 199 * 10_000_000
    assert np.all((stamps - stamps[0]) % 10_000_000 == 0)


def test_colcon_build_gives_what_ros2_run_needs(ros, tmp_path, colcon_install):
    """
    Build with colcon, check the ament index and lib/<pkg>/ executables, run the built node.

    ``ros2 run`` finds a package by ``ament_index_python.get_package_prefix`` and runs
    ``<prefix>/lib/<package>/<executable>``; this checks exactly that, then starts the built
    executable (not the editable one) and receives its pose over DDS. The build is the
    session's (``conftest.py``), which ``test_launch`` reads too.
    """
    prefix = colcon_install
    marker = prefix / 'share' / 'ament_index' / 'resource_index' / 'packages'
    assert (marker / 'mouse_constraint_ros').is_file()
    assert (prefix / 'share' / 'mouse_constraint_ros' / 'config' / 'params.yaml').is_file()
    site_packages = next(prefix.glob('lib/python3*/site-packages'))
    # What `source install/setup.bash` puts in the environment.
    run_environment = dict(os.environ, AMENT_PREFIX_PATH=str(prefix),
                           PYTHONPATH=str(site_packages))
    found = subprocess.run(
        [sys.executable, '-c', 'from ament_index_python.packages import get_package_prefix; '
         'print(get_package_prefix("mouse_constraint_ros"))'],
        capture_output=True, text=True, env=run_environment, cwd=tmp_path, check=True)
    assert found.stdout.strip() == str(prefix)
    for name in ('mouse_constraint_node', 'mouse_target', 'mouse_wrench', 'mouse_record',
                 'mouse_ctl', 'mouse_view', 'mouse_marker'):
        executable = prefix / 'lib' / 'mouse_constraint_ros' / name
        assert executable.is_file() and os.access(executable, os.X_OK), name
    poses = ros.collect(PoseStamped, 'pose')
    process = subprocess.Popen(
        [sys.executable, str(prefix / 'lib' / 'mouse_constraint_ros' / 'mouse_constraint_node'),
         '--ros-args', '--params-file',
         str(prefix / 'share' / 'mouse_constraint_ros' / 'config' / 'params.yaml')],
        stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, env=run_environment,
        cwd=tmp_path)
    try:
        assert ros.spin_until(lambda: len(poses) > 10, timeout=20.0)
    finally:
        process.send_signal(signal.SIGINT)
        process.wait(timeout=5.0)
    _, stderr = process.communicate()
    assert process.returncode == 0, stderr
    # The built copy ran, not the source tree's.
    assert not any(path.name == 'build' for path in ROOT.iterdir() if path.is_dir())
    assert shutil.which('mouse_constraint_node', path=str(prefix / 'lib' /
                                                          'mouse_constraint_ros'))


def test_slow_ticks_leave_services_and_parameters_answering(ros):
    """
    With 1000 substeps at 1 kHz a tick costs more than its period, and the node stays responsive.

    Each timer callback stops running ticks after its wall budget and drops the rest, so
    ~/reset and a parameter set answer promptly (a generous behaviour bound, not a benchmark)
    and /diagnostics report the drops with their cause.
    """
    from diagnostic_msgs.msg import DiagnosticArray
    from rcl_interfaces.msg import Parameter as ParameterMessage, ParameterType, ParameterValue
    from rcl_interfaces.srv import SetParameters
    from std_srvs.srv import Trigger
    poses = ros.collect(PoseStamped, 'pose')
    arrays = ros.collect(DiagnosticArray, '/diagnostics')
    process = subprocess.Popen(
        [str(BIN / 'mouse_constraint_node'), '--ros-args', '--params-file', str(PARAMS),
         '-p', 'substeps:=1000', '-p', 'diagnostics_rate_hz:=2.0'],
        stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)

    def answer_time(service_type, name, request) -> float:
        """Return how long the second call takes: the first one also waits for discovery."""
        client = ros.probe.create_client(service_type, name)
        assert client.wait_for_service(timeout_sec=15.0)
        for _ in range(2):
            started = time.monotonic()
            future = client.call_async(request)
            assert ros.spin_until(future.done, timeout=10.0)
        return time.monotonic() - started

    try:
        assert ros.spin_until(lambda: len(poses) > 10, timeout=15.0)
        ros.spin_for(0.5)
        reset = answer_time(Trigger, '/mouse_constraint/reset', Trigger.Request())
        mass = answer_time(SetParameters, '/mouse_constraint/set_parameters',
                           SetParameters.Request(parameters=[ParameterMessage(
                               name='mass', value=ParameterValue(
                                   type=ParameterType.PARAMETER_DOUBLE, double_value=3.0))]))
        assert ros.spin_until(lambda: any(
            int(values(a.status[0])['dropped ticks since start']) > 0 for a in arrays),
            timeout=10.0)
    finally:
        process.send_signal(signal.SIGINT)
        process.wait(timeout=5.0)
    _, stderr = process.communicate()
    assert reset < 0.5 and mass < 0.5, (reset, mass)
    rate = arrays[-1].status[0]
    cause = values(rate)['last drop cause']
    assert '1000 substeps' in cause and 'services and parameters answer' in cause
    assert 'cannot keep 1000 Hz: dropped' in stderr and '1000 substeps' in stderr
