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
``make demo`` as it runs: the recording holds every target published, the committed figure stays.

The demo script runs once, into a temporary output folder, with the executables of this venv.
Each ``mouse_target`` waits for the node and ``mouse_record`` (``--subscribers 2``) before it
publishes, so the MCAP holds exactly the grab and the targets the commands say they published,
in order: the grab point, the circle, the jump.
"""

import ast
import math
import os
from pathlib import Path
import re
import subprocess
import sys
import time

import pytest

from mouse_constraint_ros.node.mouse_constraint_node import MouseConstraintNode

ROOT = Path(__file__).resolve().parent.parent
BIN = Path(sys.executable).parent
RADIUS = 0.3


def logged_point(log: str, what: str) -> list:
    """Return the points of the log's lines '<what> (x, y, z) in ... received on'."""
    return [ast.literal_eval(match) for match in
            re.findall(rf'\] \[mouse_target\]: {what} (\([^)]*\)) in .* received on', log)]


@pytest.fixture(scope='module')
def demo(tmp_path_factory):
    """Run demo/run_demo.sh into a temporary folder; return the folder and the script's run."""
    output = tmp_path_factory.mktemp('demo')
    figure = (ROOT / 'demo' / 'figure.png').read_bytes()
    environment = dict(os.environ, DEMO_OUTPUT=str(output), DEMO_BIN=str(BIN),
                       SETTLE_SECONDS='1')
    run = subprocess.run([str(ROOT / 'demo' / 'run_demo.sh')], capture_output=True, text=True,
                         env=environment, timeout=180)
    assert (ROOT / 'demo' / 'figure.png').read_bytes() == figure
    return output, run


def test_demo_writes_its_outputs_where_asked_and_leaves_the_committed_figure(demo):
    """Exit 0; the figure, CSV and MCAP in DEMO_OUTPUT; demo/figure.png as it was."""
    output, run = demo
    assert run.returncode == 0, run.stdout + run.stderr
    assert f'figure, CSV and MCAP in {output}/' in run.stdout
    for name in ('figure.png', 'recording.png', 'recording.csv', 'recording.mcap'):
        assert (output / name).stat().st_size > 0, name


def test_the_recording_holds_every_target_published_in_order(demo):
    """The MCAP's grab and targets are those the commands published: none lost, in order."""
    reader_module = pytest.importorskip('mcap.reader')
    mcap_ros2 = pytest.importorskip('mcap_ros2.decoder')
    output, run = demo
    assert run.returncode == 0, run.stdout + run.stderr
    log = (output / 'target.log').read_text()
    [grab] = logged_point(log, 'grab')
    targets = logged_point(log, 'target')
    assert len(targets) == 2 and targets[0] == grab
    [count] = [int(n) for n in re.findall(r'(\d+) targets published on /target$', log, re.M)]
    assert count > 150   # 4 s at 50 Hz
    with open(output / 'recording.mcap', 'rb') as stream:
        reader = reader_module.make_reader(stream, decoder_factories=[mcap_ros2.DecoderFactory()])
        decoded = [(channel.topic, (m.point.x, m.point.y, m.point.z)) for _, channel, _, m
                   in reader.iter_decoded_messages(topics=['/grab', '/target'])]
    assert [p for topic, p in decoded if topic == '/grab'] == [grab]
    recorded = [p for topic, p in decoded if topic == '/target']
    assert len(recorded) == count + 2
    assert recorded[0] == grab and recorded[-1] == targets[1]
    centre = (grab[0] - RADIUS, grab[1])
    for x, y, z in recorded[1:-1]:
        assert math.hypot(x - centre[0], y - centre[1]) == pytest.approx(RADIUS, abs=1e-12)
        assert z == grab[2]


def test_the_recording_knows_the_nodes_tick_grid(demo):
    """With --anchor the recorder still reads the node's rates: the grid is the node's 1 kHz."""
    output, run = demo
    assert run.returncode == 0, run.stdout + run.stderr
    with open(output / 'recording.csv') as stream:
        comments = [line for line in stream if line.startswith('#')]
    assert '# grid: 1000 Hz, every tick published\n' in comments
    assert 'was not read' not in (output / 'record.log').read_text()


def test_the_summary_reads_the_run_phase_by_phase(demo):
    """demo/summary.py finds the grab, the circle and the jump; the circle is followed closely."""
    output, run = demo
    assert run.returncode == 0, run.stdout + run.stderr
    result = subprocess.run([sys.executable, str(ROOT / 'demo' / 'summary.py'), str(output)],
                            capture_output=True, text=True, timeout=60)
    assert result.returncode == 0, result.stderr
    lines = result.stdout.splitlines()
    assert [line.split()[0] for line in lines] == ['grab', 'circle', 'after', 'jump', 'whole']
    circle = re.search(r'median ([\d.e-]+) mm, .* from 0.2 s into it largest ([\d.e-]+) mm',
                       lines[1])
    # Measured against the target path, the median is well under the 19 mm a target moves
    # between two (against the latest target it is about half of that). The largest is a wall-
    # clock figure: 0.5 to 0.7 mm mostly, 5.4 mm for 40 ms once on a loaded machine where a
    # target of the 50 Hz stream came 3 ms late, never the fling of a stream extrapolated on.
    assert float(circle.group(1)) < 1.0 and float(circle.group(2)) < 19.0, lines[1]


def test_a_node_already_running_stops_the_demo_at_once(ros, tmp_path):
    """
    ``make run`` left running: the demo says a mouse_constraint runs, where, and exits 1.

    Nothing is started (no node log): the other node would have taken the demo's grab.
    """
    ros.add(MouseConstraintNode(context=ros.context))
    environment = dict(os.environ, DEMO_OUTPUT=str(tmp_path), DEMO_BIN=str(BIN))
    start = time.monotonic()
    run = subprocess.run([str(ROOT / 'demo' / 'run_demo.sh')], capture_output=True, text=True,
                         env=environment, timeout=120)
    assert run.returncode == 1, run.stdout + run.stderr
    domain = os.environ['ROS_DOMAIN_ID']
    assert (f'a mouse_constraint is already running: /mouse_constraint in namespace / on '
            f'ROS_DOMAIN_ID {domain}') in run.stderr
    assert 'Traceback' not in run.stderr and not (tmp_path / 'node.log').exists()
    assert time.monotonic() - start < 30.0
