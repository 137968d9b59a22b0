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
The floor through the node: rest, slide and drop, markers, /diagnostics and refusals.

The node is stepped in lockstep with the shipped parameters (config/params.yaml: the floor at
z = 0): every tick's pose is there, stamped with its simulated time.
"""

import math

from diagnostic_msgs.msg import DiagnosticArray
import numpy as np
import pytest
from rclpy.node import Node
from visualization_msgs.msg import Marker, MarkerArray

from mouse_constraint_ros.node.startup import StartupRefusal
from test_support import floor_scenarios

SHIPPED = floor_scenarios.shipped()
WORLD = floor_scenarios.world()
G = -WORLD.gravity[2]
# Free, and nothing published but what a test reads.
QUIET = {'hold_initial_anchor': False, 'marker_rate_hz': 0.0, 'diagnostics_rate_hz': 0.0,
         'publish_tf': False}


def start(factory, **overrides):
    """Return a body with config/params.yaml (floor on at z = 0) and ``overrides``."""
    values = {**SHIPPED, **QUIET, **overrides}
    # The harness is the clock.
    for name in ('publish_clock', 'real_time_factor'):
        values.pop(name, None)
    return factory(**values)


def record_path(body) -> list:
    """Return the list each tick appends (t, x, y, z) of its published pose to."""
    rows = []
    body.add_tick_callback(lambda b: rows.append((b.pose.time, *b.pose.position)))
    return rows


def test_a_box_put_on_the_floor_comes_to_rest_and_stays(simulated_body_factory):
    """Put 1 cm above the floor: after 1 s at rest on it, and the poses stay within 0.1 mm."""
    body = start(simulated_body_factory, initial_position=[0.0, 0.0, WORLD.half_height + 0.01])
    simulation = body.node.simulation
    body.step(1000)
    state = simulation.state
    assert math.hypot(*state.linear_velocity) <= 1e-4
    assert math.hypot(*state.angular_velocity) <= 1e-3
    assert simulation.contact_count == 4
    rows = record_path(body)
    body.step(2000)
    settled = np.array(rows)
    assert len(settled) == 2000 and settled[-1, 0] == pytest.approx(3.0, abs=1e-12)
    assert np.max(np.linalg.norm(settled[:, 1:] - settled[0, 1:], axis=1)) <= 1e-4
    assert np.min(settled[:, 3]) >= WORLD.half_height - 1e-3


def test_a_wrench_above_the_friction_bound_slides_the_box_at_f_minus_mu_m_g(
        simulated_body_factory):
    """A wrench 2 mu m g along x through the COM, on the wrench topic: a = mu g within 2 %."""
    body = start(simulated_body_factory, initial_position=[0.0, 0.0, WORLD.half_height],
                 wrench_timeout=0.0)
    body.step(200)
    force = 2.0 * WORLD.floor.friction * WORLD.mass * G
    body.wrench((force, 0.0, 0.0))
    pushed_at = body.time
    rows = record_path(body)
    body.step(1500)
    path = np.array(rows)
    path = path[path[:, 0] > pushed_at + 0.3]
    acceleration = 2.0 * np.polyfit(path[:, 0], path[:, 1], 2)[0]
    expected = (force - WORLD.floor.friction * WORLD.mass * G) / WORLD.mass
    assert acceleration == pytest.approx(expected, rel=0.02)


def test_a_wrench_below_the_friction_bound_does_not_slide_the_box(simulated_body_factory):
    """Half the friction bound, for 2 s: the box moves at most 0.1 mm."""
    body = start(simulated_body_factory, initial_position=[0.0, 0.0, WORLD.half_height],
                 wrench_timeout=0.0)
    body.step(200)
    start_x = body.node.simulation.state.position[0]
    body.wrench((0.5 * WORLD.floor.friction * WORLD.mass * G, 0.0, 0.0))
    body.step(2000)
    assert abs(body.node.simulation.state.position[0] - start_x) <= 1e-4


@pytest.mark.parametrize('restitution, peak', [(0.5, 0.5 ** 2 * 0.5), (0.0, 0.0)])
def test_a_flat_drop_rebounds_to_e_squared_h(simulated_body_factory, restitution, peak):
    """Dropped flat from 0.5 m: the poses rebound to e^2 h within 5 % (e = 0: within 1 mm)."""
    body = start(simulated_body_factory, initial_position=[0.0, 0.0, WORLD.half_height + 0.5],
                 restitution=restitution)
    rows = record_path(body)
    body.step(1200)
    path = np.array(rows)
    bottom = path[:, 3] - WORLD.half_height
    # The first impact and the first rebound's flight, in closed form.
    impact = math.sqrt(2.0 * 0.5 / G)
    flight = 2.0 * restitution * impact
    after = (path[:, 0] > impact + 0.02) & (path[:, 0] < impact + max(flight - 0.02, 0.5))
    assert np.count_nonzero(after) > 20
    if restitution == 0.0:
        assert np.max(bottom[after]) <= 1e-3
    else:
        assert np.max(bottom[after]) == pytest.approx(peak, rel=0.05)


def test_the_target_pulling_the_box_into_the_floor_is_held_by_it(simulated_body_factory):
    """A target 0.5 m below the floor, on the target topic: the box goes at most 2 mm in."""
    body = start(simulated_body_factory, initial_position=[0.0, 0.0, WORLD.half_height],
                 hold_initial_anchor=True)
    simulation = body.node.simulation
    body.step(200)
    anchor = simulation.anchor_position()
    body.target((anchor[0], anchor[1], WORLD.floor.height - 0.5))
    deepest = [0.0]
    body.add_tick_callback(lambda b: deepest.append(floor_scenarios.depth(WORLD, simulation)))
    body.step(2000)
    assert math.hypot(*simulation.constraint_force) > 0.5 * WORLD.mass * G
    assert max(deepest) <= 2e-3


def test_markers_draw_the_floor_and_the_contacts_and_diagnostics_count_them(
        simulated_body_factory):
    """Resting: the floor plate at floor_height, four contact spheres, 'floor contacts' 4."""
    body = start(simulated_body_factory, initial_position=[0.0, 0.0, WORLD.half_height],
                 marker_rate_hz=20.0, diagnostics_rate_hz=10.0)
    viewer = Node('viewer', context=body.context)
    markers, diagnostics = [], []
    viewer.create_subscription(MarkerArray, '/mouse_constraint/markers', markers.append, 10)
    viewer.create_subscription(DiagnosticArray, '/diagnostics', diagnostics.append, 10)
    body.add_node(viewer)
    body.step(100)
    # Markers and diagnostics come on their own timers (wall time).
    count = len(markers), len(diagnostics)
    body.step_until(lambda: len(markers) > count[0] and len(diagnostics) > count[1],
                    max_ticks=100_000)
    by_name = {m.ns: m for m in markers[-1].markers}
    plate, contacts = by_name['floor'], by_name['contacts']
    assert plate.action == Marker.ADD and plate.type == Marker.CUBE
    assert plate.pose.position.z + 0.5 * plate.scale.z == pytest.approx(0.0, abs=1e-12)
    assert contacts.type == Marker.SPHERE_LIST and len(contacts.points) == 4
    for point in contacts.points:
        assert point.z == pytest.approx(0.0, abs=1e-3)
    statuses = {s.name.rpartition(': ')[2]: s for s in diagnostics[-1].status}
    values = {kv.key: kv.value for kv in statuses['constraint'].values}
    assert values['floor contacts'] == '4'
    assert body.node.simulation.contact_count == 4


@pytest.mark.parametrize('name, value, reason', [
    ('friction', -0.5, 'friction'),
    ('restitution', 1.5, 'restitution'),
    ('floor_height', math.nan, 'floor_height'),
    ('floor_height', 2.0, 'below floor_height'),
])
def test_bad_floor_parameters_are_refused_at_run_time_and_change_nothing(
        simulated_body_factory, name, value, reason):
    """ros2 param set of a bad value: refused in one line naming it; the settings unchanged."""
    body = start(simulated_body_factory, initial_position=[0.0, 0.0, 1.0])
    before = body.node.simulation.settings
    with pytest.raises(ValueError) as refused:
        body.set_parameters(**{name: value})
    assert reason in str(refused.value) and '\n' not in str(refused.value)
    assert body.node.simulation.settings is before


@pytest.mark.parametrize('name, value, reason', [
    ('friction', -0.5, 'friction'),
    ('restitution', 1.5, 'restitution'),
    ('floor_height', math.nan, 'floor_height'),
    ('initial_position', [0.0, 0.0, 0.0], 'below floor_height'),
])
def test_bad_floor_parameters_are_refused_at_start_in_one_line(simulated_body_factory, name,
                                                               value, reason):
    """At start: StartupRefusal whose one-line reason names the parameter."""
    with pytest.raises(StartupRefusal) as refused:
        start(simulated_body_factory, **{name: value})
    assert reason in str(refused.value) and '\n' not in str(refused.value)


def test_a_run_time_floor_change_takes_effect_and_reset_goes_back_above_it(
        simulated_body_factory):
    """Raise the floor under a falling box: it lands on the new height; reset goes back up."""
    body = start(simulated_body_factory, initial_position=[0.0, 0.0, 1.0])
    body.set_parameters(floor_height=0.3)
    body.step(1500)
    assert body.node.simulation.state.position[2] == pytest.approx(0.3 + WORLD.half_height,
                                                                   abs=1e-3)
    body.reset()
    assert body.node.simulation.state.position == (0.0, 0.0, 1.0)
