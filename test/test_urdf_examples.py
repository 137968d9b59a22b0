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
The shipped URDF bodies of config/ and the parameters file that carries a URDF's text.

The tool's <inertial> is that of its two solids (a wooden handle, a steel head), derived here
from their sizes and densities; the mug weighs its closed mesh and its handle at the density of
config/mug.yaml. Both start as nodes with config/params.yaml and their own .yaml.
"""

import math
from pathlib import Path
from xml.etree import ElementTree

import numpy as np
import pytest
import trimesh
import yaml

from mouse_constraint_ros.cli.urdf_params import main, params_text
from mouse_constraint_ros.description.urdf_link import body_model
from mouse_constraint_ros.node.parameters import DEFAULTS, node_config

ROOT = Path(__file__).resolve().parent.parent
CONFIG = ROOT / 'config'


def shipped(name: str) -> dict:
    """Return config/params.yaml's parameters, config/<name>.yaml's and the URDF's over them."""
    values = dict(DEFAULTS)
    for path in (CONFIG / 'params.yaml', CONFIG / f'{name}.yaml'):
        values.update(yaml.safe_load(path.read_text())['/**']['ros__parameters'])
    values['robot_description'] = (CONFIG / f'{name}.urdf').read_text()
    return values


def source_tree(package: str) -> str:
    """Find ``package://mouse_constraint_ros/`` in the source tree (its share/ mirrors it)."""
    assert package == 'mouse_constraint_ros'
    return str(ROOT)


def solid(mass: float, inertia: np.ndarray, centre, com) -> np.ndarray:
    """Return a solid's inertia about ``com`` by the parallel axis theorem."""
    d = np.subtract(centre, com)
    return inertia + mass * (d @ d * np.eye(3) - np.outer(d, d))


def test_the_tool_inertial_is_its_handle_and_head():
    """Mass, COM and inertia of the tool's <inertial> are its solids' to the digits written."""
    handle_mass = 700.0 * math.pi * 0.015 ** 2 * 0.3
    handle = np.diag([handle_mass * (3 * 0.015 ** 2 + 0.3 ** 2) / 12] * 2
                     + [0.5 * handle_mass * 0.015 ** 2])
    size = np.array([0.1, 0.03, 0.03])
    head_mass = 7850.0 * float(np.prod(size))
    head = head_mass / 12 * np.diag([size[1] ** 2 + size[2] ** 2, size[0] ** 2 + size[2] ** 2,
                                     size[0] ** 2 + size[1] ** 2])
    mass = handle_mass + head_mass
    com = (handle_mass * np.array([0.0, 0.0, -0.15])
           + head_mass * np.array([0.02, 0.005, -0.315])) / mass
    inertia = solid(handle_mass, handle, (0.0, 0.0, -0.15), com) + solid(
        head_mass, head, (0.02, 0.005, -0.315), com)
    inertial = ElementTree.parse(CONFIG / 'tool.urdf').find('link/inertial')
    assert float(inertial.find('mass').get('value')) == pytest.approx(mass, abs=5e-4)
    written = [float(c) for c in inertial.find('origin').get('xyz').split()]
    assert written == pytest.approx(com, abs=5e-5)
    moments = inertial.find('inertia')
    for name, (i, j) in (('ixx', (0, 0)), ('ixy', (0, 1)), ('ixz', (0, 2)), ('iyy', (1, 1)),
                         ('iyz', (1, 2)), ('izz', (2, 2))):
        assert float(moments.get(name)) == pytest.approx(inertia[i, j], rel=2e-3, abs=5e-8)


def test_the_mug_weighs_its_mesh_and_handle_at_its_density():
    """The mug's mass is density x (the cup's volume + the handle's)."""
    model = body_model(shipped('mug')['robot_description'], density=2400.0,
                       find_package=source_tree)
    volume = trimesh.load(CONFIG / 'mug.stl').volume + 0.012 * 0.02 * 0.06
    assert model.mass == pytest.approx(2400.0 * volume, rel=1e-9)
    assert [p.kind for p in model.geometry.collisions] == ['mesh', 'box']


@pytest.mark.parametrize('name', ['tool', 'mug'])
def test_each_example_configures_a_node(name, monkeypatch, tmp_path):
    """
    config/params.yaml, then config/<name>.yaml and the URDF: a valid node configuration.

    The package:// mesh resolves through the ament index of a prefix laid out as make run's
    (share/mouse_constraint_ros/config linked to the source's).
    """
    index = tmp_path / 'share' / 'ament_index' / 'resource_index' / 'packages'
    index.mkdir(parents=True)
    (index / 'mouse_constraint_ros').touch()
    (tmp_path / 'share' / 'mouse_constraint_ros').mkdir()
    (tmp_path / 'share' / 'mouse_constraint_ros' / 'config').symlink_to(CONFIG)
    monkeypatch.setenv('AMENT_PREFIX_PATH', str(tmp_path))
    config = node_config(shipped(name))
    assert config.geometry.link == name and config.body_frame_id == name
    assert config.settings.floor.enabled


def test_the_params_file_carries_the_urdf_text_whole(tmp_path):
    """Every character of the URDF (quotes, colons, newlines) comes back from the YAML."""
    for urdf in sorted(CONFIG.glob('*.urdf')):
        text = urdf.read_text()
        assert yaml.safe_load(params_text(text))['/**']['ros__parameters'][
            'robot_description'] == text
        target = tmp_path / (urdf.stem + '.yaml')
        assert main([str(urdf), str(target)]) == 0
        assert target.read_text() == params_text(text, str(urdf.resolve()))
    assert main([str(tmp_path / 'absent.urdf'), str(tmp_path / 'out.yaml')]) == 2
    assert main([]) == 2


def test_each_example_is_text_to_yaml_as_a_p_override():
    """
    The shipped URDFs read as one YAML string: ``-p robot_description:="$(cat f.urdf)"`` works.

    rcl reads an override's value as YAML: a ': ' or ' #' in a comment would make the text a
    mapping or cut it short.
    """
    for urdf in sorted(CONFIG.glob('*.urdf')):
        text = urdf.read_text()
        assert isinstance(yaml.safe_load(text), str), urdf.name
        assert ': ' not in text and ' #' not in text, urdf.name
