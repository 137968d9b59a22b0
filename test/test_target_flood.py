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
A flood of targets: one stream fit a tick at most, the newest target at each tick, in lockstep.

``OnePerTick`` alone, then the node stepped by ``SimulatedBody``: targets sent faster than the
node ticks cost it one fit a tick (the first after a tick as it comes, the newest of the rest at
the next tick), and the body moves as it does when the node is sent only those.
"""

import numpy as np

from mouse_constraint_ros.inputs.one_per_tick import OnePerTick
from mouse_constraint_ros.testing import SimulatedBody

GRAB = (0.2, 0.1, 1.05)  # the anchor where the body starts (corner of the default box)


def test_the_first_after_a_tick_goes_at_once_the_newest_of_the_rest_at_the_next():
    """Items 1 to 4 between two ticks: 1 at once, 4 at the tick; none held: the next at once."""
    latch = OnePerTick()
    assert latch.offer(1) == 1
    assert [latch.offer(n) for n in (2, 3, 4)] == [None] * 3
    assert latch.held_over == 2
    assert latch.tick() == 4
    assert latch.offer(5) is None  # after a tick that took one: held again
    assert latch.flush() == 5 and latch.flush() is None
    assert latch.tick() is None
    assert latch.offer(6) == 6  # after a tick that took none: at once


def test_a_flood_costs_the_node_one_fit_a_tick_and_moves_the_body_as_the_newest_targets_do():
    """
    Ten stamped targets between ticks, 200 ticks: one taken a tick, the newest, and no more.

    The first target is taken as it comes; from then on each tick takes the newest of the ten
    that came since the tick before, as it came (its stamp and arrival): the stream is fitted
    once a tick, not ten times. The body's poses are bit for bit those of a node sent only the
    targets taken.
    """
    def run(flood: bool):
        taken = []
        with SimulatedBody(rate_hz=500.0) as body:
            take = body.node.simulation.set_target

            def counted(point, **timing):
                taken.append(point)
                return take(point, **timing)
            body.node.simulation.set_target = counted
            body.step(2)
            poses = []
            for n in range(200):
                for k in range(10):
                    t = body.time - 0.002 + (k + 1) * 0.0002  # since the tick before
                    point = (GRAB[0] + 0.2 * np.sin(4.0 * t), GRAB[1], GRAB[2] + 0.05 * t)
                    if flood or k == 9 or (n, k) == (0, 0):
                        body.target(point, stamp=t)
                body.step()
                poses.append(body.pose.position.copy())
        return taken, np.array(poses)

    flooded, flood_poses = run(True)
    sparse, sparse_poses = run(False)
    assert len(flooded) == len(sparse) == 201
    assert flooded == sparse
    np.testing.assert_array_equal(flood_poses, sparse_poses)
