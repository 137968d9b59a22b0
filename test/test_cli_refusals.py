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
The CLIs as separate processes: refusals with a reason, signals, and plain help.

``mouse_target`` refuses what the node would ignore, says why and exits 1; it stops at once on
SIGINT, even started with SIGINT ignored (a background job of a script); and both commands'
``--help`` is plain text naming every default.
"""

import argparse
import math
import os
from pathlib import Path
import shutil
import signal
import subprocess
import sys
import threading

from geometry_msgs.msg import PointStamped
import pytest
from rclpy.parameter import Parameter

from mouse_constraint_ros.cli import record as recorder, target as target_cli
from mouse_constraint_ros.description import BodyGeometry
from mouse_constraint_ros.inputs.grab import grab
from mouse_constraint_ros.inputs.target_gate import TargetGate
from mouse_constraint_ros.node.mouse_constraint_node import MouseConstraintNode

BIN = Path(sys.executable).parent
FRAME = 'odom'
RADIUS = 2.0
# Long enough that a command which misses a signal or a refusal is caught by its exit status,
# not by this timeout (only there so that a hang fails instead of blocking the run).
LONG = 60.0


def run_while_spinning(ros, command, timeout=30.0, env=None) -> subprocess.CompletedProcess:
    """Run ``command`` to completion while the in-process nodes spin; return its result."""
    process = subprocess.Popen(command, stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                               text=True, env=env)
    try:
        assert ros.spin_until(lambda: process.poll() is not None, timeout=timeout), command
    finally:
        if process.poll() is None:
            process.kill()
    stdout, stderr = process.communicate()
    return subprocess.CompletedProcess(command, process.returncode, stdout, stderr)


@pytest.fixture
def node(ros):
    """Start the node in-process in frame FRAME with workspace_radius RADIUS."""
    return ros.add(MouseConstraintNode(context=ros.context, parameter_overrides=[
        Parameter('rate_hz', value=100.0), Parameter('frame_id', value=FRAME),
        Parameter('workspace_radius', value=RADIUS), Parameter('marker_rate_hz', value=0.0),
        Parameter('diagnostics_rate_hz', value=0.0)]))


def error_lines(stderr: str) -> list:
    """Return the lines of ``stderr`` logged at ERROR."""
    return [line for line in stderr.splitlines() if line.startswith('[ERROR]')]


@pytest.mark.parametrize('arguments', [
    ['1e9', '0', '0'],
    [str(RADIUS), '0', '0.001'],
    ['0', '0', '1', '--frame', 'map'],
    ['--circle', '--center', '1.8', '0', '0.5', '--radius', '0.3', '--duration', str(LONG)],
    ['--circle', '--center', '0', '0', '1', '--frame', 'world', '--duration', str(LONG)],
])
def test_target_the_node_would_ignore_is_refused_with_the_reason(ros, node, arguments):
    """Exit 1, one error line with the gate's reason, and the node never got a target."""
    received = ros.collect(PointStamped, 'target')
    before = node.simulation.target
    result = run_while_spinning(ros, [str(BIN / 'mouse_target'), *arguments, '--timeout',
                                      str(LONG)])
    ros.spin_for(0.2)
    options = target_cli.parse_arguments(arguments)
    gate = TargetGate(FRAME, RADIUS)
    frame = options.frame or FRAME
    refusal = (gate.circle_refusal(frame, options.center, options.radius) if options.circle
               else gate.refusal(frame, options.point))
    assert refusal is not None
    assert result.returncode == 1, result.stderr
    [line] = error_lines(result.stderr)
    assert refusal.reason in line and 'nothing published' in line
    assert 'Traceback' not in result.stderr
    assert received == [] and node.simulation.target == before


def test_target_without_frame_is_published_in_the_node_s_frame(ros, node):
    """No --frame: the target goes out in the node's frame_id, and the node takes it."""
    received = ros.collect(PointStamped, 'target')
    result = run_while_spinning(ros, [str(BIN / 'mouse_target'), '0.5', '0', '1'])
    assert result.returncode == 0, result.stderr
    assert ros.spin_until(lambda: received)
    assert received[-1].header.frame_id == FRAME
    assert node.simulation.target == (0.5, 0.0, 1.0)


def test_circle_inside_the_workspace_runs(ros, node):
    """A circle whose farthest point is inside the workspace circles for its duration."""
    received = ros.collect(PointStamped, 'target')
    result = run_while_spinning(ros, [str(BIN / 'mouse_target'), '--circle', '--center', '1.6',
                                      '0', '0.5', '--radius', '0.3', '--duration', '0.5'])
    assert result.returncode == 0, result.stderr
    assert received and all(m.header.frame_id == FRAME for m in received)


def test_unanswered_parameters_are_said_and_the_target_still_goes_out(ros):
    """A subscriber but no parameter service: a warning, then the target, unchecked; exit 0."""
    received = ros.collect(PointStamped, 'target')
    result = run_while_spinning(ros, [str(BIN / 'mouse_target'), '1e9', '0', '0', '--node',
                                      'nobody_here', '--timeout', '5'])
    assert result.returncode == 0, result.stderr
    assert 'no parameter service nobody_here/get_parameters' in result.stderr
    assert 'publishing it unchecked' in result.stderr
    assert ros.spin_until(lambda: received)
    assert received[-1].point.x == 1e9 and received[-1].header.frame_id == 'world'


def ignore_sigint() -> None:
    """Start with SIGINT ignored, as a shell starts a background job of a script."""
    signal.signal(signal.SIGINT, signal.SIG_IGN)


@pytest.mark.parametrize('inherited', [signal.SIG_DFL, signal.SIG_IGN], ids=['default', 'ignored'])
def test_sigint_while_waiting_for_a_subscriber_exits_130_at_once(inherited):
    """No node: SIGINT during the wait ends the one-shot command with 130, no traceback."""
    process = subprocess.Popen(
        [str(BIN / 'mouse_target'), '0', '0', '1', '--timeout', str(LONG)],
        stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True,
        preexec_fn=ignore_sigint if inherited == signal.SIG_IGN else None)
    lines = []
    waiting = threading.Event()

    def read() -> None:
        for line in process.stderr:
            lines.append(line)
            if 'waiting up to' in line:
                waiting.set()
    reader = threading.Thread(target=read, daemon=True)
    reader.start()
    try:
        assert waiting.wait(timeout=LONG / 2), ''.join(lines)
        process.send_signal(signal.SIGINT)
        returncode = process.wait(timeout=LONG / 2)
    finally:
        if process.poll() is None:
            process.kill()
        process.wait()
        reader.join(timeout=5.0)
    stderr = ''.join(lines)
    assert returncode == 128 + signal.SIGINT, stderr
    assert 'Traceback' not in stderr and 'no subscriber' not in stderr


@pytest.mark.parametrize('module, executable', [(target_cli, 'mouse_target'),
                                                (recorder, 'mouse_record')])
def test_help_is_plain_text_and_names_every_default(module, executable):
    """No reST backticks in --help; each option's help says its default, numbers as set."""
    result = subprocess.run([str(BIN / executable), '--help'], capture_output=True, text=True,
                            timeout=30)
    assert result.returncode == 0, result.stderr
    assert '`' not in result.stdout
    parser = module.build_parser()
    compact = ''.join(result.stdout.split())
    actions = [a for a in parser._actions if not isinstance(a, argparse._HelpAction)]
    assert actions
    for action in actions:
        text = action.help % dict(vars(action), prog=parser.prog)
        assert 'default' in text, action.dest
        assert ''.join(text.split()) in compact, action.dest
        defaults = action.default if isinstance(action.default, list) else [action.default]
        for value in defaults:
            if isinstance(value, float) and math.isfinite(value):
                assert f'{value:g}' in text, action.dest


def test_grab_goes_out_on_grab_and_the_node_makes_the_point_its_anchor(ros):
    """--grab X Y Z: one message on grab (none on target); the point becomes the anchor."""
    start = (0.0, 0.0, 1.0)
    node = ros.add(MouseConstraintNode(context=ros.context, parameter_overrides=[
        Parameter('rate_hz', value=100.0), Parameter('frame_id', value=FRAME),
        Parameter('gravity', value=[0.0, 0.0, 0.0]),
        Parameter('hold_initial_anchor', value=False),
        Parameter('initial_position', value=list(start)),
        Parameter('marker_rate_hz', value=0.0), Parameter('diagnostics_rate_hz', value=0.0)]))
    grabs = ros.collect(PointStamped, 'grab')
    targets = ros.collect(PointStamped, 'target')
    # The centre of the box's -x face, on the body at rest where it starts.
    half = [0.5 * size for size in node.get_parameter('box_size').value]
    point = (start[0] - half[0], start[1], start[2])
    result = run_while_spinning(ros, [str(BIN / 'mouse_target'), '--grab',
                                      *(repr(c) for c in point)])
    assert result.returncode == 0, result.stderr
    assert 'grab (' in result.stderr and f"in '{FRAME}' received on /grab" in result.stderr
    assert ros.spin_until(lambda: node.simulation.target == point)
    assert len(grabs) == 1 and targets == [] and grabs[0].header.frame_id == FRAME
    assert list(node.get_parameter('anchor').value) == pytest.approx(
        [p - s for p, s in zip(point, start)], abs=1e-9)


def test_grab_the_node_would_ignore_is_refused_with_the_reason(ros, node):
    """The target checks hold for --grab: exit 1, the gate's reason, nothing on grab."""
    grabs = ros.collect(PointStamped, 'grab')
    before = node.get_parameter('anchor').value
    result = run_while_spinning(ros, [str(BIN / 'mouse_target'), '--grab', '1e9', '0', '0',
                                      '--timeout', str(LONG)])
    ros.spin_for(0.2)
    refusal = TargetGate(FRAME, RADIUS).refusal(FRAME, (1e9, 0.0, 0.0))
    assert result.returncode == 1, result.stderr
    [line] = error_lines(result.stderr)
    assert f'would ignore grab {refusal.reason}; nothing published' in line
    assert grabs == [] and node.get_parameter('anchor').value == before


def test_grab_takes_one_point_not_a_circle():
    """--grab with --circle is a usage error (exit 2)."""
    with pytest.raises(SystemExit) as exit_info:
        target_cli.parse_arguments(['--grab', '--circle'])
    assert exit_info.value.code == 2


@pytest.fixture
def resting_node(ros):
    """Start a node whose body rests at (0, 0, 1), anchored at its COM: a known pose."""
    return ros.add(MouseConstraintNode(context=ros.context, parameter_overrides=[
        Parameter('rate_hz', value=100.0), Parameter('anchor', value=[0.0, 0.0, 0.0]),
        Parameter('initial_position', value=[0.0, 0.0, 1.0]),
        Parameter('marker_rate_hz', value=0.0), Parameter('diagnostics_rate_hz', value=0.0)]))


@pytest.mark.parametrize('point', [(5.0, 5.0, 5.0), (0.3, 0.0, 1.0)])
def test_grab_off_the_body_is_refused_with_its_distance(ros, resting_node, point):
    """A grab off the box by more than grab_margin: exit 1, the node's own distance, nothing."""
    grabs = ros.collect(PointStamped, 'grab')
    before = resting_node.get_parameter('anchor').value
    result = run_while_spinning(ros, [str(BIN / 'mouse_target'), '--grab',
                                      *(repr(c) for c in point), '--timeout', str(LONG)])
    ros.spin_for(0.2)
    landed = grab(resting_node.simulation.state,
                  BodyGeometry.box(resting_node.get_parameter('box_size').value), point)
    margin = resting_node.get_parameter('grab_margin').value
    assert landed.distance > margin
    assert result.returncode == 1, result.stderr
    [line] = error_lines(result.stderr)
    assert f'would ignore grab {point}: {landed.distance:.6g} m off the body' in line
    assert f'farther than grab_margin {margin:g} m' in line and 'nothing published' in line
    assert grabs == [] and resting_node.get_parameter('anchor').value == before


def test_grab_within_the_margin_is_published_and_taken(ros, resting_node):
    """A grab just off the box, within grab_margin, passes the check and becomes the anchor."""
    margin = resting_node.get_parameter('grab_margin').value
    half_x = 0.5 * resting_node.get_parameter('box_size').value[0]
    point = (half_x + 0.5 * margin, 0.0, 1.0)
    result = run_while_spinning(ros, [str(BIN / 'mouse_target'), '--grab',
                                      *(repr(c) for c in point)])
    assert result.returncode == 0, result.stderr
    assert ros.spin_until(lambda: resting_node.simulation.target == point)
    assert resting_node.get_parameter('anchor').value[0] == pytest.approx(point[0], abs=1e-6)


ROOT = Path(__file__).resolve().parent.parent
# The handle's outer face of the shipped mug, in its link frame (config/mug.yaml's anchor).
HANDLE = (0.052, 0.0, 0.05)


def mug_node(ros, description: str) -> MouseConstraintNode:
    """Start the mug of ``description`` in-process, its link frame held at (0, 0, 0.3)."""
    return ros.add(MouseConstraintNode(context=ros.context, parameter_overrides=[
        Parameter('rate_hz', value=100.0), Parameter('robot_description', value=description),
        Parameter('body_link', value='mug'), Parameter('density', value=2400.0),
        Parameter('initial_position', value=[0.0, 0.0, 0.3]),
        Parameter('gravity', value=[0.0, 0.0, 0.0]),
        Parameter('hold_initial_anchor', value=False),
        Parameter('marker_rate_hz', value=0.0), Parameter('diagnostics_rate_hz', value=0.0)]))


def test_grab_on_the_shipped_mug_with_no_workspace(ros, monkeypatch):
    """
    No AMENT_PREFIX_PATH in the node's process nor mouse_target's: the mug's mesh is found.

    A second terminal has no ``make run`` environment: the package finds its own
    ``package://mouse_constraint_ros/`` files, and the grab on the handle is checked and taken.
    """
    monkeypatch.delenv('AMENT_PREFIX_PATH', raising=False)
    node = mug_node(ros, (ROOT / 'config' / 'mug.urdf').read_text())
    point = (HANDLE[0], HANDLE[1], HANDLE[2] + 0.3)
    # The command reads the mesh too (trimesh): a loaded machine takes its time.
    result = run_while_spinning(ros, [str(BIN / 'mouse_target'), '--grab',
                                      *(repr(c) for c in point), '--timeout', str(LONG)],
                                timeout=2 * LONG)
    assert result.returncode == 0 and 'Traceback' not in result.stderr, result.stderr
    assert ros.spin_until(lambda: node.simulation.target == point)


def test_grab_on_a_mesh_this_machine_cannot_find_goes_out_unchecked(ros, monkeypatch, tmp_path):
    """
    The node's mesh is another package's, unknown where mouse_target runs: one line, published.

    mouse_target cannot build the body's shape to check the grab; it says so in one warning
    line (no traceback) and publishes the grab, which the node, which has the mesh, takes.
    """
    index = tmp_path / 'share' / 'ament_index' / 'resource_index' / 'packages'
    index.mkdir(parents=True)
    (index / 'cups').touch()
    (tmp_path / 'share' / 'cups').mkdir()
    shutil.copy(ROOT / 'config' / 'mug.stl', tmp_path / 'share' / 'cups' / 'mug.stl')
    monkeypatch.setenv('AMENT_PREFIX_PATH', str(tmp_path))
    node = mug_node(ros, (ROOT / 'config' / 'mug.urdf').read_text().replace(
        'package://mouse_constraint_ros/config/mug.stl', 'package://cups/mug.stl'))
    point = (HANDLE[0], HANDLE[1], HANDLE[2] + 0.3)
    environment = {k: v for k, v in os.environ.items() if k != 'AMENT_PREFIX_PATH'}
    result = run_while_spinning(ros, [str(BIN / 'mouse_target'), '--grab',
                                      *(repr(c) for c in point), '--timeout', str(LONG)],
                                timeout=2 * LONG, env=environment)
    assert result.returncode == 0 and 'Traceback' not in result.stderr, result.stderr
    [warning] = [line for line in result.stderr.splitlines() if line.startswith('[WARN]')]
    assert "cannot check the grab against the body here: link 'mug' <collision> 1: mesh " \
           "'package://cups/mug.stl' cannot be resolved" in warning
    assert warning.endswith('publishing it unchecked')
    assert ros.spin_until(lambda: node.simulation.target == point)


def test_subscribers_waits_for_that_many_and_says_how_many_matched(ros, node):
    """--subscribers 2 with only the node: exit 1 naming 1 of 2; with a second one: published."""
    short = run_while_spinning(ros, [str(BIN / 'mouse_target'), '0.5', '0', '1', '--subscribers',
                                     '2', '--timeout', '5'])
    assert short.returncode == 1, short.stderr
    [line] = error_lines(short.stderr)
    assert '1 of 2 subscribers on /target after 5 s' in line
    received = ros.collect(PointStamped, 'target')
    result = run_while_spinning(ros, [str(BIN / 'mouse_target'), '0.5', '0', '1',
                                      '--subscribers', '2'])
    assert result.returncode == 0, result.stderr
    assert 'waiting up to 10 s for 2 subscribers on /target' in result.stderr
    assert ros.spin_until(lambda: received) and node.simulation.target == (0.5, 0.0, 1.0)
