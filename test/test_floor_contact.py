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

"""The floor's contact solver against the closed forms of rest, sliding, bouncing and energy."""

import dataclasses
import math

from hypothesis import example, given, settings as hypothesis_settings, strategies as st
import numpy as np
import pytest
from scipy.spatial.transform import Rotation

from mouse_constraint_ros.physics import BodyState, MouseConstraint, MouseSimulation, RigidBody
from mouse_constraint_ros.physics import Settings
from mouse_constraint_ros.physics.floor import Floor
from mouse_constraint_ros.physics.limits import MAX_CONTACT_ITERATIONS, MAX_FRICTION
from test_support import floor_scenarios as scenarios

WORLD = scenarios.world()
G = -WORLD.gravity[2]


def test_the_core_default_has_no_floor():
    """Settings without a floor: the body falls through z = 0, as every accuracy test expects."""
    body = RigidBody.solid_box(WORLD.mass, WORLD.box)
    sim = MouseSimulation(Settings(body), BodyState((0.0, 0.0, 0.1)))
    for _ in range(1000):
        sim.step(0.001)
    assert not Settings(body).floor.enabled
    assert sim.state.position[2] < -4.0 and sim.contact_count == 0


def test_a_box_put_on_the_floor_settles_within_a_second_and_stays():
    """Dropped 1 cm tilted 2 deg: after 1 s |v| <= 1e-4, |w| <= 1e-3, then still for 10 s."""
    rest = scenarios.rest(WORLD)
    assert rest.speed <= 1e-4
    assert rest.spin <= 1e-3
    assert rest.penetration <= 1e-3
    assert rest.moved <= 1e-4
    assert rest.contacts == 4


def test_resting_contacts_carry_the_weight():
    """The four corners' normal impulses add up to m g h per substep (the weight)."""
    sim = scenarios.resting(WORLD)
    h = WORLD.dt / WORLD.substeps
    assert sim.contact_count == 4
    assert sum(impulse for _, impulse in sim.contacts) == pytest.approx(WORLD.mass * G * h,
                                                                        rel=1e-9)
    for point, _ in sim.contacts:
        assert point[2] == pytest.approx(WORLD.floor.height, abs=1e-9)


@pytest.mark.parametrize('ratio', [1.5, 3.0])
def test_a_push_above_the_friction_bound_accelerates_at_f_minus_mu_m_g(ratio):
    """F = ratio mu m g through the COM: the box slides at (F - mu m g) / m within 2 %."""
    mu = WORLD.floor.friction
    force = ratio * mu * WORLD.mass * G
    acceleration, _ = scenarios.slide(WORLD, force)
    assert acceleration == pytest.approx((force - mu * WORLD.mass * G) / WORLD.mass, rel=0.02)


@pytest.mark.parametrize('ratio', [0.5, 0.95])
def test_a_push_below_the_friction_bound_does_not_slide(ratio):
    """F = ratio mu m g: the box moves at most 0.1 mm in 2 s."""
    force = ratio * WORLD.floor.friction * WORLD.mass * G
    _, moved = scenarios.slide(WORLD, force)
    assert abs(moved) <= 1e-4


def test_a_flat_drop_with_restitution_half_rebounds_to_e_squared_h():
    """Dropped flat from 0.5 m with e = 0.5: the first rebound peaks at e^2 h within 5 %."""
    peak, _ = scenarios.drop(WORLD, height=0.5, restitution=0.5)
    assert peak == pytest.approx(0.5 ** 2 * 0.5, rel=0.05)


def test_a_flat_drop_without_restitution_does_not_bounce():
    """Dropped flat from 0.5 m with e = 0: it stays within 1 mm of the floor after landing."""
    _, bottom = scenarios.drop(WORLD, height=0.5, restitution=0.0)
    landed = int(np.argmax(np.array(bottom) < 1e-3))
    assert landed > 0
    assert max(bottom[landed:]) <= 1e-3


def test_the_mouse_pulling_the_body_into_the_floor_is_held():
    """The grabbed corner pulled 0.5 m into the floor, force bound and all: depth <= 2 mm."""
    assert scenarios.held_down(WORLD, depth_below=0.5) <= 2e-3


def test_a_bottom_corner_pulled_down_tips_the_box_and_is_held():
    """Grabbed at a bottom corner and pulled 0.5 m down and aside: depth <= 2 mm throughout."""
    constraint = MouseConstraint(anchor=(0.2, 0.1, -0.05), max_force_per_weight=20.0,
                                 angular_friction=0.25)
    sim = WORLD.simulation(BodyState((0.0, 0.0, WORLD.half_height)), constraint=constraint)
    anchor = sim.anchor_position()
    sim.target = (anchor[0] + 0.3, anchor[1], -0.5)
    deepest = 0.0
    for _ in range(3000):
        sim.step(WORLD.dt)
        deepest = max(deepest, scenarios.depth(WORLD, sim))
    assert deepest <= 2e-3


def test_the_wrench_and_the_floor_act_together():
    """A torque about z on the resting box turns it against friction; it stays on the floor."""
    sim = scenarios.resting(WORLD)
    sim.wrench = ((0.0, 0.0, 0.0), (0.0, 0.0, 20.0))
    for _ in range(500):
        sim.step(WORLD.dt)
    assert sim.state.angular_velocity[2] > 1.0
    assert scenarios.depth(WORLD, sim) <= 1e-3
    assert sim.state.position[2] == pytest.approx(WORLD.half_height, abs=1e-3)


@hypothesis_settings(max_examples=25, deadline=None)
@given(seed=st.integers(0, 2 ** 32 - 1),
       height=st.floats(0.3, 1.0),
       spin=st.tuples(*[st.floats(-10.0, 10.0)] * 3),
       restitution=st.one_of(st.just(1.0), st.just(0.0), st.floats(0.0, 1.0)),
       friction=st.floats(0.0, 1.5))
# Spun onto one corner: a contact whose friction undid its normal impulse, sweep after sweep.
@example(seed=0, height=1.0, spin=(1.71484375, 0.0, 2.640625), restitution=1.0, friction=1.0)
# Off one corner within a substep, gone by the step's end: the impact is still found.
@example(seed=1058, height=0.9453125, spin=(1.5, -5.5, -4.5), restitution=1.0, friction=0.0)
# A warm start that the sweeps could not undo, at a corner that now separates.
@example(seed=2121521665, height=0.7222751006953539,
         spin=(2.802149078009551, -1.3520188362239356, 7.738648175080272), restitution=0.0,
         friction=1.4000366780880542)
# Rocking onto an edge: one edge bounces and turns the other edge into the floor.
@example(seed=2871153081, height=0.39261444916575783,
         spin=(-6.515036200359237, 4.123992125668657, 0.5443691819093477),
         restitution=0.08769500045692191, friction=0.0)
def test_after_the_first_impact_the_energy_never_grows(seed, height, spin, restitution,
                                                       friction):
    """A box dropped tumbling: kinetic + potential energy never exceeds its least so far (1e-6)."""
    orientation = tuple(Rotation.random(random_state=seed).as_quat())
    energies, first = scenarios.tumble(WORLD, height=height, orientation=orientation,
                                       spin=spin, restitution=restitution, friction=friction)
    assert first >= 0
    after = np.array(energies[first:])
    growth = after - np.minimum.accumulate(after)
    assert np.max(growth) <= 1e-6 * abs(after[0])


EXTREME_FLOORS = st.fixed_dictionaries({
    'friction': st.sampled_from([0.0, 1e-9, 1.0, MAX_FRICTION]),
    'restitution': st.sampled_from([0.0, 1e-9, 0.5, 1.0]),
    'iterations': st.sampled_from([1, 2, MAX_CONTACT_ITERATIONS]),
    'margin': st.sampled_from([1e-9, 0.02, 10.0]),
    'slop': st.sampled_from([0.0, 1e-10]),
    'restitution_threshold': st.sampled_from([0.0, 0.5, 1e6]),
    'height': st.sampled_from([-1e6, 0.0, 1e6]),
})


@hypothesis_settings(max_examples=40, deadline=None)
@given(floor=EXTREME_FLOORS, mass=st.sampled_from([1e-80, 0.01, 2.0, 1e50]),
       size=st.sampled_from([1e-3, 0.4, 100.0]), seed=st.integers(0, 1000),
       speed=st.sampled_from([0.0, 10.0, 1e4]), substeps=st.sampled_from([1, 2]),
       dt=st.sampled_from([1e-4, 0.001, 0.05]))
def test_extreme_valid_settings_step_finite(floor, mass, size, seed, speed, substeps, dt):
    """Any valid floor, body and throw: every state stays finite and above the floor's reach."""
    box = (size, 0.5 * size, 0.25 * size)
    rng = np.random.default_rng(seed)
    orientation = tuple(Rotation.random(random_state=seed).as_quat())
    body = RigidBody.solid_box(mass, box)
    settings = Settings(body, substeps=substeps, floor=Floor(enabled=True, box_size=box,
                                                             **floor))
    lift = 0.6 * math.hypot(*box)
    start = BodyState((0.0, 0.0, floor['height'] + lift), orientation,
                      tuple(speed * rng.normal(size=3)), tuple(speed * rng.normal(size=3)))
    sim = MouseSimulation(settings, start)
    for _ in range(200):
        state = sim.step(dt)
        assert all(math.isfinite(c) for part in state for c in part), state
        assert all(math.isfinite(impulse) and impulse >= 0.0 for _, impulse in sim.contacts)


@pytest.mark.parametrize('field, value, name', [
    ('friction', -0.1, 'friction'),
    ('friction', math.nan, 'friction'),
    ('restitution', 1.5, 'restitution'),
    ('restitution', -0.1, 'restitution'),
    ('height', math.nan, 'floor_height'),
    ('height', math.inf, 'floor_height'),
    ('iterations', 0, 'contact_iterations'),
    ('margin', 0.0, 'contact_margin'),
    ('slop', 0.5, 'contact_slop'),
    ('restitution_threshold', -1.0, 'restitution_threshold'),
    ('box_size', (0.4, 0.0, 0.1), 'box_size'),
    ('enabled', 1, 'floor'),
])
def test_bad_floor_settings_are_refused_naming_the_parameter(field, value, name):
    """Each invalid value raises one ValueError line that starts with the parameter's name."""
    with pytest.raises(ValueError) as raised:
        Floor(**{'enabled': True, 'box_size': WORLD.box, field: value})
    message = str(raised.value)
    assert message.startswith(name + ' ') and '\n' not in message


def test_an_initial_state_below_the_floor_is_refused_and_reset_returns_above_it():
    """Start below the floor: refused naming initial_position; a reset goes back on top."""
    floor = dataclasses.replace(WORLD.floor)
    body = RigidBody.solid_box(WORLD.mass, WORLD.box)
    settings = Settings(body, floor=floor, substeps=WORLD.substeps)
    with pytest.raises(ValueError, match=r'^initial_position .* below floor_height'):
        MouseSimulation(settings, BodyState((0.0, 0.0, 0.0)))
    sim = MouseSimulation(settings, BodyState((0.0, 0.0, 0.3)))
    with pytest.raises(ValueError, match='below floor_height'):
        sim.initial_state = BodyState((0.0, 0.0, 0.01))
    with pytest.raises(ValueError, match='below floor_height'):
        sim.settings = Settings(body, floor=dataclasses.replace(floor, height=0.5))
    assert sim.settings.floor is floor and sim.initial_state.position == (0.0, 0.0, 0.3)
    for _ in range(1000):
        sim.step(WORLD.dt)
    sim.reset()
    assert sim.state.position == (0.0, 0.0, 0.3) and sim.contact_count == 0


@pytest.mark.parametrize('height', [0.0, -1.25, 3.0])
def test_a_corner_exactly_the_slop_below_the_floor_is_taken(height):
    """
    The lowest corner exactly ``contact_slop`` deep is taken, as the docs say ("more than").

    0.0495 - 0.05 is not -0.0005 in binary: the check allows the subtraction's rounding, and
    a corner a micrometre deeper is still refused.
    """
    floor = dataclasses.replace(WORLD.floor, height=height)
    slop = floor.slop
    exact = height + WORLD.half_height - slop
    floor.check_state((0.0, 0.0, exact), (0.0, 0.0, 0.0, 1.0))
    with pytest.raises(ValueError, match='below floor_height'):
        floor.check_state((0.0, 0.0, exact - 1e-6), (0.0, 0.0, 0.0, 1.0))
