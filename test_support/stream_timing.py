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
A drag as a browser streams it, and how closely the anchor follows it: bench and tests share it.

The pointer moves round a horizontal circle at ``SPEED`` (radius ``RADIUS``) through the held
anchor, starting there at rest (so the guide's start is part of the run). A browser samples it
at ``rate_hz`` with irregular timing: each event is 1 / rate_hz after the previous one's slot,
give or take ``EVENT_JITTER`` of a period (uniform), and is sent ``SEND_DELAY`` of a period or
less after its event (uniform; at 20 Hz up to 25 ms, at 60 Hz up to 8 ms), stamped with the
event's time and carrying the pointer's exact position then.

The metrics, over the published states from ``WARM_UP`` after the start to ``TAIL`` before the
last event:

- anchor error: the RMS distance between the anchor (COM + R anchor) in the state stamped t and
  the pointer's true position on the circle at t;
- speed deviation: the RMS of |v_anchor| / SPEED - 1, v_anchor the finite difference of the
  anchor between two states one tick apart.
"""

import math
from typing import Callable, NamedTuple, Sequence, Tuple

import numpy as np

from mouse_constraint_ros.inputs.target_stamps import TargetTiming
from mouse_constraint_ros.physics import MouseSimulation
from mouse_constraint_ros.physics.target_stream import STREAM_GAP
from test_support.mouse_feel import configured

# The drags the benches run (bench.stream_timing, bench.stream_estimators): a browser's rates
# (Hz) and how long each drag lasts (s).
RATES_HZ = (20.0, 60.0)
SECONDS = 6.0
SPEED = 1.0
RADIUS = 0.25
EVENT_JITTER = 0.2
SEND_DELAY = 0.5
WARM_UP = 1.0
TAIL = 0.1


class Schedule(NamedTuple):
    """When each pointer event happened and when it is sent, from the drag's start (s)."""

    events: np.ndarray
    sends: np.ndarray


def schedule(rate_hz: float, seconds: float, seed: int = 1) -> Schedule:
    """Return the events of a ``seconds``-long drag at ``rate_hz``, in the order sent."""
    random = np.random.default_rng(seed)
    period = 1.0 / rate_hz
    count = int(seconds * rate_hz) + 1
    events = np.arange(count) * period + random.uniform(
        -EVENT_JITTER * period, EVENT_JITTER * period, count)
    events[0] = 0.0
    sends = events + random.uniform(0.0, SEND_DELAY * period, count)
    order = np.argsort(sends, kind='stable')
    return Schedule(events[order], sends[order])


def circle(start: Sequence[float]) -> Callable[[float], np.ndarray]:
    """Return the pointer's position at t (s from the start) on the circle through ``start``."""
    centre = np.asarray(start, dtype=float) - (RADIUS, 0.0, 0.0)
    turn_rate = SPEED / RADIUS

    def position(t: float) -> np.ndarray:
        angle = turn_rate * t
        return centre + RADIUS * np.array([math.cos(angle), math.sin(angle), 0.0])
    return position


class Following(NamedTuple):
    """How closely the anchor followed the pointer: RMS error (m), RMS speed deviation (1)."""

    error: float
    speed_deviation: float
    states: int


def following(times: np.ndarray, anchors: np.ndarray, path: Callable[[float], np.ndarray],
              duration: float, tick: float) -> Following:
    """
    Return the metrics of the module docstring.

    :param times: the states' stamps, from the drag's start (s), increasing.
    :param anchors: the anchor's world position in each state (m), one row each.
    :param path: the pointer's position at a time.
    :param duration: the time of the last event (s).
    :param tick: the node's tick (s): speeds are taken between states this far apart.
    """
    inside = (times >= WARM_UP) & (times <= duration - TAIL)
    errors = np.linalg.norm(anchors[inside] - np.array([path(t) for t in times[inside]]), axis=1)
    gaps = np.diff(times)
    steps = np.linalg.norm(np.diff(anchors, axis=0), axis=1)
    paired = inside[1:] & inside[:-1] & (np.abs(gaps - tick) < 1e-3 * tick)
    speeds = steps[paired] / gaps[paired]
    return Following(float(np.sqrt(np.mean(np.square(errors)))),
                     float(np.sqrt(np.mean(np.square(speeds / SPEED - 1.0)))),
                     int(np.count_nonzero(inside)))


def replay(rate_hz: float, stamped: bool, seconds: float, seed: int = 1, *,
           stamp_noise: float = 0.0, pixel: float = 0.0,
           drops: Sequence[Tuple[float, float]] = ()) -> Following:
    """
    Return the metrics of the same drag fed to the core as the node feeds it, without ROS.

    Each target arrives when it is sent and is taken before the first tick due at or after
    that, timed as the node times it (``TargetTiming``) with the latest tick's stamp. Ticks run
    on time: this is the floor that scheduling and transport add to.

    :param stamp_noise: each stamp is off its event by up to this much (s, uniform), as a
        coarse clock would stamp it.
    :param pixel: positions are rounded to this grid in x and y (m), as screen pixels are.
    :param drops: (start, length) of spells of dropped ticks (s from the start): the core does
        not step and no state is published, as when the node cannot keep its rate.
    """
    config = configured({})
    simulation = MouseSimulation(config.settings, config.initial_state)
    simulation.target = config.initial_anchor()
    path = circle(config.initial_anchor())
    plan = schedule(rate_hz, seconds, seed)
    random = np.random.default_rng(seed + 1000)
    tick = 1.0 / config.rate_hz
    tick_ns = round(tick * 1e9)
    timing = TargetTiming(STREAM_GAP)
    origin_ns = 1_000_000_000_000
    last_tick_ns = origin_ns
    pending = list(zip(plan.events, plan.sends))
    times, anchors = [], []
    n = 0
    while n * tick <= seconds + 0.1:
        now_ns = origin_ns + n * tick_ns
        while pending and origin_ns + round(pending[0][1] * 1e9) <= now_ns:
            event = pending.pop(0)[0]
            jitter = random.uniform(-stamp_noise, stamp_noise) if stamp_noise else 0.0
            stamp = origin_ns + round((event + jitter) * 1e9) if stamped else 0
            point = path(event)
            if pixel:
                point[:2] = np.round(point[:2] / pixel) * pixel
            timing.take(simulation, tuple(point), stamp_ns=stamp, now_ns=now_ns,
                        tick_stamp_ns=last_tick_ns, tick_s=tick, ticked=n > 0)
        if any(start <= n * tick < start + length for start, length in drops):
            n += 1  # dropped: no step, no state
            continue
        state = simulation.step(tick)
        last_tick_ns = now_ns
        times.append(n * tick)
        anchors.append(state.world_point(config.settings.constraint.anchor))
        n += 1
    return following(np.array(times), np.array(anchors), path, seconds, tick)
