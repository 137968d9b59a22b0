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

"""The whole robot's step (physics.robot_simulation): energy, accuracy, damping, limits, drag."""

import math

import numpy as np
import pinocchio
import pytest

from mouse_constraint_ros.description.robot_description import load_robot
from mouse_constraint_ros.physics.mouse_joint import MouseConstraint
from mouse_constraint_ros.physics.robot_rows import MAX_JOINT_TRAVEL, travel_bound
from mouse_constraint_ros.physics.robot_simulation import RobotSimulation
from mouse_constraint_ros.physics.robot_state import initial_state, RobotSettings
from test_support.robots import (collection_urdf, double_pendulum, double_pendulum_tip, G)

START = math.radians(60.0)
DT = 1e-3


def pendulum(text: str = double_pendulum(), settings: RobotSettings = RobotSettings(),
             positions=(START, 0.0)) -> RobotSimulation:
    """Return the double pendulum released from ``positions``."""
    robot = load_robot(text)
    model = robot.model
    return RobotSimulation(model, settings,
                           initial_state(model, joint_positions=positions))


def swing_energy(simulation: RobotSimulation) -> float:
    """Return the energy above the hanging rest: the swing's (J)."""
    model = simulation.model
    data = model.model.createData()
    rest = pinocchio.computePotentialEnergy(model.model, data, pinocchio.neutral(model.model))
    return simulation.energy() - rest


def test_a_double_pendulum_keeps_its_energy_within_a_thousandth_of_its_swing():
    simulation = pendulum()
    swing = swing_energy(simulation)
    start = simulation.energy()
    means = []
    for _second in range(10):
        total = 0.0
        for _tick in range(1000):
            simulation.step(DT)
            total += simulation.energy()
        means.append(total / 1000.0)
    drift = np.abs(np.array(means) - start) / swing
    assert drift.max() < 1e-3, drift


def test_one_pass_from_the_last_change_lands_on_the_implicit_momentum_step():
    # The free motion's v* solves M v* = p + h (C(q, v*)^T v* - g). One fixed-point pass from
    # M^-1 p plus the last substep's change lands within 1e-5 rad/s of the converged v*, over a
    # swing at up to 9 rad/s; one pass from M^-1 p alone misses it by some 4e-4 rad/s.
    simulation = pendulum()
    model = simulation.model.model
    data = model.createData()
    free_velocity = simulation._free_velocity
    misses = []

    def checked(h: float) -> np.ndarray:
        q, p = simulation._q, simulation._p
        v = free_velocity(h)
        gravity = pinocchio.computeGeneralizedGravity(model, data, q)
        mass = np.triu(pinocchio.crba(model, data, q))
        mass = mass + np.triu(mass, 1).T
        converged = np.linalg.solve(mass, p)
        for _pass in range(50):
            coriolis = pinocchio.computeCoriolisMatrix(model, data, q, converged)
            converged = np.linalg.solve(mass, p + h * (coriolis.T @ converged - gravity))
        misses.append(float(np.abs(v - converged).max()))
        return v

    simulation._free_velocity = checked
    for _tick in range(3000):
        simulation.step(DT)
    assert max(misses) < 1e-5, max(misses)
    assert max(misses[3:]) > 0.0  # the check compares two computations, not one with itself


def test_plain_semi_implicit_euler_would_gain_energy_on_the_same_chain():
    # The contrast that makes the momentum form necessary: v' = v + h M^-1 (tau - C v - g).
    simulation = pendulum()
    model, data = simulation.model.model, simulation.model.model.createData()
    q, v = simulation.state
    swing = swing_energy(simulation)
    energy = pinocchio.computeKineticEnergy(model, data, q, v) \
        + pinocchio.computePotentialEnergy(model, data, q)
    means = []
    for _second in range(10):
        total = 0.0
        for _tick in range(1000):
            v = v + DT * pinocchio.aba(model, data, q, v, np.zeros(model.nv))
            q = pinocchio.integrate(model, q, DT * v)
            total += pinocchio.computeKineticEnergy(model, data, q, v) \
                + pinocchio.computePotentialEnergy(model, data, q)
        means.append(total / 1000.0)
    assert (means[-1] - energy) / swing > 1e-2


def test_the_tip_follows_the_closed_equations_within_a_millimetre_rms():
    simulation = pendulum()
    times = np.arange(1, 2001) * DT
    tips = []
    for _tick in times:
        simulation.step(DT)
        tips.append(simulation.link_state('tip').position)
    tips = np.array(tips)[:, (0, 2)]
    reference = double_pendulum_tip(times, START, gravity=G)
    errors = np.linalg.norm(tips - reference, axis=1)
    assert math.sqrt(np.mean(errors ** 2)) < 1e-3
    # The swing is a real one: the tip travels far more than the error.
    assert np.ptp(reference[:, 0]) > 0.5


def test_a_damped_arm_settles_where_gravitys_torques_vanish():
    # A bent arm whose lower link carries its mass off the axis: it settles hanging, its COM
    # under the shoulder, where g(q) = 0 (not at q = 0).
    text = double_pendulum(kind='revolute', damping=2.0,
                           limit='<limit lower="-3" upper="3" effort="10" velocity="10"/>')
    text = text.replace('<origin xyz="0 0 -0.25"/><mass value="1.0"/>',
                        '<origin xyz="0.1 0 -0.25"/><mass value="1.0"/>', 2)
    simulation = pendulum(text, positions=(1.0, -0.5))
    for _tick in range(20000):
        simulation.step(DT)
    model = simulation.model.model
    q, v = simulation.state
    gravity = pinocchio.computeGeneralizedGravity(model, model.createData(), q)
    assert np.abs(gravity).max() < 1e-6 * simulation.model.mass * G
    assert np.abs(v).max() < 1e-6
    assert abs(simulation.joint_positions()[0]) > 0.05  # the offset mass turns it off zero


def test_a_limit_stops_a_falling_link_within_the_slop():
    text = double_pendulum(kind='revolute',
                           limit='<limit lower="-0.3" upper="0.3" effort="10" velocity="50"/>')
    settings = RobotSettings()
    simulation = pendulum(text, settings, positions=(0.29, 0.0))
    worst = 0.0
    for _tick in range(3000):
        simulation.step(DT)
        for position in simulation.joint_positions():
            worst = max(worst, abs(position) - 0.3)
    assert worst <= settings.limit_slop
    assert min(simulation.joint_positions()) > -0.3 - settings.limit_slop


def test_the_mouse_on_the_middle_link_holds_it_and_its_force_is_the_constraints():
    simulation = pendulum(positions=(0.0, 0.0))
    simulation.grab('lower', (0.0, 0.0, -0.25))
    target = np.array((0.2, 0.0, -0.6))
    simulation.target = target
    for _tick in range(3000):
        simulation.step(DT)
    assert np.linalg.norm(simulation.anchor_position() - target) < 1e-6
    # At rest the joint carries what gravity does not hand to the base: the impulse's torques
    # J^T P / h balance g(q) at each joint.
    model = simulation.model.model
    q, _ = simulation.state
    gravity = pinocchio.computeGeneralizedGravity(model, model.createData(), q)
    assert np.allclose(simulation.joint_efforts(), gravity, atol=1e-6)


def test_the_soft_mouse_rings_at_its_frequency_on_the_effective_mass():
    # A soft spring of f on the robot's effective mass: the anchor's error decays by the
    # damping ratio, whatever K is (zeta = 1: no overshoot).
    settings = RobotSettings(constraint=MouseConstraint(frequency_hz=5.0, damping_ratio=1.0),
                             gravity=(0.0, 0.0, 0.0))
    simulation = pendulum(settings=settings, positions=(0.3, 0.4))
    simulation.grab('tip', (0.0, 0.0, 0.0))
    start = simulation.anchor_position()
    target = start + np.array((0.05, 0.0, 0.0))
    simulation.target = target
    along = []
    for _tick in range(1000):
        simulation.step(DT)
        along.append(float((simulation.anchor_position() - start)[0]))
    assert max(along) < 0.05 + 1e-4  # critically damped: no overshoot past the target
    assert abs(along[-1] - 0.05) < 5e-4


@pytest.fixture(scope='module')
def panda():
    """Return the Panda of the public collection, as shipped (its fingers a mimic pair)."""
    return load_robot(collection_urdf('panda_description/urdf/panda.urdf').read_text())


@pytest.mark.parametrize('offset', [(0.3, 0.0, 0.0), (0.0, 0.3, 0.0), (0.0, 0.0, 0.3)])
def test_a_real_arm_hangs_and_its_tool_is_dragged_0_3_m_within_a_millimetre(panda, offset):
    model = panda.model
    settings = RobotSettings()
    simulation = RobotSimulation(model, settings, initial_state(model))
    assert panda.structure.tool == 'panda_hand_tcp'
    for _tick in range(1000):  # it hangs from its base, at its stops
        simulation.step(DT)
    start = np.array(simulation.link_state('panda_hand_tcp').position)
    simulation.grab('panda_hand_tcp', (0.0, 0.0, 0.0))
    simulation.target = start + offset
    worst = 0.0
    for _tick in range(2000):
        simulation.step(DT)
        for joint, position in zip(model.joints, simulation.joint_positions()):
            worst = max(worst, joint.lower - position, position - joint.upper)
    assert np.linalg.norm(simulation.anchor_position() - (start + offset)) < 1e-3
    assert worst <= settings.limit_slop
    fingers = simulation.joint_positions()[-2:]
    assert abs(fingers[0] - fingers[1]) < 1e-6  # the mimic joint follows its leader


def test_the_force_out_is_the_operational_space_inertia_times_the_asked_change():
    # A UR5 at rest, weightless, its tool pulled in rigid mode: the first tick's impulse is
    # -(J M^-1 J^T)^-1 (delta / h) C, the tool's operational-space inertia, computed here
    # independently from Pinocchio's frame Jacobian and CRBA.
    robot = load_robot(collection_urdf('ur_description/urdf/ur5_robot.urdf').read_text())
    model = robot.model
    settings = RobotSettings(gravity=(0.0, 0.0, 0.0))
    simulation = RobotSimulation(model, settings,
                                 initial_state(model, joint_positions=[0.3, -1.0, 1.2, -0.5,
                                                                       0.4, 0.1]))
    tool = robot.structure.tool
    start = np.array(simulation.link_state(tool).position)
    simulation.grab(tool, (0.0, 0.0, 0.0))
    simulation.target = start + (0.01, -0.02, 0.005)
    q, _ = simulation.state
    data = model.model.createData()
    jacobian = pinocchio.computeFrameJacobian(
        model.model, data, q, model.link_frames[tool],
        pinocchio.ReferenceFrame.LOCAL_WORLD_ALIGNED)[:3]
    mass = pinocchio.crba(model.model, data, q)
    mass = np.triu(mass) + np.triu(mass, 1).T
    inertia = np.linalg.inv(jacobian @ np.linalg.solve(mass, jacobian.T))
    simulation.step(DT)
    impulse, dt = simulation.tick_impulse
    expected = -inertia @ ((settings.constraint.baumgarte / DT) * (start - simulation.target))
    assert dt == DT
    assert np.allclose(impulse, expected, rtol=1e-9, atol=1e-12)
    assert np.allclose(simulation.constraint_force, expected / DT, rtol=1e-9)


def test_a_floating_robot_falls_as_a_whole_its_momentum_changing_by_its_weight():
    massive_base = double_pendulum().replace('<link name="base"/>', '<link name="base">' + (
        '<inertial><mass value="0.5"/><inertia ixx="0.01" iyy="0.01" izz="0.01" ixy="0" '
        'ixz="0" iyz="0"/></inertial></link>'))
    robot = load_robot(massive_base, base='floating')
    model = robot.model
    assert model.floating and model.nv == 8
    simulation = RobotSimulation(model, RobotSettings(), initial_state(
        model, joint_positions=(0.7, -0.4)))
    for _tick in range(500):
        simulation.step(DT)
    q, v = simulation.state
    data = model.model.createData()
    pinocchio.centerOfMass(model.model, data, q, v)
    # Linear momentum gains m g h a step, from the half step the start is staggered back by:
    # v_com = -g (N h - h / 2); in a uniform field nothing bends the falling robot.
    assert np.allclose(data.vcom[0], (0.0, 0.0, -9.80665 * (500 * DT - DT / 2)), atol=1e-9)
    with pytest.raises(ValueError, match="root link 'base' and the links fixed to it have no"):
        load_robot(double_pendulum(), base='floating')
    assert np.allclose(simulation.joint_positions(), (0.7, -0.4), atol=1e-9)


def single_rod(dynamics: str = '', limit: str = '') -> str:
    """Return one rod on a revolute joint about y, its own <dynamics> and <limit>."""
    from test_support.robots import rod_link
    limit = limit or '<limit lower="-3" upper="3" effort="100" velocity="100"/>'
    return ('<robot name="rod"><link name="base"/>' + rod_link('rod', 1.0, 0.5)
            + '<joint name="hinge" type="revolute"><parent link="base"/><child link="rod"/>'
            f'<axis xyz="0 1 0"/>{limit}{dynamics}</joint></robot>')


def test_joint_friction_holds_a_rod_whose_gravity_torque_it_exceeds_and_not_beyond():
    # Gravity's torque at 0.3 rad: m g (l / 2) sin 0.3 = 0.725 N m.
    torque = 1.0 * 9.80665 * 0.25 * math.sin(0.3)
    for friction, held in ((1.05 * torque, True), (0.95 * torque, False)):
        robot = load_robot(single_rod(f'<dynamics friction="{friction}"/>'))
        simulation = RobotSimulation(robot.model, RobotSettings(),
                                     initial_state(robot.model, joint_positions=[0.3]))
        for _tick in range(500):
            simulation.step(DT)
        moved = abs(simulation.joint_positions()[0] - 0.3)
        assert (moved < 1e-9) == held, (friction, moved)


def test_the_speed_limit_caps_the_joint_with_at_most_its_effort():
    robot = load_robot(single_rod(limit='<limit lower="-3" upper="3" effort="100" '
                                  'velocity="0.5"/>'))
    simulation = RobotSimulation(robot.model, RobotSettings(),
                                 initial_state(robot.model, joint_positions=[1.5]))
    fastest = 0.0
    for _tick in range(2000):
        simulation.step(DT)
        fastest = max(fastest, abs(simulation.joint_velocities()[0]))
    assert 0.49 < fastest <= 0.5 + 1e-9
    # With a weak brake (effort below gravity's torque) the rod runs past the limit.
    weak = load_robot(single_rod(limit='<limit lower="-3" upper="3" effort="0.5" '
                                 'velocity="0.5"/>'))
    simulation = RobotSimulation(weak.model, RobotSettings(),
                                 initial_state(weak.model, joint_positions=[1.5]))
    for _tick in range(500):
        simulation.step(DT)
    assert abs(simulation.joint_velocities()[0]) > 0.6


def test_a_pinocchio_that_fills_the_upper_triangle_only_steps_the_same(panda, monkeypatch):
    # Pinocchio before 4 returns M and M^-1 with their upper triangle only: the simulation
    # mirrors them, and steps exactly as with this Pinocchio's whole matrices.
    model = panda.model
    whole = RobotSimulation(model, RobotSettings(), initial_state(model))
    for _tick in range(50):
        whole.step(DT)
    for name in ('crba', 'computeMinverse'):
        compute = getattr(pinocchio, name)
        monkeypatch.setattr(pinocchio, name,
                            lambda *arguments, compute=compute: np.triu(compute(*arguments)))
    upper = RobotSimulation(model, RobotSettings(), initial_state(model))
    assert upper._mirrored and not whole._mirrored
    for _tick in range(50):
        upper.step(DT)
    assert upper.state.q.tolist() == whole.state.q.tolist()
    assert upper.state.v.tolist() == whole.state.v.tolist()


def test_a_robot_of_vector_space_joints_moves_by_the_sum_pinocchio_integrates(panda):
    # Revolute and prismatic joints only (nq = nv): q + h v is Pinocchio's integrate, bit for
    # bit, while the arm falls onto its stops and the mouse drags it.
    model = panda.model
    runs = []
    for additive in (True, False):
        settings = RobotSettings(constraint=MouseConstraint(max_force_per_weight=20.0),
                                 substeps=2)
        simulation = RobotSimulation(model, settings, initial_state(model))
        assert simulation._additive
        simulation._additive = additive
        simulation.grab('panda_hand', (0.0, 0.0, 0.1))
        states = []
        for tick in range(100):
            simulation.target = (0.4, 0.1 * math.sin(0.05 * tick), 0.5) if tick >= 50 else None
            states.append(simulation.step(DT))
        runs.append(states)
    for summed, integrated in zip(*runs):
        assert summed.q.tolist() == integrated.q.tolist()
        assert summed.v.tolist() == integrated.v.tolist()


def test_a_continuous_joint_is_integrated_on_its_circle():
    simulation = pendulum(double_pendulum(kind='continuous'))
    assert not simulation._additive
    for _tick in range(100):
        simulation.step(DT)
    cos, sin = simulation.state.q[:2].tolist()
    assert math.hypot(cos, sin) == pytest.approx(1.0, abs=1e-15)


@pytest.mark.parametrize('goal', [(3.0, 0.0, 0.5), (0.0, -3.0, 0.5), (0.5, 0.3, 0.4)])
def test_an_unbounded_rigid_mouse_moves_no_joint_more_than_the_travel_a_substep(panda, goal):
    # From the Panda's stretched, singular zero pose, toward a target out of reach or within
    # it, with no force bound: without the bounds the joints reach thousands of rad/s and the
    # step runs away to NaN within a few hundred ticks.
    model = panda.model
    simulation = RobotSimulation(model, RobotSettings(substeps=2), initial_state(model))
    simulation.grab('panda_hand', (0.0, 0.0, 0.0))
    guide = np.array(simulation.anchor_position())
    q = simulation.state.q
    largest_move = 0.0
    for _tick in range(1500):
        away = np.array(goal) - guide
        distance = float(np.linalg.norm(away))
        guide = guide + away * min(1.0, 0.002 / distance) if distance > 0.0 else guide
        simulation.target = tuple(guide)
        state = simulation.step(DT)
        assert np.all(np.isfinite(state.q)) and np.all(np.isfinite(state.v))
        assert np.all(np.isfinite(simulation.tick_impulse[0]))
        largest_move = max(largest_move, float(np.abs(state.q - q).max()))
        q = state.q
    # Two substeps a tick, each moving every joint by at most the travel.
    assert largest_move <= 2 * MAX_JOINT_TRAVEL * (1.0 + 1e-12)


def test_the_travel_bound_keeps_the_mouse_impulse_alone_within_the_travel():
    rng = np.random.default_rng(3)
    mobility = rng.normal(size=(7, 3))
    h = 5e-4
    bound = travel_bound(mobility, h)
    for _ in range(100):
        direction = rng.normal(size=3)
        impulse = bound * direction / np.linalg.norm(direction)
        assert np.abs(h * mobility @ impulse).max() <= MAX_JOINT_TRAVEL * (1.0 + 1e-12)
    assert travel_bound(np.zeros((7, 3)), h) == math.inf
