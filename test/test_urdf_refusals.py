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
A bad URDF body is refused in one line that says what is wrong and how to mend it.

Each input of ``test_support.meshes.bad_bodies`` (malformed XML, a missing link, a mesh that
does not exist, is not closed, is 100 MB or lies in a package that cannot be found, a
non-physical inertia, a zero mass, no inertia and no density) is refused by the parser, by the
node's configuration (start-up, ``ros2 param set``) and by the harness, never with a traceback;
``test_startup_refusals`` starts the executable with each.
"""

import pytest
import trimesh

from mouse_constraint_ros.description.urdf_link import body_model
from mouse_constraint_ros.node.parameters import DEFAULTS, node_config
from mouse_constraint_ros.node.startup import StartupRefusal
from test_support.meshes import bad_bodies, BAD_BODY_NAMES


@pytest.fixture
def cases(tmp_path):
    """Return the bad bodies, their meshes written into ``tmp_path``."""
    return bad_bodies(tmp_path)


@pytest.mark.parametrize('name', BAD_BODY_NAMES)
def test_the_parser_refuses_it_in_one_line(cases, name):
    """``body_model`` raises one ValueError line with the reason; nothing else escapes."""
    text, link, words = cases[name]
    with pytest.raises(ValueError) as refused:
        body_model(text, link)
    message = str(refused.value)
    assert words in message and '\n' not in message, message


@pytest.mark.parametrize('name', BAD_BODY_NAMES)
def test_the_node_configuration_names_the_parameter(cases, name):
    """As start-up and ``ros2 param set`` see it: one line, the same reason."""
    text, link, words = cases[name]
    with pytest.raises(ValueError) as refused:
        node_config(dict(DEFAULTS, robot_description=text, body_link=link))
    assert words in str(refused.value) and '\n' not in str(refused.value)


def test_a_huge_mesh_is_refused_before_it_is_read(cases, monkeypatch):
    """The size is checked first: the 100 MB file is refused unread."""
    text, link, _ = cases['huge mesh']

    def read(*_args, **_kwargs):
        raise AssertionError('the huge mesh was read')
    monkeypatch.setattr(trimesh, 'load', read)
    with pytest.raises(ValueError, match='over the limit'):
        body_model(text, link)


@pytest.mark.parametrize('name', ['malformed XML', 'zero mass'])
def test_the_harness_refuses_it_as_the_node_would(cases, name, simulated_body_factory):
    """``SimulatedBody(robot_description=...)`` raises ``StartupRefusal`` with the reason."""
    text, link, words = cases[name]
    with pytest.raises(StartupRefusal, match=words):
        simulated_body_factory(robot_description=text, body_link=link)
