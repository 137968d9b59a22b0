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
``package://mouse_constraint_ros/...`` without a workspace: the package finds its own files.

With no ``AMENT_PREFIX_PATH``, or one that does not list the package, the shipped mug's mesh
resolves to the source tree's, and in an installed layout to ``share/mouse_constraint_ros`` of
its prefix; another package's ``package://`` is still refused with the way round. The lockstep
harness starts the shipped mug so, with no variable set.
"""

import importlib.util
from pathlib import Path
import shutil

import pytest

from mouse_constraint_ros.description.mesh_files import mesh_path
from mouse_constraint_ros.description.own_share import __file__ as OWN_SHARE_FILE
from mouse_constraint_ros.testing import SimulatedBody

ROOT = Path(__file__).resolve().parent.parent
MUG = 'package://mouse_constraint_ros/config/mug.stl'


def test_the_package_finds_its_own_mesh_with_no_workspace(monkeypatch):
    """No AMENT_PREFIX_PATH: the mug's mesh is the source tree's; another package is refused."""
    monkeypatch.delenv('AMENT_PREFIX_PATH', raising=False)
    assert Path(mesh_path(MUG)) == ROOT / 'config' / 'mug.stl'
    with pytest.raises(ValueError, match=r"'package://other_package/m.stl' cannot be resolved: "
                                         r'AMENT_PREFIX_PATH is not set.*file:///absolute/path'):
        mesh_path('package://other_package/m.stl')


def test_the_package_finds_its_own_mesh_when_the_index_does_not_list_it(monkeypatch, tmp_path):
    """A sourced workspace of other packages: the package's own files are still found."""
    (tmp_path / 'share' / 'ament_index' / 'resource_index' / 'packages').mkdir(parents=True)
    monkeypatch.setenv('AMENT_PREFIX_PATH', str(tmp_path))
    assert Path(mesh_path(MUG)) == ROOT / 'config' / 'mug.stl'


def own_share_installed_in(prefix: Path):
    """Return ``own_share`` of a copy of its module laid out as installed in ``prefix``."""
    folder = prefix / 'lib' / 'python3.11' / 'site-packages' / 'mouse_constraint_ros'
    (folder / 'description').mkdir(parents=True)
    shutil.copy(OWN_SHARE_FILE, folder / 'description' / 'own_share.py')
    spec = importlib.util.spec_from_file_location(
        'installed_own_share', folder / 'description' / 'own_share.py')
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module.own_share


def test_an_installed_package_finds_the_share_of_its_prefix(tmp_path):
    """Installed under a prefix (colcon's, a venv's data_files): prefix/share/<package>."""
    share = tmp_path / 'prefix' / 'share' / 'mouse_constraint_ros'
    (share / 'config').mkdir(parents=True)
    shutil.copy(ROOT / 'package.xml', share / 'package.xml')
    assert own_share_installed_in(tmp_path / 'prefix')() == str(share)
    assert own_share_installed_in(tmp_path / 'bare')() is None


def test_the_harness_starts_the_shipped_mug_with_no_workspace(monkeypatch):
    """The harness with the shipped mug and no AMENT_PREFIX_PATH: it starts, the handle grabs."""
    monkeypatch.delenv('AMENT_PREFIX_PATH', raising=False)
    with SimulatedBody(robot_description=(ROOT / 'config' / 'mug.urdf').read_text(),
                       body_link='mug', density=2400.0, initial_position=[0.0, 0.0, 0.3],
                       gravity=[0.0, 0.0, 0.0]) as body:
        assert body.grab((0.052, 0.0, 0.35)) == pytest.approx((0.052, 0.0, 0.05), abs=1e-9)
