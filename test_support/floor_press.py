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
A resting box's held corner pressed into the floor, then lifted: through the node, in lockstep.

The box rests on the floor (shipped: z = 0) holding its top corner; the target goes below the
floor, where the floor holds the anchor back, then above it, where the anchor is let go. The
node runs as ``lockstep_runs`` runs it (shipped parameters, ``QUIET``, its ticks undrained), and
the run's peaks say whether the let-go anchor flung the body (docs/contact.md, docs/dragging.md:
a held-back anchor).
"""

from typing import NamedTuple

import numpy as np

from mouse_constraint_ros.testing import SimulatedBody
from test_support.lockstep_runs import parameters, QUIET


class Peaks(NamedTuple):
    """The highest COM speed (m/s) and angular speed (rad/s) of a run."""

    speed: float
    spin: float


def floor_press(depth: float = 0.5, aside: float = 0.3, lift: float = 0.5, *,
                press: float = 1.0, back: bool = False) -> Peaks:
    """
    Return the peaks of a resting box whose held corner is pressed into the floor, then lifted.

    The box rests on the floor (shipped: z = 0) holding its top corner; after 0.5 s the target
    is the corner ``depth`` below the floor and ``aside`` along x, for ``press`` seconds; then
    ``lift`` above where the corner started (``back``) or above the pressed point, for 1.5 s.
    """
    values = {**parameters(), **QUIET}
    values['initial_position'] = [0.0, 0.0, 0.5 * values['box_size'][2]]
    peaks = [0.0, 0.0]
    with SimulatedBody(**values) as body:
        simulation = body.node.simulation
        ticker = body.node.ticker

        def ticks(count: int, watched: bool = True) -> None:
            # The node's ticks, undrained (``lockstep_runs``); the speeds the twist says.
            for _ in range(count):
                ticker.step()
                if watched:
                    state = simulation.state
                    peaks[0] = max(peaks[0], float(np.linalg.norm(state.linear_velocity)))
                    peaks[1] = max(peaks[1], float(np.linalg.norm(state.angular_velocity)))

        # At rest on the floor first; then pressed in; then lifted.
        ticks(500, watched=False)
        corner = np.array(simulation.anchor_position())
        body.target(tuple(corner + (aside, 0.0, -depth)))
        body.drain()
        ticks(round(press * 1000))
        body.target(tuple(corner + (0.0 if back else aside, 0.0, lift)))
        body.drain()
        ticks(1500)
    return Peaks(*peaks)
