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
Property tests of the physics core: random valid and invalid inputs, and extreme bodies.

Hypothesis draws the random cases with a fixed seed and no example database, so every run on any
machine replays the same examples. The extreme bodies are fixed: the lightest and the heaviest
mass, an inertia ratio of 1:1000, an anchor 10 m from the COM and a target 1 km away.

The energy bound used throughout is derived in ``energy_allowance``.
"""

import dataclasses
import functools
import math
from typing import NamedTuple

from hypothesis import given
from hypothesis import HealthCheck
from hypothesis import settings
from hypothesis import strategies as st
import numpy as np
import pytest
from scipy.spatial.transform import Rotation

from mouse_constraint_ros.physics import BodyState
from mouse_constraint_ros.physics import MouseConstraint
from mouse_constraint_ros.physics import MouseSimulation
from mouse_constraint_ros.physics import RigidBody
from mouse_constraint_ros.physics import Settings
from mouse_constraint_ros.physics import STANDARD_GRAVITY
from mouse_constraint_ros.physics.limits import MAX_ACCELERATION
from mouse_constraint_ros.physics.limits import MAX_CONDITION
from mouse_constraint_ros.physics.limits import MAX_DISTANCE
from mouse_constraint_ros.physics.limits import MAX_MASS
from mouse_constraint_ros.physics.limits import MAX_MOMENT
from mouse_constraint_ros.physics.limits import MAX_STEP
from mouse_constraint_ros.physics.limits import MIN_MASS
from mouse_constraint_ros.physics.limits import MIN_MOMENT
from mouse_constraint_ros.physics.limits import MIN_STEP
from mouse_constraint_ros.physics.mouse_joint import soft_gains

NO_GRAVITY = (0.0, 0.0, 0.0)
NON_FINITE = st.sampled_from([math.nan, math.inf, -math.inf])
# Down to the smallest negative float: -0.0 compares equal to 0.0, a valid 'at least 0'.
NEGATIVE = st.floats(max_value=-5e-324, allow_nan=False)
NOT_A_NUMBER = st.sampled_from(['heavy', None, [1.0], (), {}])
REPRODUCIBLE = settings(derandomize=True, database=None, deadline=None,
                        suppress_health_check=[HealthCheck.too_slow])
# Relative slack for rounding in energy comparisons. A substep rounds a few hundred operations
# (~1e-14 of the energies involved) and the implicit midpoint rotation stops iterating at 1e-13
# of the angular velocity; 1e-9 is far above both and far below any real energy gain.
ROUNDING = 1e-9


def log_uniform(low: float, high: float) -> st.SearchStrategy:
    """
    Return floats spread evenly over the decades from ``low`` to ``high``, both included.

    :param low: the smallest value (> 0).
    :param high: the largest value.
    """
    return st.floats(math.log10(low), math.log10(high)).map(
        lambda e: min(max(10.0 ** e, low), high))


def unit_vectors() -> st.SearchStrategy:
    """Return unit 3-vectors in every direction (normalized cube samples away from 0)."""
    return st.tuples(*[st.floats(-1.0, 1.0)] * 3).filter(
        lambda v: np.linalg.norm(v) > 0.1).map(lambda v: tuple(np.array(v) / np.linalg.norm(v)))


def unit_quaternions() -> st.SearchStrategy:
    """Return unit quaternions (x, y, z, w)."""
    return st.tuples(*[st.floats(-1.0, 1.0)] * 4).filter(
        lambda q: np.linalg.norm(q) > 0.1).map(lambda q: tuple(np.array(q) / np.linalg.norm(q)))


def rotated(moments, orientation) -> tuple:
    """Return R diag(moments) R^T in URDF order (xx, xy, xz, yy, yz, zz)."""
    axes = Rotation.from_quat(orientation).as_matrix()
    m = axes @ np.diag(moments) @ axes.T
    return (m[0, 0], m[0, 1], m[0, 2], m[1, 1], m[1, 2], m[2, 2])


@st.composite
def bodies(draw) -> RigidBody:
    """
    Return a valid body: mass 1e-3..1e4 kg and a realizable inertia, ratio up to 1:1000.

    The largest moment is m s^2 for a size s of 1 cm..10 m; the smallest is 1..1e-3 of it and
    the middle one lies between them and no lower than largest - smallest (triangle inequality),
    in a random order, rotated off the body axes by a random orientation.
    """
    mass = draw(log_uniform(1e-3, 1e4))
    largest = mass * draw(log_uniform(1e-2, 10.0)) ** 2
    smallest = largest * draw(log_uniform(1e-3, 1.0))
    middle = draw(st.floats(max(largest - smallest, smallest), largest))
    moments = draw(st.permutations([smallest, middle, largest]))
    return RigidBody(mass, rotated(moments, draw(unit_quaternions())))


def anchors() -> st.SearchStrategy:
    """Return anchors up to 10 m from the COM, the COM itself included."""
    return st.one_of(st.just((0.0, 0.0, 0.0)), st.builds(
        lambda d, r: tuple(r * np.array(d)), unit_vectors(), st.floats(0.0, 10.0)))


def constraints() -> st.SearchStrategy:
    """Return rigid (baumgarte in (0, 1]) or soft (0.1..50 Hz, zeta 0..3) modes, +- max force."""
    max_force = st.one_of(st.just(math.inf), log_uniform(1e-3, 1e7))
    rigid = st.builds(MouseConstraint, anchor=anchors(), max_force=max_force,
                      baumgarte=st.floats(0.0, 1.0, exclude_min=True))
    soft = st.builds(MouseConstraint, anchor=anchors(), max_force=max_force,
                     frequency_hz=st.floats(0.1, 50.0), damping_ratio=st.floats(0.0, 3.0))
    return st.one_of(rigid, soft)


def all_settings(gravity=st.sampled_from([STANDARD_GRAVITY, NO_GRAVITY]),
                 substeps=st.integers(1, 8)) -> st.SearchStrategy:
    """
    Return valid settings: any body and mode, damping 0..10 /s, gravity on or off.

    :param gravity: the gravity strategy.
    :param substeps: the substeps strategy.
    """
    return st.builds(Settings, body=bodies(), constraint=constraints(), gravity=gravity,
                     linear_damping=st.floats(0.0, 10.0), angular_damping=st.floats(0.0, 10.0),
                     substeps=substeps)


def states() -> st.SearchStrategy:
    """Return valid initial states: anywhere within 10 m, any orientation, moderate speeds."""
    vector = st.tuples(*[st.floats(-10.0, 10.0)] * 3)
    return st.builds(BodyState, vector, unit_quaternions(), vector, vector)


STEP_SIZES = log_uniform(1e-4, 1.0 / 30.0)
# One command per step: keep the target, clear it (None), reset, jump to a point up to 1 km
# away, or move the target (or, without one, the anchor's position) by up to 5 cm.
POINT = st.tuples(*[st.floats(-1e3, 1e3)] * 3)
COMMANDS = st.lists(st.one_of(
    st.just('keep'), st.none(), st.just('reset'), st.tuples(st.just('jump'), POINT),
    st.tuples(st.just('move'), st.tuples(*[st.floats(-0.05, 0.05)] * 3))), min_size=1,
    max_size=30)


def apply(sim: MouseSimulation, command) -> None:
    """Apply one target command (see COMMANDS) to ``sim``."""
    if command is None:
        sim.target = None
    elif command == 'reset':
        sim.reset()
    elif command != 'keep':
        kind, point = command
        if kind == 'move':
            base = sim.anchor_position() if sim.target is None else sim.target
            point = tuple(b + d for b, d in zip(base, point))
        sim.target = point


def problems(sim: MouseSimulation) -> str:
    """Return what is wrong with ``sim``'s state (a non-finite value, |q| != 1), or ''."""
    state = sim.state
    values = [v for part in state for v in part] + list(sim.constraint_force)
    if not all(math.isfinite(v) for v in values + [sim.kinetic_energy()]):
        return f'non-finite: {state!r}, force {sim.constraint_force!r}'
    norm = math.sqrt(sum(c * c for c in state.orientation))
    if abs(norm - 1.0) > 1e-12:
        return f'|q| = {norm!r}'
    return ''


def energy_allowance(sim: MouseSimulation, h: float) -> float:
    """
    Return the most kinetic energy the next substep of ``h`` s may add, with no gravity (J).

    Without gravity only the constraint can add energy: the implicit midpoint rotation keeps it
    (or scales it down where it cannot converge), the orientation update turns the body about w
    and so keeps w.I w, and damping takes energy away. The constraint applies the impulse
    P = c (-a K^-1 u + P_b), with u = J V the anchor's velocity, P_b = -s b K^-1 C the position
    correction, s <= 1 the turn limit's scale and c <= 1 max force's. The energy it adds is
    u.P + P.K P / 2 = (|u' + p|^2 - |u'|^2) / 2 with u' = K^-1/2 u and p = K^1/2 P, and
    |u' + p| <= (1 - c a) |u'| + c |K^1/2 P_b|, where |K^1/2 P_b|^2 = s^2 b^2 C.K^-1 C is at
    most m b^2 |C|^2 since K >= I3 / m. Maximized over |u'| (a concave quadratic for a > 0)
    and over c in (0, 1], the gain is at most

        m b^2 |C|^2 / (2 a (2 - a)).

    Rigid mode (a = 1, b = delta / h) gives m (delta |C| / h)^2 / 2, the energy of moving the
    whole body at the corrective speed. Soft mode with zeta > 0 gives about m omega^3 h |C|^2 /
    (8 zeta). Without damping (zeta = 0, a = 0) there is no bound: returns +inf.

    The first step from a given state (new, reset or set) is more than such a substep: it first
    moves the velocities back half a substep (the leapfrog start), running damping and soft
    mode's damper and spring backwards, which this bound does not cover. Those steps are left
    out: with stiff damped springs at coarse steps they do add energy beyond it.
    """
    error = sim.anchor_error()
    if error is None:
        return 0.0
    a, b = sim.settings.constraint.gains(h)
    if a == 0.0:
        return math.inf
    return 0.5 * sim.settings.body.mass * b * b * sum(c * c for c in error) / (a * (2.0 - a))


@settings(REPRODUCIBLE, max_examples=300)
@given(all_settings(), states(), COMMANDS, STEP_SIZES)
def test_random_valid_inputs_keep_the_state_finite_and_the_quaternion_unit(
        config, initial, commands, dt):
    """Any valid body, mode, damping, gravity, substeps and target script: finite, unit q."""
    sim = MouseSimulation(config, initial)
    for i, command in enumerate(commands):
        apply(sim, command)
        sim.step(dt)
        assert not problems(sim), f'step {i}: {problems(sim)}'


@settings(REPRODUCIBLE, max_examples=300)
@given(all_settings(gravity=st.just(NO_GRAVITY), substeps=st.just(1)), states(), COMMANDS,
       STEP_SIZES)
def test_random_valid_inputs_never_gain_more_energy_than_the_correction_allows(
        config, initial, commands, dt):
    """
    No gravity, one substep per step: each step's KE gain is within ``energy_allowance``.

    The bound holds for any target, still, moving or jumping: it only uses the anchor error at
    the start of the step. With no target the KE must not grow at all. Steps from a given state
    (the first, and the first after a reset) begin with the leapfrog start and are left out.
    """
    sim = MouseSimulation(config, initial)
    given_state = True
    for i, command in enumerate(commands):
        apply(sim, command)
        given_state = given_state or command == 'reset'
        before, allowance = sim.kinetic_energy(), energy_allowance(sim, dt)
        sim.step(dt)
        after = sim.kinetic_energy()
        assert given_state or after <= before + allowance + ROUNDING * (before + allowance), \
            f'step {i}: KE {before!r} -> {after!r}, allowance {allowance!r}'
        given_state = False


@settings(REPRODUCIBLE, max_examples=200)
@given(log_uniform(1e-3, 1e6), st.one_of(st.just(0.0), log_uniform(1e-6, 1e6)),
       log_uniform(MIN_STEP, MAX_STEP))
def test_soft_gains_stay_finite_and_stable_for_stiff_springs_and_long_steps(
        frequency, damping_ratio, h):
    """
    0 <= a <= 1 and 0 <= b h <= 4, finite, from 1 mHz to 1 MHz, zeta up to 1e6, any valid h.

    The gains make the anchor error's map have eigenvalues l1, l2 with |l| <= 1: a = 1 - l1 l2
    lies in [0, 1] and b h = (1 - l1)(1 - l2) in [0, 4]; b h may round below 0 by an ulp.
    """
    a, b = soft_gains(frequency, damping_ratio, h)
    assert 0.0 <= a <= 1.0
    assert math.isfinite(b)
    assert -4.0 * np.finfo(float).eps <= b * h <= 4.0


@settings(REPRODUCIBLE, max_examples=150)
@given(all_settings(), states(), COMMANDS, log_uniform(8.0 * MIN_STEP, MAX_STEP),
       log_uniform(0.1, 1e4))
def test_any_valid_step_size_and_stiff_springs_stay_finite(config, initial, commands, dt,
                                                           frequency):
    """
    Steps from 8 ns to 1 s, soft springs up to 10 kHz (far beyond resolution): still finite.

    The soft modes drawn get a frequency of 0.1 Hz..10 kHz; at 10 kHz, zeta = 3 and h = 1/30 s
    the gains once overflowed.
    """
    if not config.constraint.rigid:
        config = dataclasses.replace(config, constraint=dataclasses.replace(
            config.constraint, frequency_hz=frequency))
    sim = MouseSimulation(config, initial)
    for i, command in enumerate(commands):
        apply(sim, command)
        sim.step(dt)
        assert not problems(sim), f'step {i}: {problems(sim)}'


@st.composite
def bad_inertias(draw) -> tuple:
    """
    Return an inertia that is non-finite, not positive definite or not physically realizable.

    Non-SPD: a principal moment below 0 by at least 1e-6 of the largest, or exactly 0 on the
    diagonal (rotated, a zero moment may round to a tiny positive one: a valid thin rod).
    Non-realizable: the largest moment exceeds the sum of the other two by at least 1e-6 of it
    (the core accepts 1e-9 of slack for rounding). Too small or too large: realizable moments
    1e3 or more beyond MIN_MOMENT..MAX_MOMENT.
    """
    kind = draw(st.sampled_from(['non-finite', 'not SPD', 'zero', 'not realizable', 'size',
                                 'too small', 'too large']))
    a, b = draw(log_uniform(1e-3, 1e3)), draw(log_uniform(1e-3, 1e3))
    if kind in ('too small', 'too large'):
        # Realizable moments of a scale beyond the range where the gyroscopic step's
        # determinant is a normal float.
        scale = (draw(log_uniform(1e-300, MIN_MOMENT * 1e-3)) if kind == 'too small'
                 else draw(log_uniform(MAX_MOMENT * 1e3, 1e300)))
        return rotated((scale, 1.2 * scale, 1.5 * scale), draw(unit_quaternions()))
    if kind == 'size':
        return draw(st.lists(log_uniform(1e-3, 1e3), max_size=9).filter(lambda v: len(v) != 6))
    if kind == 'non-finite':
        inertia = list(rotated((a, b, a + b), draw(unit_quaternions())))
        inertia[draw(st.integers(0, 5))] = draw(NON_FINITE)
        return tuple(inertia)
    if kind == 'zero':
        moments = draw(st.permutations([a, b, draw(st.sampled_from([0.0, -0.0]))]))
        return (moments[0], 0.0, 0.0, moments[1], 0.0, moments[2])
    if kind == 'not SPD':
        moments = (a, b, -max(a, b) * draw(log_uniform(1e-6, 1e3)))
    else:
        moments = (a, b, (a + b) * (1.0 + draw(log_uniform(1e-6, 1e3))))
    return rotated(draw(st.permutations(moments)), draw(unit_quaternions()))


def bad_vectors(size: int = 3, none: bool = True) -> st.SearchStrategy:
    """
    Return vectors that are not ``size`` finite numbers.

    :param size: the valid length.
    :param none: include None (a valid target: no target).
    """
    numbers = st.lists(st.floats(-1e3, 1e3), min_size=size, max_size=size)
    non_finite = st.tuples(st.integers(0, size - 1), NON_FINITE, numbers).map(
        lambda t: tuple(t[1] if i == t[0] else c for i, c in enumerate(t[2])))
    not_numbers = st.tuples(st.integers(0, size - 1), NOT_A_NUMBER, numbers).map(
        lambda t: tuple(t[1] if i == t[0] else c for i, c in enumerate(t[2])))
    wrong_size = st.lists(st.floats(-1e3, 1e3), max_size=size + 2).filter(
        lambda v: len(v) != size)
    others = [None, 1.0, 'xyz'] if none else [1.0, 'xyz']
    return st.one_of(non_finite, not_numbers, wrong_size, st.sampled_from(others))


@st.composite
def bad_states(draw) -> BodyState:
    """Return a state with a non-finite value, a wrong-sized vector or a non-unit orientation."""
    fields = dict(zip(BodyState._fields, draw(states())))
    field = draw(st.sampled_from(BodyState._fields))
    if field == 'orientation':
        scale = draw(st.one_of(st.just(0.0), st.floats(0.0, 1.0 - 1e-5),
                               st.floats(1.0 + 1e-5, 1e3)))
        fields[field] = draw(st.one_of(
            bad_vectors(4), st.just(tuple(scale * c for c in fields[field]))))
    else:
        fields[field] = draw(bad_vectors())
    return BodyState(**fields)


def bad_changes() -> st.SearchStrategy:
    """
    Return (description, change) pairs: ``change(sim)`` must raise ValueError.

    Every setting and input: non-finite, non-numeric or wrong-sized values; mass <= 0 or out of
    MIN_MASS..MAX_MASS; a non-SPD or non-realizable inertia, or one of moments out of their
    range; gravity stronger than MAX_ACCELERATION; an anchor or a position farther than
    MAX_DISTANCE, or an anchor so far that K is too ill-conditioned;
    substeps < 1 or not an int; baumgarte outside (0, 1]; negative
    damping, frequency or damping ratio; max force <= 0; settings of the wrong type; invalid
    states; dt <= 0, dt > MAX_STEP and dt / substeps < MIN_STEP.
    """
    def body(sim, **fields):
        old = sim.settings.body
        fields = {'mass': old.mass, 'inertia': old.inertia, **fields}
        sim.settings = dataclasses.replace(sim.settings, body=RigidBody(**fields))

    def constraint(sim, **fields):
        sim.settings = dataclasses.replace(
            sim.settings, constraint=dataclasses.replace(sim.settings.constraint, **fields))

    def setting(sim, **fields):
        sim.settings = dataclasses.replace(sim.settings, **fields)

    def assign(sim, **fields):
        for name, value in fields.items():
            setattr(sim, name, value)

    def set_state(sim, state):
        sim.set_state(state)

    def step(sim, dt):
        sim.step(dt)

    def ill_conditioned(sim, direction):
        # Just beyond the farthest anchor at which K's condition bound 1 + m r^2 / I_min is
        # MAX_CONDITION.
        body = sim.settings.body
        reach = math.sqrt((MAX_CONDITION - 1.0) * body.principal_moments[0] / body.mass)
        constraint(sim, anchor=tuple(1.01 * reach * np.array(direction)))

    def short_step(sim, fraction):
        sim.step(fraction * MIN_STEP * sim.settings.substeps)

    positive_or_not = st.one_of(st.just(0.0), st.just(-0.0), NEGATIVE, NON_FINITE, NOT_A_NUMBER)
    not_non_negative = st.one_of(NEGATIVE, NON_FINITE, NOT_A_NUMBER)
    far = st.builds(lambda d, r: tuple(r * np.array(d)), unit_vectors(),
                    log_uniform(1.01 * MAX_DISTANCE, 1e300))
    cases = [
        ('mass', body, 'mass', positive_or_not),
        ('mass out of range', body, 'mass', st.one_of(
            log_uniform(5e-324, MIN_MASS * 0.99), log_uniform(MAX_MASS * 1.01, 1e308))),
        ('gravity too strong', setting, 'gravity', st.builds(
            lambda d, g: tuple(g * np.array(d)), unit_vectors(),
            log_uniform(1.01 * MAX_ACCELERATION, 1e308))),
        ('anchor too far', constraint, 'anchor', far),
        ('anchor beyond the condition limit', ill_conditioned, 'direction', unit_vectors()),
        ('initial position too far', assign, 'initial_state', far.map(
            lambda p: BodyState(position=p))),
        ('inertia', body, 'inertia', bad_inertias()),
        ('substeps', setting, 'substeps', st.one_of(
            st.integers(max_value=0), st.sampled_from([2.0, True, '2', None]))),
        ('linear_damping', setting, 'linear_damping', not_non_negative),
        ('angular_damping', setting, 'angular_damping', not_non_negative),
        ('gravity', setting, 'gravity', bad_vectors()),
        ('body', setting, 'body', st.sampled_from([None, 1.0, MouseConstraint()])),
        ('constraint', setting, 'constraint', st.sampled_from([None, 1.0, {}])),
        ('anchor', constraint, 'anchor', bad_vectors()),
        ('baumgarte', constraint, 'baumgarte', st.one_of(
            positive_or_not, st.floats(min_value=1.0, exclude_min=True))),
        ('frequency_hz', constraint, 'frequency_hz', not_non_negative),
        ('damping_ratio', constraint, 'damping_ratio', not_non_negative),
        ('max_force', constraint, 'max_force', st.one_of(
            st.just(0.0), st.just(-0.0), NEGATIVE, st.just(math.nan), NOT_A_NUMBER)),
        ('settings', assign, 'settings', st.sampled_from([None, {}, 'settings'])),
        ('target', assign, 'target', bad_vectors(none=False)),
        ('initial_state', assign, 'initial_state', bad_states()),
        ('state', set_state, 'state', bad_states()),
        ('dt', step, 'dt', st.one_of(
            positive_or_not, st.floats(min_value=MAX_STEP, exclude_min=True),
            st.sampled_from([5e-324, 1e-320, 1e-12, MIN_STEP * (1.0 - np.finfo(float).eps),
                             MAX_STEP * (1.0 + 2.0 * np.finfo(float).eps), 1e300]))),
        ('dt / substeps', short_step, 'fraction', st.floats(0.0, 0.999, exclude_min=True)),
    ]
    strategies = [value.map(lambda v, n=name, f=field, c=change: (
        f'{n}: {v!r}', lambda sim: c(sim, **{f: v}))) for name, change, field, value in cases]
    return st.one_of(strategies)


def snapshot(sim: MouseSimulation) -> str:
    """Return everything observable about ``sim``, exactly (repr round-trips floats and -0.0)."""
    return repr((sim.state, sim.initial_state, sim.target, sim.settings, sim.constraint_force,
                 sim.anchor_error(), sim.kinetic_energy()))


@settings(REPRODUCIBLE, max_examples=500)
@given(all_settings(), states(), COMMANDS, STEP_SIZES, bad_changes())
def test_invalid_inputs_raise_and_the_simulation_continues_like_an_untouched_twin(
        config, initial, commands, dt, bad):
    """
    A rejected setting or input raises ValueError and changes nothing.

    A twin that never saw the bad input is stepped alongside, with the same target commands
    (resets included, so the initial state is compared in use too): both stay bit-identical.
    """
    description, change = bad
    touched, twin = MouseSimulation(config, initial), MouseSimulation(config, initial)
    for sim in (touched, twin):
        for command in commands[:len(commands) // 2]:
            apply(sim, command)
            sim.step(dt)
    with pytest.raises(ValueError):
        change(touched)
    assert snapshot(touched) == snapshot(twin), description
    for command in commands[len(commands) // 2:] + ['reset', 'keep']:
        for sim in (touched, twin):
            apply(sim, command)
            sim.step(dt)
        assert snapshot(touched) == snapshot(twin), description


# The extreme bodies, stepped 2000 times at 1 ms (one substep each, so that each step's anchor
# error is observable) from rest with no gravity: a thin rod (principal
# moments 1e-3 : 1 : 1) rotated off the axes, of the lightest and the heaviest mass, 3.5 m long
# ('rod', moments m (1e-3, 1, 1) m^2) or 3.5 cm long ('small rod', m r^2 / I_min = 1e9 for the
# 10 m anchor: the most ill-conditioned K), with a target 1 km from the anchor.
ORIENTATION = tuple(Rotation.from_rotvec([0.3, -0.7, 0.5]).as_quat())
ANCHOR = tuple(10.0 * np.array([1.0, 2.0, -0.5]) / np.linalg.norm([1.0, 2.0, -0.5]))
OFFSET = 1e3 * np.array([-0.3, 1.0, 0.4]) / np.linalg.norm([-0.3, 1.0, 0.4])
STEPS, H = 2000, 1e-3
MASSES = [1e-3, 1e4]
SHAPES = {'rod': 1.0, 'small rod': 1e-4}
MODES = {
    'rigid 0.2': {'baumgarte': 0.2},
    'rigid 1.0': {'baumgarte': 1.0},
    'soft 0.1 Hz zeta 3': {'frequency_hz': 0.1, 'damping_ratio': 3.0},
    'soft 5 Hz zeta 1': {'frequency_hz': 5.0, 'damping_ratio': 1.0},
    'soft 50 Hz zeta 1': {'frequency_hz': 50.0, 'damping_ratio': 1.0},
    'soft 50 Hz zeta 0.1': {'frequency_hz': 50.0, 'damping_ratio': 0.1},
    'soft 50 Hz zeta 3': {'frequency_hz': 50.0, 'damping_ratio': 3.0},
    'soft 50 Hz zeta 0': {'frequency_hz': 50.0, 'damping_ratio': 0.0},
}
# Modes whose pull peaks at the launch: the error decays by 1 - delta per step, or at the slow
# root's rate, zeta omega below critical damping and omega (zeta - sqrt(zeta^2 - 1)) above, at
# least 31 /s for these (the turn limit slows the pull-in of the 1 km error, without adding to
# the launch). 0.1 Hz at zeta 3 decays at 0.11 /s and is still accelerating the body after 2 s.
SETTLING = ['rigid 0.2', 'rigid 1.0', 'soft 5 Hz zeta 1', 'soft 50 Hz zeta 1',
            'soft 50 Hz zeta 0.1', 'soft 50 Hz zeta 3']
# Every mode but the undamped spring has a > 0 and so a finite ``energy_allowance``. The
# undamped spring has no energy bound: its stiffness omega^2 K^-1 turns with the body, so it is
# no potential force, and on these bodies it pumps energy in (the 1 km error grows). It is
# checked for finiteness, and with max force against the impulse bound.
BOUNDED = [name for name in MODES if name != 'soft 50 Hz zeta 0']
# The force limit: at most 2000 m/s^2 on the COM.
LIMIT = 2000.0


class Run(NamedTuple):
    """One extreme run: KE, |p| and |L| at the start and after every step; the allowances."""

    energies: np.ndarray
    momenta: np.ndarray
    angular_momenta: np.ndarray
    allowances: np.ndarray
    failure: str


def extreme(mass: float, shape: str, mode: str, limited: bool) -> MouseSimulation:
    """
    Return the extreme simulation, at rest, its target 1 km from the anchor.

    :param mass: the body's mass (kg).
    :param shape: a key of SHAPES.
    :param mode: a key of MODES.
    :param limited: whether max force is LIMIT * mass (else unlimited).
    """
    moments = mass * SHAPES[shape] * np.array([1e-3, 1.0, 1.0])
    body = RigidBody(mass, rotated(moments, ORIENTATION))
    constraint = MouseConstraint(anchor=ANCHOR, max_force=LIMIT * mass if limited else math.inf,
                                 **MODES[mode])
    sim = MouseSimulation(Settings(body, constraint, gravity=NO_GRAVITY, substeps=1))
    sim.target = tuple(np.add(sim.anchor_position(), OFFSET))
    return sim


@functools.lru_cache(maxsize=None)
def extreme_run(mass: float, shape: str, mode: str, limited: bool) -> Run:
    """Step the extreme simulation STEPS times at H; stop at the first state with a problem."""
    sim = extreme(mass, shape, mode, limited)
    energies, momenta, angular_momenta, allowances = [], [], [], []
    failure = ''
    for i in range(STEPS + 1):
        energies.append(sim.kinetic_energy())
        momenta.append(mass * math.sqrt(sum(v * v for v in sim.state.linear_velocity)))
        angular_momenta.append(math.sqrt(sum(c * c for c in sim.angular_momentum())))
        if i == STEPS:
            break
        allowances.append(energy_allowance(sim, H))
        sim.step(H)
        failure = problems(sim)
        if failure:
            failure = f'step {i}: {failure}'
            break
    return Run(*(np.array(v) for v in (energies, momenta, angular_momenta, allowances)), failure)


EXTREMES = pytest.mark.parametrize('mass', MASSES)
SHAPED = pytest.mark.parametrize('shape', list(SHAPES))


@EXTREMES
@SHAPED
@pytest.mark.parametrize('mode', list(MODES))
@pytest.mark.parametrize('limited', [False, True], ids=['unlimited', 'max force'])
def test_extreme_bodies_never_produce_a_non_finite_value(mass, shape, mode, limited):
    """2000 steps at 1 ms of every extreme body and mode: finite, |q| = 1, no exception."""
    assert not extreme_run(mass, shape, mode, limited).failure


@EXTREMES
@SHAPED
@pytest.mark.parametrize('mode', BOUNDED)
@pytest.mark.parametrize('limited', [False, True], ids=['unlimited', 'max force'])
def test_extreme_bodies_gain_no_more_energy_per_step_than_the_correction_allows(
        mass, shape, mode, limited):
    """
    Each step's KE gain is within ``energy_allowance`` of the anchor error it starts from.

    This is the energy balance of the step (see ``energy_allowance``): the velocity projection
    and the rotation only keep or remove energy, and the position correction, limited in turn
    and by max force, adds at most m b^2 |C|^2 / (2 a (2 - a)). Every step but the first, which
    begins with the leapfrog start (see ``energy_allowance``).
    """
    run = extreme_run(mass, shape, mode, limited)
    assert not run.failure
    before, gain = run.energies[1:-1], np.diff(run.energies)[1:]
    allowances = run.allowances[1:]
    excess = gain - allowances - ROUNDING * (before + allowances)
    worst = int(np.argmax(excess))
    assert excess[worst] <= 0.0, \
        f'step {worst + 1}: gain {gain[worst]!r} > allowance {allowances[worst]!r}'


@EXTREMES
@SHAPED
@pytest.mark.parametrize('mode', SETTLING)
def test_extreme_bodies_do_not_gain_energy_once_a_still_target_is_reached(mass, shape, mode):
    """
    Still target, no max force: the second second's largest KE is below the first second's.

    Once the anchor is on the still target the body is a free body pinned at a point, with no
    gravity: its exact KE is constant (rigid) or decays (a damped spring absorbs the spin's
    centripetal error). The only energy the step adds is the correction's, at most
    m b^2 |C|^2 / (2 a (2 - a)), largest at the launch (|C| = 1 km) and shrinking with |C|^2 as
    the error closes. So the KE must never again reach the launch's peak; energy pumped in by a
    missed linearized step (the failure the turn limit fixed) would make it grow past it.
    """
    run = extreme_run(mass, shape, mode, False)
    assert not run.failure
    first, second = run.energies[1:STEPS // 2 + 1], run.energies[STEPS // 2 + 1:]
    assert second.max() <= first.max(), (first.max(), second.max())


@EXTREMES
@SHAPED
@pytest.mark.parametrize('mode', list(MODES))
def test_max_force_bounds_momentum_and_kinetic_energy_by_the_impulse_it_can_give(
        mass, shape, mode):
    """
    With |F| <= F_max: |p|, |L| / |r| <= F_max t', KE <= (F_max t')^2 (1/m + r^2/I_min) / 2.

    Each substep changes the momentum by the impulse P, |P| <= F_max h, and the angular
    momentum about the COM by r x P; the rotation keeps |L| (the implicit midpoint rule keeps
    |I w|, turning the body keeps |L|) and nothing else acts. The leapfrog start adds one
    backward half substep, |P| <= F_max h / 2. So from rest, after t > 0, |p| <= F_max t' and
    |L| <= F_max |r| t' with t' = t + h / 2, and KE = p^2 / 2m + L.I^-1 L / 2 is at most the
    bound. It holds for every mode, undamped included. (The target is 1 km away and
    F_max / m = 2000 m/s^2: the body is still being dragged after 2 s, its KE rising.)
    """
    run = extreme_run(mass, shape, mode, True)
    assert not run.failure
    impulse = LIMIT * mass * H * np.concatenate([[0.0], np.arange(1, STEPS + 1) + 0.5])
    lever = float(np.linalg.norm(ANCHOR))
    smallest_moment = 1e-3 * mass * SHAPES[shape]
    assert np.all(run.momenta <= impulse * (1.0 + ROUNDING))
    assert np.all(run.angular_momenta <= lever * impulse * (1.0 + ROUNDING))
    bound = 0.5 * impulse ** 2 * (1.0 / mass + lever ** 2 / smallest_moment)
    assert np.all(run.energies <= bound * (1.0 + ROUNDING))
