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

"""A new anchor on a held body (a grab): the guide starts again where the new anchor is."""

import dataclasses
import math

import numpy as np

from mouse_constraint_ros.physics import MouseSimulation
from test_support.mouse_feel import configured

# A point on the shipped box (0.4 x 0.2 x 0.1 m): the centre of its -y face, as a grab gives it.
GRABBED = (0.0, -0.1, 0.0)


def test_a_grab_on_a_hanging_body_swings_it_without_a_fling():
    """
    Shipped parameters: the body hangs from its corner, then the anchor becomes another point.

    The joint pulls the new anchor to where it is (the guide starts there), so the body only
    swings down from it: its COM can fall at most 2 |r| (r the new lever), so its speed stays
    below sqrt(2 g 2 |r|). A guide left where the old anchor was would pull the new point there
    at the force bound instead.
    """
    config = configured({})
    simulation = MouseSimulation(config.settings, config.initial_state)
    simulation.target = config.initial_anchor()
    dt = 1.0 / config.rate_hz
    for _ in range(round(config.rate_hz)):
        simulation.step(dt)
    settings = simulation.settings
    simulation.settings = dataclasses.replace(settings, constraint=dataclasses.replace(
        settings.constraint, anchor=GRABBED))
    point = simulation.anchor_position()
    simulation.target = point
    simulation.step(dt)
    assert math.dist(simulation.joint_target, point) <= (
        settings.target_motion.max_speed * dt)
    speeds = [math.hypot(*simulation.step(dt).linear_velocity)
              for _ in range(round(2.0 * config.rate_hz))]
    gravity = math.hypot(*settings.gravity)
    assert max(speeds) < math.sqrt(2.0 * gravity * 2.0 * np.linalg.norm(GRABBED))
