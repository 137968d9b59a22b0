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
A body point's world position x + R(q) r: ``BodyState.world_point``, and all that use it.

The simulation's anchor, the node's initial anchor and the recorder's anchor column are that one
function: they agree to the bit, and it agrees with scipy's rotation.
"""

import math

from geometry_msgs.msg import PoseStamped, TwistStamped
import numpy as np
import pytest
from rclpy.serialization import serialize_message
from scipy.spatial.transform import Rotation

from mouse_constraint_ros.node.parameters import DEFAULTS, node_config
from mouse_constraint_ros.physics import BodyState, MouseSimulation
from mouse_constraint_ros.recording.received import Received
from mouse_constraint_ros.recording.rows import tick_rows
from mouse_constraint_ros.wire.messages import fill_pose, fill_twist, set_stamp

RNG_SEED = 7
ANCHOR = (0.2, -0.1, 0.05)


def random_states(count: int) -> list:
    """Return ``count`` states with random positions and unit orientations."""
    rng = np.random.default_rng(RNG_SEED)
    return [BodyState(tuple(rng.uniform(-2.0, 2.0, 3)),
                      tuple(Rotation.random(random_state=rng).as_quat()),
                      tuple(rng.normal(size=3)), tuple(rng.normal(size=3)))
            for _ in range(count)]


@pytest.mark.parametrize('state', random_states(8))
def test_world_point_is_the_position_plus_the_rotated_point(state):
    """The point is x + R(q) r, with R(q) as scipy makes it from the quaternion (x, y, z, w)."""
    expected = np.add(state.position, Rotation.from_quat(state.orientation).apply(ANCHOR))
    np.testing.assert_allclose(state.world_point(ANCHOR), expected, rtol=0.0, atol=1e-14)
    assert state.world_point((0.0, 0.0, 0.0)) == state.position


def test_simulation_and_initial_anchor_are_the_world_point_of_the_anchor():
    """The stepped simulation's anchor and the config's initial anchor, bit for bit."""
    config = node_config({**DEFAULTS, 'anchor': list(ANCHOR),
                          'initial_orientation': [0.0, math.sin(0.4), 0.0, math.cos(0.4)]})
    assert config.initial_anchor() == config.initial_state.world_point(ANCHOR)
    simulation = MouseSimulation(config.settings, config.initial_state)
    simulation.target = (0.5, 0.3, 1.2)
    for _ in range(20):
        simulation.step(0.01)
    assert simulation.state.orientation != config.initial_state.orientation
    assert simulation.anchor_position() == simulation.state.world_point(ANCHOR)


def test_recorded_anchor_is_the_world_point_of_the_anchor():
    """The CSV's anchor column for a published pose is that pose's world point of the anchor."""
    received = []
    states = random_states(3)
    for k, state in enumerate(states):
        pose, twist = PoseStamped(), TwistStamped()
        for message in (pose, twist):
            set_stamp(message.header.stamp, 1_000_000 * (k + 1))
        fill_pose(pose, state)
        fill_twist(twist, state)
        received += [Received('pose', k, serialize_message(pose)),
                     Received('twist', k, serialize_message(twist))]
    rows = tick_rows(received, {'anchor': ANCHOR})
    assert [row.anchor for row in rows] == [state.world_point(ANCHOR) for state in states]
