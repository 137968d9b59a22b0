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
A body changed at run time: loaded off the tick, swapped in whole, or refused in one line.

The node keeps ticking while a new ``robot_description`` loads (the load is held at a gate
here, so that the ticks it lets run are certain, not a race with the machine); a change that
comes meanwhile is refused with the reason; a description that is refused leaves the body and
the parameters as they were and the node running. The fuzz sets 500 mutated URDFs
(``test_support.urdf_mutations``) one after the other on one node: each is taken, or refused
in one line, and the node ticks on. Through ROS, the executable answers a set at once and then
refuses it in one logged line, or takes it.
"""

import math
import threading

import pytest
from rcl_interfaces.srv import GetParameters, SetParameters
from rclpy.parameter import Parameter
from rclpy.qos import qos_profile_parameters
import trimesh

from mouse_constraint_ros.description import urdf_link
from mouse_constraint_ros.node.parameters import DEFAULTS, node_config
from test_support.hardening_tools import NodeProcess
from test_support.meshes import geometry, urdf, write
from test_support.processes import finish
from test_support.urdf_mutations import mutations

# Wall seconds a gate or a load may take before the test fails (a watchdog, not a timing).
WATCHDOG = 120.0
# The fuzz: how many mutated URDFs, and the generator's seed.
FUZZ_COUNT = 500
FUZZ_SEED = 50


def test_a_big_mesh_loads_while_the_ticks_run_and_comes_in_whole(simulated_body_factory,
                                                                 tmp_path, monkeypatch):
    """40 000 triangles on two circles: 300 ticks run while it loads; then it is the body."""
    body = simulated_body_factory()
    radius, height, density = 0.05, 0.2, 1000.0
    mesh = trimesh.creation.cylinder(radius=radius, height=height, sections=10000)
    assert len(mesh.faces) == 40000
    text = urdf([geometry('mesh', filename=str(write(mesh, tmp_path / 'roller.stl')))],
                link='roller')
    gate, reached = threading.Event(), threading.Event()
    load = urdf_link.body_model

    def gated(*args, **kwargs):
        reached.set()
        assert gate.wait(WATCHDOG), 'the test never opened the gate'
        return load(*args, **kwargs)
    monkeypatch.setattr(urdf_link, 'body_model', gated)
    body.step(10)
    box = body.node.simulation.settings
    start = body.time
    result = body.node.set_parameters_atomically([
        Parameter('robot_description', value=text), Parameter('density', value=density),
        Parameter('anchor', value=[0.0, 0.0, 0.0])])
    assert result.successful and body.node.body_loads.loading
    assert reached.wait(WATCHDOG)
    body.step(300)
    assert body.time == pytest.approx(start + 300 * 1e-3, abs=1e-9)
    assert body.node.simulation.settings is box
    with pytest.raises(ValueError, match='the body of the last change is still loading'):
        body.set_parameters(mass=3.0)
    gate.set()
    assert body.node.body_loads.wait(WATCHDOG)
    ticks = body.step_until(lambda: not body.node.body_loads.loading, max_ticks=100000)
    assert body.time == pytest.approx(start + (300 + ticks) * 1e-3, abs=1e-9)
    settings = body.node.simulation.settings
    assert settings is not box
    assert settings.body.mass == pytest.approx(density * math.pi * radius ** 2 * height,
                                               rel=1e-6)
    assert body.node.get_parameter('robot_description').value == text
    body.step(10)


def test_a_bad_body_is_refused_in_one_line_and_the_parameters_go_back(simulated_body_factory):
    """A collision with an empty geometry: refused naming link and element; the box ticks on."""
    body = simulated_body_factory()
    body.step(5)
    box = body.node.simulation.settings
    bad = '<robot name="r"><link name="b"><collision><geometry/></collision></link></robot>'
    with pytest.raises(ValueError) as refused:
        body.set_parameters(robot_description=bad)
    assert str(refused.value) == (
        "link 'b' <collision> needs one <geometry> holding one box, sphere, cylinder or mesh; "
        'it has 1 <geometry> holding nothing')
    assert body.node.get_parameter('robot_description').value == ''
    assert body.node.simulation.settings is box and not body.node.body_loads.loading
    body.step(5)
    assert body.time == pytest.approx(10e-3, abs=1e-12)


def test_500_mutated_urdfs_are_each_taken_or_refused_in_one_line(simulated_body_factory,
                                                                 tmp_path):
    """At run time, one node: no input ends it, each refusal is one line, the body unchanged."""
    cases = mutations(tmp_path, FUZZ_COUNT, FUZZ_SEED)
    body = simulated_body_factory(anchor=[0.0, 0.0, 0.0])
    taken = refused = 0
    for index, (text, link, density) in enumerate(cases):
        settings = body.node.simulation.settings
        before = {name: body.node.get_parameter(name).value
                  for name in ('robot_description', 'body_link', 'density')}
        try:
            body.set_parameters(robot_description=text, body_link=link, density=density)
        except ValueError as error:
            reason = str(error)
            assert reason and '\n' not in reason, (index, reason)
            assert body.node.simulation.settings is settings, (index, reason)
            assert {name: body.node.get_parameter(name).value for name in before} == before
            refused += 1
        else:
            taken += 1
        body.step()
        assert body.time == pytest.approx((index + 1) * 1e-3, abs=1e-9)
    assert taken + refused == FUZZ_COUNT and taken and refused


def test_the_mutated_urdfs_are_refused_at_start_in_one_line_too(tmp_path):
    """As start-up reads them (``node_config``): a configuration, or one line."""
    for text, link, density in mutations(tmp_path, FUZZ_COUNT, FUZZ_SEED):
        values = dict(DEFAULTS, robot_description=text, body_link=link, density=density,
                      anchor=[0.0, 0.0, 0.0])
        try:
            node_config(values)
        except ValueError as error:
            assert str(error) and '\n' not in str(error)


@pytest.mark.system
def test_through_ros_a_bad_body_is_refused_and_a_good_one_comes_in(ros, tmp_path):
    """
    The executable (its own executor and tick loop): both sets are answered at once.

    The bad one is then refused in one logged line and its parameter set back, the node
    running; the cylinder of 40 000 triangles is then the body.
    """
    bad = '<robot name="r"><link name="b"><collision><geometry/></collision></link></robot>'
    mesh = trimesh.creation.cylinder(radius=0.05, height=0.2, sections=10000)
    good = urdf([geometry('mesh', filename=str(write(mesh, tmp_path / 'roller.stl')))],
                link='roller')
    node = NodeProcess('-p', 'density:=1000.0', '-p', 'anchor:=[0.0, 0.0, 0.0]')
    try:
        client = ros.probe.create_client(SetParameters, '/mouse_constraint/set_parameters',
                                         qos_profile=qos_profile_parameters)
        getter = ros.probe.create_client(GetParameters, '/mouse_constraint/get_parameters',
                                         qos_profile=qos_profile_parameters)
        assert ros.spin_until(lambda: client.service_is_ready() and getter.service_is_ready(),
                              timeout=20.0), node.log()
        assert ros.discovered_by('/mouse_constraint'), node.log()

        def description() -> str:
            future = getter.call_async(GetParameters.Request(names=['robot_description']))
            assert ros.spin_until(future.done)
            return future.result().values[0].string_value

        for text, logged in ((bad, "robot_description refused: link 'b' <collision> needs one "
                                   '<geometry>'),
                             (good, "parameters changed: 1000 Hz x 2 substeps in frame 'world': "
                                    "link 'roller'")):
            future = client.call_async(SetParameters.Request(
                parameters=[Parameter('robot_description', value=text).to_parameter_msg()]))
            assert ros.spin_until(future.done, timeout=20.0)
            assert future.result().results[0].successful
            assert ros.spin_until(lambda: logged in node.log(), timeout=WATCHDOG), node.log()
        assert node.alive()
        assert description() == good
    finally:
        exit_code, log = finish(node)
    assert exit_code == 0, log[-2000:]
    refusals = [line for line in log.splitlines() if 'robot_description refused' in line]
    assert len(refusals) == 1 and 'Traceback' not in log, log[-2000:]


def test_other_changes_do_not_read_the_urdf_again(simulated_body_factory, tmp_path,
                                                  monkeypatch):
    """A grab's anchor, a valid change, a value out of its range: the body loaded is kept."""
    mesh = trimesh.creation.cylinder(radius=0.05, height=0.2, sections=64)
    text = urdf([geometry('mesh', filename=str(write(mesh, tmp_path / 'roller.stl')))],
                link='roller')
    body = simulated_body_factory(robot_description=text, density=1000.0,
                                  anchor=[0.0, 0.0, 0.0])

    def read(*_args, **_kwargs):
        raise AssertionError('the URDF was read again')
    monkeypatch.setattr(urdf_link, 'body_model', read)
    settings = body.node.simulation.settings
    body.step(2)
    body.grab(body.pose.position)
    body.set_parameters(anchor=[0.0, 0.0, 0.05], max_force=100.0)
    with pytest.raises(ValueError, match='rate_hz'):
        body.set_parameters(rate_hz=0.5)
    assert body.node.simulation.settings.body == settings.body
    body.step(5)


def test_a_description_too_long_is_refused_in_the_set_itself(simulated_body_factory):
    """Over the limit: the set's own answer says so; nothing loads, nothing is published."""
    body = simulated_body_factory()
    text = urdf([geometry('box', size=(0.1, 0.1, 0.1)), '<!--' + 'x' * 5 * 2 ** 20 + '-->'])
    result = body.node.set_parameters_atomically([Parameter('robot_description', value=text)])
    assert not result.successful and not body.node.body_loads.loading
    assert result.reason.startswith('robot_description is 5.0 MiB, over the limit of 4 MiB')
    assert body.node.get_parameter('robot_description').value == ''
