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

"""The device presets of config/: each on config/haptic.yaml, and the documented command run."""

from pathlib import Path
import shlex
import signal
import subprocess
import sys

from geometry_msgs.msg import PoseStamped
import numpy as np
import pytest
from scipy.spatial.transform import Rotation
from std_msgs.msg import Float64MultiArray
import yaml

from mouse_constraint_ros.node.parameters import DEFAULTS, node_config

ROOT = Path(__file__).resolve().parent.parent
BIN = Path(sys.executable).parent
PRESETS = ('forcedimension', 'sensable_phantom', 'touch')
G = 9.80665


def parameters(name: str) -> dict:
    """Return the ros__parameters of config/``name``.yaml."""
    path = ROOT / 'config' / f'{name}.yaml'
    return yaml.safe_load(path.read_text())['/**']['ros__parameters']


def preset_config(name: str):
    """Return the configuration of config/haptic.yaml with the preset ``name`` loaded after."""
    return node_config({**DEFAULTS, **parameters('haptic'), **parameters(name)})


@pytest.mark.parametrize('name', PRESETS)
def test_each_preset_puts_the_device_origin_at_the_anchor_s_start(name):
    """Held at the centre of its workspace, the device holds the anchor where it starts."""
    config = preset_config(name)
    anchor = config.initial_anchor()
    np.testing.assert_allclose(config.device.mapping.from_world(anchor), (0.0, 0.0, 0.0),
                               rtol=0.0, atol=1e-15)
    assert config.device.frame_id == {'forcedimension': 'fd_base', 'sensable_phantom': 'base',
                                      'touch': '/map'}[name]
    assert config.publish_force


def test_the_phantom_s_y_up_frame_turns_into_the_world_s_z_up():
    """OpenHaptics: x right, y up, z toward the user; the world: z up, y away from the user."""
    rotation = Rotation.from_quat(preset_config('sensable_phantom').device.mapping.rotation)
    np.testing.assert_allclose(rotation.apply(np.eye(3)), [[1, 0, 0], [0, 0, 1], [0, -1, 0]],
                               atol=1e-15)


def documented_command(preset: str) -> list:
    """Return the shell line of docs/haptics.md that loads config/``preset``.yaml, as words."""
    page = (ROOT / 'docs' / 'haptics.md').read_text()
    for block in page.split('```bash\n')[1:]:
        code = block.split('```', 1)[0].replace('\\\n', ' ')
        if f'config/{preset}.yaml' in code:
            return shlex.split(code)
    raise AssertionError(f'no command with config/{preset}.yaml in docs/haptics.md')


@pytest.mark.ros
def test_the_documented_force_dimension_command_runs_and_sends_the_weight_to_the_driver(ros):
    """
    The line as written, against the driver's two topics: the array the driver takes.

    A stand-in publishes the handle at the origin of fd_base (the anchor's start) on
    /fd/ee_pose and reads /fd/fd_controller/commands: the held box's weight, [0, 0, -m g].
    """
    words = documented_command('forcedimension')
    assert words[0] == '.venv/bin/mouse_constraint_node'
    device = ros.probe.create_publisher(PoseStamped, '/fd/ee_pose', 10)
    commands = ros.collect(Float64MultiArray, '/fd/fd_controller/commands')
    process = subprocess.Popen([str(BIN / 'mouse_constraint_node'), *words[1:]], cwd=ROOT,
                               stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    pose = PoseStamped()
    pose.header.frame_id = 'fd_base'
    pose.pose.orientation.w = 1.0
    try:
        assert ros.discovered_by('/mouse_constraint')

        def held() -> bool:
            device.publish(pose)
            return len(commands) > 200

        assert ros.spin_until(held, timeout=30.0)
        process.send_signal(signal.SIGINT)
        process.wait(timeout=10.0)
    finally:
        process.kill()
    _, stderr = process.communicate()
    weight = parameters('haptic')['mass'] * G
    np.testing.assert_allclose(np.array(commands[-1].data), (0.0, 0.0, -weight), rtol=0.0,
                               atol=0.01 * weight)
    assert "hold the device there, at (0, 0, 0) in 'fd_base'" in stderr, stderr
    assert 'ignoring' not in stderr, stderr
