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
A URDF whose XML declaration states a version other than 1.0 (pybullet's ``0.0``).

It is read as XML 1.0 and the node warns once in a line, at start and when it is set at run
time; a declaration of 1.0, or none, says nothing.
"""

import pytest

from mouse_constraint_ros.description.urdf_link import body_model
from mouse_constraint_ros.description.xml_declaration import (as_xml_1_0, declared_version,
                                                              version_note)

BODY = ('<robot name="cube"><link name="cube"><inertial><mass value="1.0"/>'
        '<inertia ixx="0.1" ixy="0" ixz="0" iyy="0.1" iyz="0" izz="0.1"/></inertial>'
        '<collision><geometry><box size="0.1 0.1 0.1"/></geometry></collision></link></robot>')
PYBULLET = '<?xml version="0.0" ?>\n' + BODY


@pytest.mark.parametrize('declaration, version', [
    ('<?xml version="0.0" ?>', '0.0'), ("<?xml version='1.1'?>", '1.1'),
    ('\ufeff  <?xml  version = "2" encoding="utf-8"?>', '2'), ('<?xml version="1.0"?>', '1.0'),
    ('', None)])
def test_the_declared_version_is_read_and_made_1_0(declaration, version):
    """The version is found after a byte order mark or blanks, and only it is changed."""
    text = declaration + '\n' + BODY
    assert declared_version(text) == version
    made = as_xml_1_0(text)
    assert declared_version(made) == (None if version is None else '1.0')
    assert made == (text if version is None else text.replace(version, '1.0', 1))
    assert (version_note(text) is None) == (version in (None, '1.0'))


def test_pybullets_declaration_is_read_as_xml_1_0():
    """``<?xml version="0.0" ?>``: the body loads; the note names the version and the fix."""
    model = body_model(PYBULLET, 'cube')
    assert model.mass == 1.0 and model.geometry.link == 'cube'
    assert version_note(PYBULLET) == (
        "robot_description declares XML version '0.0': read as XML 1.0 (write "
        '<?xml version="1.0"?> to silence this)')


def test_the_node_warns_at_start_and_at_run_time(simulated_body_factory, capfd):
    """The warning comes at start and with a change to such a text; a 1.0 text is silent."""
    body = simulated_body_factory(robot_description=PYBULLET, body_link='cube')
    assert version_note(PYBULLET) in capfd.readouterr().err
    body.set_parameters(robot_description=BODY)
    assert 'XML version' not in capfd.readouterr().err
    body.set_parameters(robot_description=PYBULLET.replace('0.0', '1.1', 1))
    [warning] = [line for line in capfd.readouterr().err.splitlines() if 'XML version' in line]
    assert "declares XML version '1.1': read as XML 1.0" in warning
