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

"""Mesh paths relative to the URDF file resolve against it when the node is given the file."""

from pathlib import Path

import numpy as np
import pytest

from mouse_constraint_ros.cli.urdf_params import params_text
from mouse_constraint_ros.description.relative_meshes import absolute_meshes, described
from mouse_constraint_ros.testing import SimulatedBody
from test_support.meshes import cube, geometry, inertial, urdf, write
from test_support.robots import double_pendulum


def lay_out(folder: Path) -> Path:
    """Write a cube mesh under meshes/ and a URDF naming it relative to itself; return it."""
    (folder / 'meshes').mkdir()
    write(cube(0.1), folder / 'meshes' / 'cube.stl')
    path = folder / 'robot' / 'body.urdf'
    path.parent.mkdir()
    text = urdf([inertial(1.0, (0.01, 0.0, 0.0, 0.01, 0.0, 0.01)),
                 geometry('mesh', filename='../meshes/cube.stl')])
    path.write_text(text)
    return path


def test_relative_filenames_are_joined_to_the_files_folder_and_others_kept():
    text = ('<mesh filename="a/b.stl"/><mesh scale="1 1 1" filename=\'c.stl\'/>'
            '<mesh filename="package://p/m.stl"/><mesh filename="/abs/m.stl"/>'
            '<mesh filename="file:///x.stl"/>')
    assert absolute_meshes(text, '/data/robot') == (
        '<mesh filename="/data/robot/a/b.stl"/><mesh scale="1 1 1" '
        "filename='/data/robot/c.stl'/><mesh filename=\"package://p/m.stl\"/>"
        '<mesh filename="/abs/m.stl"/><mesh filename="file:///x.stl"/>')


def test_without_the_file_a_relative_mesh_is_refused_naming_the_way_round(tmp_path):
    path = lay_out(tmp_path)
    from mouse_constraint_ros.node.startup import StartupRefusal
    with pytest.raises(StartupRefusal, match='neither package://'):
        SimulatedBody(robot_description=path.read_text())


def test_the_harness_and_the_node_read_the_file_and_resolve_its_meshes(tmp_path):
    path = lay_out(tmp_path)
    with SimulatedBody(urdf_path=path, hold_initial_anchor=False) as body:
        body.step()
        # The mesh is the body's: a grab on the cube's face lands (0.05 m from its centre).
        anchor = body.grab(body.pose.position + np.array((0.05, 0.0, 0.0)))
        assert np.allclose(anchor, (0.05, 0.0, 0.0), atol=1e-9)
        description = body.node.get_parameter('robot_description').value
        assert str(tmp_path / 'meshes' / 'cube.stl') in description


def test_a_robot_with_relative_meshes_loads_from_its_file(tmp_path):
    write(cube(0.04), tmp_path / 'tip.stl')
    text = double_pendulum().replace(
        '<link name="tip"/>', '<link name="tip"><collision><geometry><mesh filename="tip.stl"/>'
        '</geometry></collision></link>')
    path = tmp_path / 'pendulum.urdf'
    path.write_text(text)
    with SimulatedBody(urdf_path=path, substeps=1) as body:
        body.step()
        body.grab(body.pose.position + np.array((0.0, 0.0, -0.02)))
        assert body.node.simulation.grabbed_link == 'tip'


def test_make_runs_parameters_file_names_the_urdf_file(tmp_path):
    path = lay_out(tmp_path)
    assert f'robot_description_file: "{path}"' in params_text(path.read_text(), str(path))


def test_an_unreadable_file_is_one_line(tmp_path):
    with pytest.raises(ValueError, match='cannot be read') as refusal:
        described('', str(tmp_path / 'absent.urdf'))
    assert '\n' not in str(refusal.value)


def test_the_file_is_read_at_start_and_a_change_of_it_later_refused(tmp_path):
    path = lay_out(tmp_path)
    with SimulatedBody(urdf_path=path) as body:
        with pytest.raises(ValueError, match='robot_description_file is read at start'):
            body.set_parameters(robot_description_file=str(tmp_path / 'other.urdf'))
        body.set_parameters(robot_description_file=str(path))  # the same value: taken
