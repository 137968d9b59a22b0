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
Pointer events delivered to the real node, stepped in lockstep on simulated time.

The node runs with the shipped parameters (config/params.yaml, ``parameters``) in
``SimulatedBody``. A point delivered at time d is published before the first tick after d and
the executor drained, so the node takes it before that tick. Between deliveries the node's ticks
run alone, undrained, and the node publishes its state once a second (``QUIET``): nothing it
hears changes between them and what it publishes is not read. These are the same ticks as
``SimulatedBody.step``'s with every state published, at a tenth of the cost
(``run(..., drained=True)`` steps so; test_late_streams checks the two agree to the bit). The
anchor's world position of every tick is recorded (``Trace``).

The scenarios that run so: ``late_streams`` (pointer streams late and mixed) and
``floor_press`` (a held corner pressed into the floor and lifted).
"""

from functools import lru_cache
from typing import NamedTuple, Sequence

import numpy as np

from mouse_constraint_ros.testing import SimulatedBody
from test_support.mouse_feel import shipped_parameters

# What the node publishes, while its ticks run undrained: its state once a second, no markers.
QUIET = {'marker_rate_hz': 0.0, 'diagnostics_rate_hz': 0.0, 'publish_rate_hz': 1.0}


class Event(NamedTuple):
    """A pointer event: at ``time`` it was at ``point``; delivered at ``delivered``."""

    time: float
    delivered: float
    point: tuple
    stamped: bool = True


class Trace(NamedTuple):
    """The anchor's world position at each tick's time (s)."""

    times: np.ndarray
    anchors: np.ndarray


def parameters() -> dict:
    """Return the shipped parameters, less those the harness owns."""
    values = shipped_parameters()
    for name in ('publish_clock', 'real_time_factor', 'use_sim_time'):
        values.pop(name, None)
    return values


@lru_cache(maxsize=1)
def _start() -> tuple:
    """Return ``start_point`` as a tuple, read from the shipped parameters once."""
    values = parameters()
    return tuple(np.array(values['initial_position']) + np.array(values['anchor']))


def start_point() -> np.ndarray:
    """Return where the shipped body's anchor is held at the start (m)."""
    return np.array(_start())


def run(events: Sequence[Event], seconds: float, *, drained: bool = False,
        **overrides) -> Trace:
    """
    Deliver ``events`` to the node (shipped parameters and ``overrides``) for ``seconds``.

    Stamped events carry their time as the stamp (the node's clock is the simulated one, from
    0); the others a zero stamp.

    :param drained: step with ``SimulatedBody.step``, the executor drained after every tick,
        every state published.
    """
    pending = sorted(events, key=lambda e: e.delivered)
    quiet = {**QUIET, 'publish_rate_hz': 0.0} if drained else QUIET
    values = {**parameters(), **quiet, **overrides}
    times, anchors = [], []
    with SimulatedBody(**values) as body:
        anchor = tuple(values['anchor'])
        simulation = body.node.simulation
        ticker = body.node.ticker
        index = 0
        while body.time < seconds - 1e-9:
            while index < len(pending) and pending[index].delivered <= body.time + 1e-12:
                event = pending[index]
                body.target(event.point, stamp=event.time if event.stamped else None)
                index += 1
            if drained:
                body.step()
            else:
                ticker.step()  # the node's tick, the executor not drained
            times.append(body.time)
            anchors.append(simulation.state.world_point(anchor))
    return Trace(np.array(times), np.array(anchors))
