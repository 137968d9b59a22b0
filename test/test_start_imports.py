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
Which heavy libraries each executable has loaded once it runs: the box body and a URDF body.

Each executable is the installed console script, started as a user starts it, with one
difference in its environment: ``PYTHONPROFILEIMPORTTIME`` (``python -X importtime``), with which
the interpreter writes a line to stderr for every module as it is first imported. The lines
written by the moment the executable has done what it started for (the node published a pose,
the recorder wrote a row to its CSV, the marker served the body, the view sent it to a page;
a one-shot command exited) are the modules it loaded to get there: a module imported before
that moment wrote its line before it, in the same process. The libraries of ``HEAVY`` load
where they are first needed (docs/architecture.md, "Heavy libraries"): the URDF's parser, its
meshes and scipy.spatial (which trimesh imports) only where a URDF is read, the figure's
matplotlib and the MCAP writer only for the recorder's figure and ``--mcap``, pinocchio only in
the robot mode.
"""

import csv
from pathlib import Path
import re
import subprocess
import time
from typing import Dict, Set

from geometry_msgs.msg import PoseStamped
import pytest
from visualization_msgs.msg import Marker
from visualization_msgs.srv import GetInteractiveMarkers

from mouse_constraint_ros.cli.urdf_params import params_text
from mouse_constraint_ros.timing.spin import call_until_answered, StopRequest
from mouse_constraint_ros.wire.interface import MARKER_SERVICE
from test_support import processes
from test_support.ros_harness import RosHarness

pytestmark = pytest.mark.system

ROOT = processes.ROOT
BIN = processes.BIN
HEAVY = ('yourdfpy', 'trimesh', 'scipy.spatial', 'matplotlib', 'mcap', 'pinocchio')
# What reading a URDF loads: the parser, the meshes, and scipy.spatial (trimesh imports it).
URDF_LIBRARIES = {'yourdfpy', 'trimesh', 'scipy.spatial'}
IMPORT_LINE = re.compile(r'^import time:\s+\d+ \|\s+\d+ \|\s*(\S+)\s*$', re.MULTILINE)
BODIES = ('box', 'urdf')
SCRIPTS = ('mouse_constraint_node', 'mouse_view', 'mouse_marker', 'mouse_record', 'mouse_target',
           'mouse_wrench', 'mouse_ctl')
TIMEOUT = 60.0
ZSTD_MAGIC = b'\x28\xb5\x2f\xfd'


def loaded(log: str) -> Set[str]:
    """Return the heavy libraries of ``HEAVY`` whose import a ``-X importtime`` log shows."""
    modules = set(IMPORT_LINE.findall(log))
    return {name for name in HEAVY
            if any(module == name or module.startswith(name + '.') for module in modules)}


def test_loaded_reads_an_importtime_log():
    """The parser of the logs: nested and top-level lines, a package's submodules, no others."""
    log = ('import time: self [us] | cumulative | imported package\n'
           'import time:       418 |     590367 |         scipy.spatial\n'
           'import time:        34 |     590400 |       scipy.spatial.transform\n'
           'import time:       812 |       9001 | scipy\n'
           '[INFO] [mouse_record]: trimesh is mentioned in a log line\n'
           'import time:        20 |         20 |   mcap.writer\n'
           'import time:        20 |         20 |   mcap_like\n')
    assert loaded(log) == {'scipy.spatial', 'mcap'}


def _environment() -> Dict[str, str]:
    return dict(processes.private_environment(), PYTHONPROFILEIMPORTTIME='1')


def _wait(ros, condition, process: processes.ChildProcess, what: str) -> None:
    deadline = time.monotonic() + TIMEOUT
    while not condition():
        assert process.alive(), f'{what}: exited\n{process.log()[-3000:]}'
        assert time.monotonic() < deadline, f'{what}: not within {TIMEOUT:g} s\n' + \
            process.log()[-3000:]
        ros.spin_for(0.05)


def _node_parameters(body: str, folder: Path) -> list:
    if body == 'box':
        return ['--params-file', str(ROOT / 'config' / 'params.yaml')]
    description = folder / 'tool_description.yaml'
    description.write_text(params_text((ROOT / 'config' / 'tool.urdf').read_text()))
    return ['--params-file', str(ROOT / 'config' / 'params.yaml'), '--params-file',
            str(description), '--params-file', str(ROOT / 'config' / 'tool.yaml')]


@pytest.fixture(scope='module', params=BODIES)
def node(request, tmp_path_factory):
    """Yield the body's name and its node's log once it published a pose; a context beside."""
    ros = RosHarness()
    poses = ros.collect(PoseStamped, 'pose')
    process = processes.ChildProcess(
        processes.node_command(*_node_parameters(request.param, tmp_path_factory.mktemp('node'))),
        environment=_environment())
    try:
        _wait(ros, lambda: poses, process, 'the first pose')
        yield request.param, process.log(), ros
    finally:
        process.close()
        ros.shutdown()


def _rows(path: Path) -> int:
    try:
        with open(path, newline='') as stream:
            return max(0, sum(1 for line in csv.reader(
                line for line in stream if not line.startswith('#'))) - 1)
    except FileNotFoundError:
        return 0


def _run(ros, command, process_name: str) -> str:
    """Run a one-shot command to its end while ``ros`` spins; return its log."""
    process = subprocess.Popen(command, stdout=subprocess.PIPE, stderr=subprocess.STDOUT,
                               text=True, env=_environment(), cwd=ROOT)
    assert ros.spin_until(lambda: process.poll() is not None, timeout=TIMEOUT), process_name
    log = process.communicate()[0]
    assert process.returncode == 0, log[-3000:]
    return log


def test_the_node_loads_only_what_its_body_needs(node):
    """The box body's node loads none of them; a URDF body's the URDF's libraries."""
    body, log, _ = node
    assert loaded(log) == (URDF_LIBRARIES if body == 'urdf' else set())


def test_the_recorder_loads_none_of_them_while_it_records(node, tmp_path):
    """From its start to its first row, for either body: the figure's libraries come at the end."""
    ros = node[2]
    prefix = tmp_path / 'run'
    recorder = processes.ChildProcess([str(BIN / 'mouse_record'), '-d', '60', '-o', str(prefix)],
                                      environment=_environment())
    try:
        _wait(ros, lambda: _rows(prefix.with_suffix('.csv')) > 0, recorder, 'the first row')
        assert loaded(recorder.log()) == set()
    finally:
        recorder.close()


def test_the_marker_loads_only_what_the_body_needs(node):
    """Once it serves the body: the box's CUBE, or the tool's pieces (its handle a CYLINDER)."""
    body, _, ros = node
    drawn = Marker.CYLINDER if body == 'urdf' else Marker.CUBE
    client = ros.probe.create_client(GetInteractiveMarkers, MARKER_SERVICE)

    def served() -> bool:
        # The marker as it stands, asked again until it holds the body: the one update that
        # brings the body may go before this process's reader matched the marker's writer.
        if not client.service_is_ready():
            return False
        response = call_until_answered(client, GetInteractiveMarkers.Request(), ros.executor,
                                       StopRequest(), deadline=time.monotonic() + TIMEOUT)
        return response is not None and any(
            piece.type == drawn for marker in response.markers for control in marker.controls
            for piece in control.markers)
    marker = processes.ChildProcess([str(BIN / 'mouse_marker')], environment=_environment())
    try:
        _wait(ros, served, marker, 'the body served')
        assert loaded(marker.log()) == (URDF_LIBRARIES if body == 'urdf' else set())
    finally:
        marker.close()


def _page_message(frame: bytes) -> bytes:
    """Return a frame of viser's websocket decompressed (from its zstd frame's magic on)."""
    import zstandard  # viser's, as the view's tests
    start = frame.find(ZSTD_MAGIC)
    return frame if start < 0 else zstandard.ZstdDecompressor().decompressobj().decompress(
        frame[start:])


def test_the_view_loads_only_what_the_body_needs(node):
    """Once a page got the body: the box, or the tool's pieces."""
    viser_client = pytest.importorskip('test_support.viser_client')
    body, _, ros = node
    drawn = b'/body/piece_0' if body == 'urdf' else b'/body'
    view = processes.ChildProcess([str(BIN / 'mouse_view'), '--port', '0'],
                                  environment=_environment())
    try:
        port, _ = viser_client.wait_for_address(view, timeout=TIMEOUT)
        frames = []
        with viser_client.connect(port, origin=f'http://127.0.0.1:{port}') as page:
            page.send(viser_client.camera((1.0, 1.0, 1.0), (0.0, 0.0, 0.0)))

            def drew() -> bool:
                try:
                    frames.append(_page_message(page.recv(timeout=0.05, decode=False)))
                except TimeoutError:
                    pass
                return any(drawn in frame for frame in frames)
            _wait(ros, drew, view, 'the body sent to the page')
        assert loaded(view.log()) == (URDF_LIBRARIES if body == 'urdf' else set())
    finally:
        view.close()


@pytest.mark.parametrize('command', [
    ['mouse_target', '0.1', '0.0', '0.7'],
    ['mouse_wrench', '--force', '0.1', '0.0', '0.0', '--duration', '0.2'],
    ['mouse_ctl', 'release'],
], ids=lambda command: command[0])
def test_a_command_loads_none_of_them(node, command):
    """The one-shot commands, from their start to their exit, against either body."""
    ros = node[2]
    log = _run(ros, [str(BIN / command[0]), *command[1:]], command[0])
    assert loaded(log) == set()


@pytest.mark.parametrize('script', SCRIPTS)
def test_help_loads_none_of_them_nor_viser(script):
    """``--help`` prints and exits: no heavy library, nor the view's web server."""
    result = subprocess.run([str(BIN / script), '--help'], capture_output=True, text=True,
                            env=_environment(), cwd=ROOT, timeout=TIMEOUT)
    assert result.returncode == 0 and 'usage: ' + script in result.stdout, result.stderr[-3000:]
    assert loaded(result.stderr) == set()
    assert not re.search(r'\|\s*viser$', result.stderr, re.MULTILINE)
