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
package.xml declares what the code imports, so that rosdep installs it for ``colcon test``.

Every module outside the standard library and this repository that the package, the launch file
or the tests import is a rosdep key of package.xml: an exec_depend for what the package and the
launch file import, a test_depend (or exec_depend) for what only the tests import. ROS packages
are keys by their own name; the Python libraries by the keys rosdep knows them by.
"""

import ast
from pathlib import Path
import sys
from xml.etree import ElementTree

ROOT = Path(__file__).resolve().parent.parent
LOCAL = {'mouse_constraint_ros', 'test_support', 'bench', 'conftest'}
# rosdep keys of the Python libraries (rosdistro's rosdep/python.yaml).
PYTHON_KEYS = {'numpy': 'python3-numpy', 'yaml': 'python3-yaml', 'scipy': 'python3-scipy',
               'matplotlib': 'python3-matplotlib', 'hypothesis': 'python3-hypothesis',
               'pytest': 'python3-pytest', 'PIL': 'python3-pil',
               'lxml': 'python3-lxml', 'trimesh': 'python3-trimesh', 'rtree': 'python3-rtree',
               'mcap': 'mcap-ros2-support', 'mcap_ros2': 'mcap-ros2-support',
               # test_lint.py runs flake8 in-process: ament_flake8 brings it with its plugins.
               'flake8': 'ament_flake8'}
# Imported by the package only for an option, and declared for the tests: mcap writes
# ``mouse_record --mcap`` files (requirements/viz.txt), imported when that option is given;
# pytest by the package's pytest plugin (``testing/pytest_plugin.py``), which only pytest loads.
OPTIONAL = {'mcap', 'pytest'}
# No rosdep key: viser serves ``mouse_view`` alone (and the tests of the view skip without it);
# package.xml names it in a comment and the ROS-native route installs it with pip
# (requirements/view.txt). websockets, msgspec and zstandard come with it: the view bounds
# viser's websocket server, and the view's tests speak its protocol and read its compressed
# frames.
# yourdfpy (the URDF parser) has no rosdep key either: package.xml says to pip-install it.
UNKEYED = {'viser', 'websockets', 'msgspec', 'zstandard', 'yourdfpy'}


def imported(paths) -> set:
    """Return the top-level modules ``paths`` import, outside the standard library and here."""
    modules = set()
    for path in paths:
        for node in ast.walk(ast.parse(path.read_text())):
            if isinstance(node, ast.Import):
                names = [alias.name for alias in node.names]
            elif isinstance(node, ast.ImportFrom) and node.level == 0:
                names = [node.module]
            else:
                continue
            modules.update(name.split('.')[0] for name in names)
    return modules - set(sys.stdlib_module_names) - LOCAL


def key(module: str) -> str:
    """Return the rosdep key of ``module``."""
    return PYTHON_KEYS.get(module, module)


def test_package_xml_declares_every_import():
    """The package's and launch file's imports are exec_depends; the tests' imports are keys."""
    package = ElementTree.parse(ROOT / 'package.xml').getroot()

    def keys(*tags: str) -> set:
        return {element.text for tag in tags for element in package.iter(tag)}
    run = keys('exec_depend', 'depend')
    test = keys('test_depend') | run
    shipped = imported([*(ROOT / 'mouse_constraint_ros').rglob('*.py'),
                        *(ROOT / 'launch').glob('*.py')])
    tests = imported([*(ROOT / 'test').glob('*.py'), *(ROOT / 'test_support').glob('*.py')])
    assert {'rclpy', 'numpy', 'launch_ros'} <= shipped and {'pytest', 'scipy'} <= tests
    assert sorted(key(m) for m in shipped - OPTIONAL - UNKEYED if key(m) not in run) == []
    assert sorted(key(m) for m in (tests | OPTIONAL) - UNKEYED if key(m) not in test) == []
