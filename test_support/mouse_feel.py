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
Scenarios of how a click and a drag move the body, shared by test/test_mouse_feel.py and bench.

``click`` holds the anchor where it starts (the body hangs from its corner and swings), then
jumps the target ``distance`` m along x and reports the peak COM and angular speeds and the
anchor error from 1.5 s after the click on. ``far_click`` clicks on the floor metres from the
box resting on it, held by its corner, and reports the peak speeds. ``circle`` streams a target
circling at ``speed`` at ``rate_hz`` (arrival times optionally jittered) and reports the RMS
distance between the anchor and where the target really is, once the drag is under way.
"""

import math
from pathlib import Path
from typing import Any, Dict, NamedTuple, Tuple

import numpy as np
import yaml

from mouse_constraint_ros.node.parameters import DEFAULTS, node_config, NodeConfig
from mouse_constraint_ros.physics import MouseSimulation

PARAMS_FILE = Path(__file__).resolve().parent.parent / 'config' / 'params.yaml'
# When the click comes after start (s), and how long after it the anchor must be on target.
CLICK_AT = 1.0
SETTLE = 1.5
# A click on the floor (the view's grid) this far (m) from the box resting on it, along -y.
FAR_CLICK = (0.0, -4.0, 0.0)


def shipped_parameters() -> Dict[str, Any]:
    """Return the parameters of config/params.yaml as shipped (parsed from the real file)."""
    return dict(yaml.safe_load(PARAMS_FILE.read_text())['/**']['ros__parameters'])


def configured(overrides: Dict[str, Any]) -> NodeConfig:
    """Return the node's configuration of config/params.yaml with ``overrides``."""
    return node_config({**DEFAULTS, **shipped_parameters(), **overrides})


class Click(NamedTuple):
    """What a click does: peak speeds (m/s, rad/s) and anchor errors (m)."""

    peak_speed: float
    peak_angular_speed: float
    error_at_settle: float
    error_after_settle: float
    error_last_second: float


def click(overrides: Dict[str, Any] = {}, *, distance: float = 0.5, seconds: float = 4.0) -> Click:
    """Run the click scenario on the configuration of params.yaml with ``overrides``."""
    config = configured(overrides)
    simulation = MouseSimulation(config.settings, config.initial_state)
    simulation.target = config.initial_anchor()
    dt = 1.0 / config.rate_hz
    for _ in range(round(CLICK_AT * config.rate_hz)):
        simulation.step(dt)
    target = tuple(np.array(simulation.anchor_position()) + (distance, 0.0, 0.0))
    simulation.set_target(target, time=simulation.time)
    speeds, spins, errors = [], [], []
    for _ in range(round(seconds * config.rate_hz)):
        state = simulation.step(dt)
        speeds.append(math.hypot(*state.linear_velocity))
        spins.append(math.hypot(*state.angular_velocity))
        errors.append(math.hypot(*simulation.anchor_error()))
    settled = round(SETTLE * config.rate_hz) - 1
    return Click(max(speeds), max(spins), errors[settled], max(errors[settled:]),
                 max(errors[-round(config.rate_hz):]))


def far_click(overrides: Dict[str, Any] = {}, *, target: Tuple[float, float, float] = FAR_CLICK,
              rest: float = 0.3, seconds: float = 3.0) -> Tuple[float, float]:
    """
    Return the peak COM speed (m/s) and angular speed (rad/s) of a click on the floor.

    The box of params.yaml with ``overrides`` lies on its floor, held by its corner where it
    starts, for ``rest`` s; then the target jumps to ``target`` (on the floor), and the box is
    dragged there by its corner for ``seconds``.
    """
    values = {**shipped_parameters(), **overrides}
    floor = float(values.get('floor_height', 0.0))
    config = configured({'initial_position': [0.0, 0.0, floor + 0.5 * values['box_size'][2]],
                         **overrides})
    simulation = MouseSimulation(config.settings, config.initial_state)
    simulation.target = config.initial_anchor()
    dt = 1.0 / config.rate_hz
    for _ in range(round(rest * config.rate_hz)):
        simulation.step(dt)
    simulation.set_target(target, time=simulation.time)
    speed = spin = 0.0
    for _ in range(round(seconds * config.rate_hz)):
        state = simulation.step(dt)
        speed = max(speed, math.hypot(*state.linear_velocity))
        spin = max(spin, math.hypot(*state.angular_velocity))
    return speed, spin


def circle(overrides: Dict[str, Any] = {}, *, speed: float = 1.0, radius: float = 0.25,
           rate_hz: float = 50.0, jitter: float = 0.0, seconds: float = 6.0,
           warm_up: float = 2.0, target_feed_forward: bool = True) -> float:
    """
    Return the RMS tracking error (m) of a circling target streamed at ``rate_hz``.

    :param jitter: each point arrives up to this late (s, uniform, seeded), positions exact.
    :param warm_up: the error is measured from this time on (s).
    """
    config = configured({**overrides, 'target_feed_forward': target_feed_forward})
    simulation = MouseSimulation(config.settings, config.initial_state)
    centre = np.array(config.initial_anchor()) - (radius, 0.0, 0.0)
    turn_rate = speed / radius

    def path(t: float) -> np.ndarray:
        return centre + radius * np.array([math.cos(turn_rate * t), math.sin(turn_rate * t), 0.0])

    dt = 1.0 / config.rate_hz
    random = np.random.default_rng(7)
    sent = [(k / rate_hz + random.uniform(0.0, jitter), path(k / rate_hz))
            for k in range(int(seconds * rate_hz) + 1)]
    sent.sort(key=lambda item: item[0])
    errors = []
    for tick in range(round(seconds * config.rate_hz)):
        now = tick * dt
        while sent and sent[0][0] <= now + 1e-12:
            simulation.set_target(tuple(sent.pop(0)[1]), time=simulation.time)
        simulation.step(dt)
        if now + dt >= warm_up:
            errors.append(np.linalg.norm(np.array(simulation.anchor_position()) - path(now + dt)))
    return float(np.sqrt(np.mean(np.square(errors))))


def seed_joint() -> Dict[str, Any]:
    """Return the overrides that give the seed's joint: none of the bounds or feed-forwards."""
    return {'max_force_per_weight': math.inf, 'angular_friction': 0.0,
            'max_target_speed': math.inf, 'max_target_acceleration': math.inf,
            'target_feed_forward': False, 'gravity_feed_forward': False}


SOFT = {'frequency_hz': 7.5, 'damping_ratio': 1.0}
