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
The shipped angular friction: a hung body's spin dies down, its swing goes on.

The friction acts on the spin about the line from the anchor to the COM alone. A body hung by
its anchor and released some degrees from hanging swings as the compound pendulum of its mass,
inertia and anchor distance, T = 4 sqrt(I_A / (m g d)) K(sin^2(theta_0 / 2)), I_A its moment
about the swing axis through the anchor, and keeps its energy; spun about the hanging line, it
stops at the friction's torque bound. Each case runs the node's shipped parameters
(config/params.yaml), in the core and through the lockstep harness.
"""

import math
from typing import List, Tuple

import numpy as np
import pytest
from scipy.spatial.transform import Rotation
from scipy.special import ellipk

from mouse_constraint_ros.physics import BodyState, MouseSimulation
from mouse_constraint_ros.physics.settings import friction_torque_bound, Settings
from test_support.mouse_feel import configured, shipped_parameters

SHIPPED_ANCHOR = tuple(shipped_parameters()['anchor'])
HOOK = np.array([0.0, 0.0, 1.5])  # where the anchor is held (m): the body hangs below it
SECONDS = 20.0


def _inertia(settings: Settings) -> np.ndarray:
    xx, xy, xz, yy, yz, zz = settings.body.inertia
    return np.array([[xx, xy, xz], [xy, yy, yz], [xz, yz, zz]])


def _hanging(settings: Settings) -> Rotation:
    """Return the orientation in which the COM hangs straight below the anchor."""
    rotation, _ = Rotation.align_vectors([[0.0, 0.0, 1.0]], [settings.constraint.anchor])
    return rotation


def swing_axes(settings: Settings) -> Tuple[np.ndarray, np.ndarray]:
    """
    Return the moments about the COM and the horizontal axes of the hung body's plain swings.

    The friction holds the spin about the hanging line at zero, so a small swing turns the body
    about a horizontal axis e; it stays in its plane when e is a principal axis of the
    horizontal block of the hung body's inertia.
    """
    rotation = _hanging(settings).as_matrix()
    moments, axes = np.linalg.eigh((rotation @ _inertia(settings) @ rotation.T)[:2, :2])
    return moments, np.vstack([axes, np.zeros(2)]).T


def pendulum_period(settings: Settings, moment: float, amplitude: float) -> float:
    """Return the compound pendulum's period (s) for ``moment`` about the COM (kg m^2)."""
    mass, g = settings.body.mass, math.hypot(*settings.gravity)
    d = math.hypot(*settings.constraint.anchor)
    small = 2.0 * math.pi * math.sqrt((moment + mass * d * d) / (mass * g * d))
    return small * 2.0 * ellipk(math.sin(amplitude / 2.0) ** 2) / math.pi


def released(settings: Settings, axis: np.ndarray, angle: float) -> MouseSimulation:
    """Return a simulation of the body hung at HOOK, turned ``angle`` about ``axis``, at rest."""
    rotation = Rotation.from_rotvec(angle * axis) * _hanging(settings)
    position = HOOK - rotation.apply(settings.constraint.anchor)
    simulation = MouseSimulation(settings, BodyState(tuple(position), tuple(rotation.as_quat())))
    simulation.target = tuple(HOOK)
    return simulation


def swing(simulation: MouseSimulation, axis: np.ndarray, seconds: float,
          dt: float) -> Tuple[List[float], float]:
    """Return the swing angle about ``axis`` after each step (rad), and the energy change."""
    settings = simulation.settings
    side = np.cross(axis, (0.0, 0.0, 1.0))
    weight = settings.body.mass * math.hypot(*settings.gravity)

    def energy() -> float:
        return simulation.kinetic_energy() + weight * simulation.state.position[2]

    start = energy()
    lowest = weight * (HOOK[2] - math.hypot(*settings.constraint.anchor))
    angles = []
    for _ in range(round(seconds / dt)):
        up = HOOK - np.array(simulation.step(dt).position)
        angles.append(math.atan2(up @ side, up[2]))
    return angles, (energy() - start) / (start - lowest)


def crossings(angles: List[float], dt: float) -> List[float]:
    """Return the times (s) at which the swing passes through hanging, interpolated."""
    return [dt * (i + 1 + a / (a - b)) for i, (a, b) in enumerate(zip(angles, angles[1:]))
            if (a > 0.0) != (b > 0.0)]


def shipped(anchor=SHIPPED_ANCHOR) -> Tuple[Settings, float]:
    """Return the shipped settings with ``anchor`` and no floor, and the tick (s)."""
    config = configured({'anchor': list(anchor), 'floor': False})
    assert config.settings.constraint.angular_friction == 0.25  # the shipped default
    return config.settings, 1.0 / config.rate_hz


@pytest.mark.parametrize('degrees', [5.0, 60.0])
@pytest.mark.parametrize('mode', [0, 1])
def test_the_shipped_box_hung_by_its_corner_swings_on(degrees, mode):
    """
    Released 5 or 60 degrees from hanging: it swings for 20 s and keeps its energy to 0.5 %.

    At 5 degrees it swings with the compound pendulum's period to 0.1 %. At 60 the corner's
    swing leaves its plane (the hung box's product of inertia across the hanging line turns
    it), so the period is the pendulum's no longer; its energy still stays.
    """
    settings, dt = shipped()
    moments, axes = swing_axes(settings)
    period = pendulum_period(settings, moments[mode], math.radians(degrees))
    angles, energy_change = swing(released(settings, axes[mode], math.radians(degrees)),
                                  axes[mode], SECONDS, dt)
    times = crossings(angles, dt)
    assert len(times) >= 2 * math.floor(SECONDS / period)
    assert abs(energy_change) < 5e-3
    if degrees == 5.0:
        assert 2.0 * np.mean(np.diff(times)) == pytest.approx(period, rel=1e-3)
        assert max(abs(a) for a in angles[-round(period / dt):]) \
            == pytest.approx(math.radians(degrees), rel=2e-2)


@pytest.mark.parametrize('degrees', [5.0, 60.0])
@pytest.mark.parametrize('anchor', [(0.2, 0.0, 0.0), (0.0, 0.0, 0.05)])
def test_a_box_hung_on_a_principal_axis_swings_as_the_compound_pendulum(degrees, anchor):
    """Hung from an end or top face's centre: the period to 0.1 % at any amplitude, 20 s."""
    settings, dt = shipped(anchor)
    moments, axes = swing_axes(settings)
    for moment, axis in zip(moments, axes):
        period = pendulum_period(settings, moment, math.radians(degrees))
        angles, energy_change = swing(released(settings, axis, math.radians(degrees)), axis,
                                      SECONDS, dt)
        times = crossings(angles, dt)
        assert len(times) >= 2 * math.floor(SECONDS / period)
        assert 2.0 * np.mean(np.diff(times)) == pytest.approx(period, rel=1e-3)
        assert abs(energy_change) < 5e-3


@pytest.mark.parametrize('anchor', [SHIPPED_ANCHOR, (0.2, 0.0, 0.0)])
def test_the_spin_about_the_hanging_line_dies_down(anchor):
    """
    Spun at 3 rad/s about the hanging line: the spin stops, the torque within its bound.

    About a principal axis (an end face's centre) the spin is the friction's alone: it falls
    at the bound's rate, tau / I_n, and stops at I_n w / tau. From the corner it shares its
    momentum with the swing, and stops within twice that.
    """
    settings, dt = shipped(anchor)
    hanging = _hanging(settings)
    line = hanging.apply(settings.constraint.anchor) / math.hypot(*settings.constraint.anchor)
    position = HOOK - hanging.apply(settings.constraint.anchor)
    spin = 3.0
    simulation = MouseSimulation(settings, BodyState(tuple(position), tuple(hanging.as_quat()),
                                                     (0.0, 0.0, 0.0), tuple(spin * line)))
    simulation.target = tuple(HOOK)
    bound = friction_torque_bound(settings)
    rotation = hanging.as_matrix()
    moment = line @ (rotation @ _inertia(settings) @ rotation.T) @ line
    stop = moment * spin / bound
    spins, torques = [], []
    for _ in range(round(2.0 * stop / dt)):
        state = simulation.step(dt)
        axis = Rotation.from_quat(state.orientation).apply(settings.constraint.anchor)
        spins.append(np.dot(state.angular_velocity, axis) / np.linalg.norm(axis))
        torques.append(simulation.friction_torque)
    assert max(torques) <= bound * (1.0 + 1e-12)
    assert abs(spins[-1]) < 1e-3 * spin
    if anchor != SHIPPED_ANCHOR:
        # w(t) = w_0 - tau t / I_n while it spins, to a substep's share of the fall.
        substep = bound * dt / settings.substeps / moment
        for tick in range(round(0.9 * stop / dt)):
            assert spins[tick] == pytest.approx(spin - bound * (tick + 1) * dt / moment,
                                                abs=substep)


def test_the_node_with_shipped_parameters_lets_its_hung_box_swing(simulated_body_factory):
    """
    Through the lockstep harness: the box hung 5 degrees from its corner swings to and fro.

    The node's defaults hold the anchor where it starts; released there, the swing passes
    through hanging twice a period and keeps its amplitude.
    """
    settings, dt = shipped()
    moments, axes = swing_axes(settings)
    angle = math.radians(5.0)
    rotation = Rotation.from_rotvec(angle * axes[0]) * _hanging(settings)
    position = HOOK - rotation.apply(settings.constraint.anchor)
    body = simulated_body_factory(initial_position=tuple(position),
                                  initial_orientation=tuple(rotation.as_quat()))
    side = np.cross(axes[0], (0.0, 0.0, 1.0))
    angles = []
    body.add_tick_callback(lambda b: angles.append(
        math.atan2((b.anchor - b.pose.position) @ side, (b.anchor - b.pose.position)[2])))
    period = pendulum_period(settings, moments[0], angle)
    body.step(round(1.6 * period / dt))
    assert np.allclose(body.anchor, HOOK, atol=1e-6)
    assert len(crossings(angles, dt)) == 3
    assert max(abs(a) for a in angles[-round(period / dt):]) \
        == pytest.approx(angle, rel=2e-2)
