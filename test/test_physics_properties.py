"""
Property-based and extreme-body tests of the physics core: finite, unit, unchanged on bad input.

The random cases are drawn by hypothesis with a fixed seed and no example database, so a CI run
replays exactly the examples of any other run.
"""

import dataclasses
import math

from hypothesis import given, HealthCheck, settings, strategies as st
import numpy as np
import pytest
from scipy.spatial.transform import Rotation

from mouse_constraint_ros.physics import (BodyState, MouseConstraint, MouseSimulation, RigidBody,
                                          Settings, STANDARD_GRAVITY)

NO_GRAVITY = (0.0, 0.0, 0.0)
NON_FINITE = st.sampled_from([math.nan, math.inf, -math.inf])
# The largest negative float: -0.0 compares equal to 0.0 and so is a valid 'at least 0'.
NEGATIVE = st.floats(max_value=-5e-324, allow_nan=False)
REPRODUCIBLE = settings(derandomize=True, database=None, deadline=None,
                        suppress_health_check=[HealthCheck.too_slow])


def log_uniform(low: float, high: float) -> st.SearchStrategy:
    """
    Return floats spread evenly over the decades from ``low`` to ``high``, both included.

    :param low: the smallest value (> 0).
    :param high: the largest value.
    """
    return st.floats(math.log10(low), math.log10(high)).map(
        lambda e: min(max(10.0 ** e, low), high))


def unit_vectors() -> st.SearchStrategy:
    """Return uniformly-ish spread unit 3-vectors (normalized cube samples away from 0)."""
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


def all_settings() -> st.SearchStrategy:
    """Return valid settings: any body and mode, gravity on or off, damping, 1..8 substeps."""
    return st.builds(Settings, body=bodies(), constraint=constraints(),
                     gravity=st.sampled_from([STANDARD_GRAVITY, NO_GRAVITY]),
                     linear_damping=st.floats(0.0, 10.0), angular_damping=st.floats(0.0, 10.0),
                     substeps=st.integers(1, 8))


def states() -> st.SearchStrategy:
    """Return valid initial states: anywhere within 10 m, any orientation, moderate speeds."""
    vector = st.tuples(*[st.floats(-10.0, 10.0)] * 3)
    return st.builds(BodyState, vector, unit_quaternions(), vector, vector)


# One command per step: keep the target, clear it, jump to a point up to 1 km away, or move
# the target (or the anchor's position when there is none) by up to 5 cm.
POINT = st.tuples(*[st.floats(-1e3, 1e3)] * 3)
COMMANDS = st.lists(st.one_of(
    st.just('keep'), st.none(), st.tuples(st.just('jump'), POINT),
    st.tuples(st.just('move'), st.tuples(*[st.floats(-0.05, 0.05)] * 3))), min_size=1,
    max_size=25)


def apply(sim: MouseSimulation, command) -> None:
    """Apply one target command (see COMMANDS) to ``sim``."""
    if command is None:
        sim.target = None
    elif command != 'keep':
        kind, point = command
        if kind == 'move':
            base = sim.anchor_position() if sim.target is None else sim.target
            point = tuple(b + d for b, d in zip(base, point))
        sim.target = point


def assert_sane(sim: MouseSimulation) -> None:
    """Every state value and the constraint force are finite; |q| = 1 within 1e-12."""
    state = sim.state
    values = [v for part in state for v in part] + list(sim.constraint_force)
    assert all(math.isfinite(v) for v in values), state
    assert math.isfinite(sim.kinetic_energy())
    assert abs(math.sqrt(sum(c * c for c in state.orientation)) - 1.0) <= 1e-12


@settings(REPRODUCIBLE, max_examples=400)
@given(all_settings(), states(), COMMANDS, st.floats(1e-4, 1.0 / 30.0))
def test_random_valid_inputs_keep_the_state_finite_and_the_quaternion_unit(
        config, initial, commands, dt):
    """Any valid body, mode, target script and step: finite state, unit quaternion."""
    sim = MouseSimulation(config, initial)
    for command in commands:
        apply(sim, command)
        sim.step(dt)
        assert_sane(sim)


@st.composite
def bad_masses(draw) -> float:
    """Return a mass that is not > 0 or not finite."""
    return draw(st.one_of(st.just(0.0), st.just(-0.0), NEGATIVE, NON_FINITE))


@st.composite
def bad_inertias(draw) -> tuple:
    """
    Return an inertia that is non-finite, not positive definite or not physically realizable.

    Non-SPD: a principal moment <= 0. Non-realizable: the largest moment exceeds the sum of the
    other two by at least 1e-6 of it (the core accepts 1e-9 of slack for rounding).
    """
    kind = draw(st.sampled_from(['non-finite', 'not SPD', 'not realizable']))
    a, b = draw(log_uniform(1e-3, 1e3)), draw(log_uniform(1e-3, 1e3))
    if kind == 'non-finite':
        inertia = list(rotated((a, b, a + b), draw(unit_quaternions())))
        inertia[draw(st.integers(0, 5))] = draw(NON_FINITE)
        return tuple(inertia)
    if kind == 'not SPD':
        moments = (a, b, -draw(st.one_of(st.just(0.0), log_uniform(1e-6, 1e3))))
    else:
        moments = (a, b, (a + b) * (1.0 + draw(log_uniform(1e-6, 1e3))))
    return rotated(draw(st.permutations(moments)), draw(unit_quaternions()))


def bad_changes() -> st.SearchStrategy:
    """
    Return (description, change) pairs: ``change(sim)`` must raise ValueError.

    Covers every setting and input of the brief: non-finite numbers, mass <= 0, non-SPD or
    non-realizable inertia, substeps < 1, baumgarte outside (0, 1], negative damping,
    frequency < 0, damping ratio < 0, max force <= 0, non-finite targets and dt <= 0.
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

    def target(sim, point):
        sim.target = point

    def step(sim, dt):
        sim.step(dt)

    bad_baumgarte = st.one_of(st.just(0.0), NEGATIVE, NON_FINITE,
                              st.floats(min_value=1.0, exclude_min=True))
    bad_vector = st.tuples(st.integers(0, 2), NON_FINITE, POINT).map(
        lambda t: tuple(t[1] if i == t[0] else c for i, c in enumerate(t[2])))
    cases = [
        ('mass', body, 'mass', bad_masses()),
        ('inertia', body, 'inertia', bad_inertias()),
        ('substeps', setting, 'substeps', st.integers(max_value=0)),
        ('linear_damping', setting, 'linear_damping', st.one_of(NEGATIVE, NON_FINITE)),
        ('angular_damping', setting, 'angular_damping', st.one_of(NEGATIVE, NON_FINITE)),
        ('gravity', setting, 'gravity', bad_vector),
        ('anchor', constraint, 'anchor', bad_vector),
        ('baumgarte', constraint, 'baumgarte', bad_baumgarte),
        ('frequency_hz', constraint, 'frequency_hz', st.one_of(NEGATIVE, NON_FINITE)),
        ('damping_ratio', constraint, 'damping_ratio', st.one_of(NEGATIVE, NON_FINITE)),
        ('max_force', constraint, 'max_force',
         st.one_of(st.just(0.0), st.just(-0.0), NEGATIVE, st.just(math.nan))),
    ]
    strategies = [value.map(lambda v, n=name, f=field, c=change: (
        f'{n}={v!r}', lambda sim: c(sim, **{f: v}))) for name, change, field, value in cases]
    strategies.append(bad_vector.map(lambda v: (f'target={v!r}', lambda sim: target(sim, v))))
    strategies.append(st.one_of(st.just(0.0), st.just(-0.0), NEGATIVE, NON_FINITE).map(
        lambda v: (f'dt={v!r}', lambda sim: step(sim, v))))
    return st.one_of(strategies)


def snapshot(sim: MouseSimulation) -> str:
    """Return everything observable about ``sim``, exactly (repr round-trips floats and -0.0)."""
    return repr((sim.state, sim.target, sim.settings, sim.constraint_force))


@settings(REPRODUCIBLE, max_examples=600)
@given(all_settings(), states(), COMMANDS, st.floats(1e-4, 1.0 / 30.0), bad_changes())
def test_invalid_inputs_raise_and_change_nothing(config, initial, commands, dt, bad):
    """
    A rejected setting or input raises ValueError and leaves state, target and settings alone.

    A twin that never saw the bad input is stepped alongside: both stay bit-identical.
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
    for command in commands[len(commands) // 2:]:
        for sim in (touched, twin):
            apply(sim, command)
            sim.step(dt)
        assert snapshot(touched) == snapshot(twin), description


# Extreme but valid bodies: the lightest and heaviest mass, a thin rod (principal moments
# 1e-3 : 1 : 1, times m in m^2) rotated off the axes, an anchor 10 m from the COM and a target
# 1 km from the anchor, stepped 2000 times at 1 ms with no gravity.
ORIENTATION = tuple(Rotation.from_rotvec([0.3, -0.7, 0.5]).as_quat())
ANCHOR = tuple(10.0 * np.array([1.0, 2.0, -0.5]) / np.linalg.norm([1.0, 2.0, -0.5]))
OFFSET = 1e3 * np.array([-0.3, 1.0, 0.4]) / np.linalg.norm([-0.3, 1.0, 0.4])
STEPS, H = 2000, 1e-3
MASSES = [1e-3, 1e4]
RIGID = [{'baumgarte': 0.2}, {'baumgarte': 1.0}]
# 0.1 Hz at zeta = 3 is still being pulled in after 2 s (slow root 0.1 /s): finiteness only.
SLOW = [{'frequency_hz': 0.1, 'damping_ratio': 3.0}]
DAMPED = [{'frequency_hz': 5.0, 'damping_ratio': 1.0},
          {'frequency_hz': 50.0, 'damping_ratio': 1.0},
          {'frequency_hz': 50.0, 'damping_ratio': 0.1}]
UNDAMPED = [{'frequency_hz': 50.0, 'damping_ratio': 0.0}]


def extreme(mass: float, mode: dict, max_force: float = math.inf) -> MouseSimulation:
    """
    Return the extreme simulation, at rest, its target 1 km from the anchor.

    :param mass: the body's mass (kg).
    :param mode: MouseConstraint keyword arguments choosing rigid or soft mode.
    :param max_force: the constraint force bound (N).
    """
    body = RigidBody(mass, rotated(mass * np.array([1e-3, 1.0, 1.0]), ORIENTATION))
    constraint = MouseConstraint(anchor=ANCHOR, max_force=max_force, **mode)
    sim = MouseSimulation(Settings(body, constraint, gravity=NO_GRAVITY))
    sim.target = tuple(np.add(sim.anchor_position(), OFFSET))
    return sim


def energies(sim: MouseSimulation) -> np.ndarray:
    """Step ``sim`` STEPS times at H, checking every state; return the kinetic energies."""
    result = []
    for _ in range(STEPS):
        sim.step(H)
        assert_sane(sim)
        result.append(sim.kinetic_energy())
    return np.array(result)


@pytest.mark.parametrize('mass', MASSES)
@pytest.mark.parametrize('mode', RIGID + SLOW + DAMPED + UNDAMPED)
@pytest.mark.parametrize('limited', [False, True])
def test_extreme_bodies_never_produce_a_non_finite_value(mass, mode, limited):
    """2000 steps at 1 ms of the extreme body, with and without max force: always finite."""
    energies(extreme(mass, mode, 2000.0 * mass if limited else math.inf))


@pytest.mark.parametrize('mass', MASSES)
@pytest.mark.parametrize('mode', RIGID)
def test_rigid_mode_energy_does_not_grow_once_the_target_is_still(mass, mode):
    """
    Rigid mode, still target, no gravity: the second second's largest KE <= the first's.

    Nothing but the constraint acts. Its impulse takes the anchor's velocity u, and its energy
    u.K^-1 u / 2, away and gives it -delta C / h instead, with energy delta^2 C.K^-1 C / 2h^2
    that shrinks with the error; the spin about the anchor it leaves alone, and the gyroscopic
    step keeps that energy. So once the first impulse has launched the body, the KE must not
    grow beyond rounding.
    """
    ke = energies(extreme(mass, mode))
    assert ke[STEPS // 2:].max() <= ke[:STEPS // 2].max() * (1.0 + 1e-9)


@pytest.mark.parametrize('mass', MASSES)
@pytest.mark.parametrize('mode', DAMPED)
def test_damped_soft_mode_energy_stays_below_the_spring_energy_and_decays(mass, mode):
    """
    Soft mode, zeta > 0, still target, no gravity: KE <= the spring's initial energy, decaying.

    The spring has stiffness k = m_eff omega^2 along the error, and m_eff = (u.K u)^-1 <= m since
    K = m^-1 I3 + (a positive semidefinite angular part). Starting at rest with error C0, the
    energy it can ever release is at most m omega^2 |C0|^2 / 2; with zeta > 0 it loses energy,
    so the KE never exceeds that and the second second's largest KE is below the first's.
    """
    sim = extreme(mass, mode)
    omega = 2.0 * math.pi * mode['frequency_hz']
    spring_energy = 0.5 * mass * omega ** 2 * float(np.dot(OFFSET, OFFSET))
    ke = energies(sim)
    assert ke.max() <= spring_energy
    assert ke[STEPS // 2:].max() <= ke[:STEPS // 2].max()


@pytest.mark.parametrize('mass', MASSES)
@pytest.mark.parametrize('mode', RIGID + DAMPED + UNDAMPED)
def test_max_force_bounds_the_kinetic_energy_by_the_impulse_it_can_give(mass, mode):
    """
    With |F| <= F_max the KE after time t is at most (F_max t)^2 (1/m + |r|^2 / I_min) / 2.

    Each substep changes the momentum by the impulse P, |P| <= F_max h, and the angular momentum
    about the COM by r x P; the gyroscopic step keeps |L| (or lowers it) and nothing else acts.
    From rest, |p| <= F_max t and |L| <= F_max |r| t, and KE = p^2 / 2m + L.I^-1 L / 2 is at most
    their bound. (This is the energy bound with max force: with a target 1 km away at
    2000 m/s^2 the body is still being dragged after 2 s, so the KE may legitimately grow.)
    """
    max_force = 2000.0 * mass
    sim = extreme(mass, mode, max_force)
    smallest_moment = 1e-3 * mass
    times = H * np.arange(1, STEPS + 1)
    bound = 0.5 * (max_force * times) ** 2 * (1.0 / mass
                                              + float(np.dot(ANCHOR, ANCHOR)) / smallest_moment)
    assert np.all(energies(sim) <= bound * (1.0 + 1e-9))
