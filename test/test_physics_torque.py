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

"""A torque on a free body: the angular momentum about the COM changes by tau t, exactly."""

import math

from hypothesis import given, settings as hypothesis_settings, strategies as st
import numpy as np
import pytest
from scipy.spatial.transform import Rotation

from mouse_constraint_ros.physics import BodyState, MouseSimulation, RigidBody, Settings
from mouse_constraint_ros.physics import STANDARD_GRAVITY

# The shipped config's rate and substeps (config/params.yaml).
DT = 0.001
SUBSTEPS = 2
H = DT / SUBSTEPS


def momentum_after(body: RigidBody, torque, *, steps: int, orientation=(0.0, 0.0, 0.0, 1.0),
                   spin=(0.0, 0.0, 0.0)):
    """Return (L at the start, L after ``steps`` ticks) of a free falling body under ``torque``."""
    sim = MouseSimulation(Settings(body, gravity=STANDARD_GRAVITY, substeps=SUBSTEPS),
                          BodyState((0.0, 0.0, 1.0), orientation, (0.0, 0.0, 0.0), spin))
    start = np.array(sim.angular_momentum())
    sim.wrench = ((0.0, 0.0, 0.0), tuple(torque))
    for _ in range(steps):
        sim.step(DT)
    return start, np.array(sim.angular_momentum())


def expected(start, torque, steps: int):
    """
    Return L0 + tau (t - h / 2): the published velocities are the leapfrog's half-step ones.

    The state after n ticks carries the angular velocity of time t - h / 2, t = n dt.
    """
    return start + np.array(torque) * (steps * DT - 0.5 * H)


@pytest.mark.parametrize('mass, torque', [
    (2.0, (80.0, 37.0, -45.0)),   # the shipped box, under max_wrench_torque
    (0.01, (0.8, 0.0, 0.0)),
    (0.01, (0.5, -0.4, 0.3)),
    (1e-87, (1e-87, 2e-87, -0.5e-87)),
])
def test_a_torque_on_the_shipped_box_gives_l_equal_to_tau_t(mass, torque):
    """A second of torque: L = tau t to 1e-9, from 2 kg to 1e-87 kg, spinning at ~1e4 rad/s."""
    body = RigidBody.solid_box(mass, (0.4, 0.2, 0.1))
    start, end = momentum_after(body, torque, steps=1000)
    goal = expected(start, torque, 1000)
    assert np.linalg.norm(end - goal) <= 1e-9 * np.linalg.norm(goal)


@hypothesis_settings(max_examples=40, deadline=None)
@given(mass=st.floats(-87.0, 3.0).map(lambda e: 10.0 ** e),
       extents=st.tuples(*[st.floats(0.1, 1.0)] * 3),
       direction=st.tuples(*[st.floats(-1.0, 1.0)] * 3).filter(
           lambda d: math.hypot(*d) > 0.1),
       reach=st.floats(0.0, 5.0),
       orientation=st.tuples(*[st.floats(-1.0, 1.0)] * 4).filter(
           lambda q: math.hypot(*q) > 0.1),
       spin=st.tuples(*[st.floats(-50.0, 50.0)] * 3))
def test_random_bodies_and_torques_give_l_equal_to_l0_plus_tau_t(mass, extents, direction,
                                                                 reach, orientation, spin):
    """
    Any box, mass, orientation, initial spin and torque: L = L0 + tau t to 1e-9 of |L|.

    The torque is drawn so that the body reaches up to ``reach`` rad per substep (up to
    10,000 rad/s), far beyond where a turn by w h would hold L.
    """
    body = RigidBody.solid_box(mass, extents)
    steps = 200
    magnitude = reach / H * body.principal_moments[0] / (steps * DT)
    torque = magnitude * np.array(direction) / np.linalg.norm(direction)
    quaternion = tuple(Rotation.from_quat(orientation).as_quat())
    start, end = momentum_after(body, torque, steps=steps, orientation=quaternion, spin=spin)
    goal = expected(start, torque, steps)
    scale = max(np.linalg.norm(goal), np.linalg.norm(start))
    assert np.linalg.norm(end - goal) <= 1e-9 * scale
