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
Pointer streams as a network delivers them, run through the node in lockstep: bench and tests.

Each scenario is a list of pointer events (when the pointer was there, when the point is
delivered to the node, where, and whether it carries its stamp): a drag that stops at once or
slows down (``line_events``), the same as a browser samples and sends it
(``browser_line_events``), a still pointer's jitter (``still_events``), a browser's drag round
a circle (``circle_events``). ``lockstep_runs.run`` delivers them to the real node with the
shipped parameters and records the anchor's world position of every tick, and the metrics say
what the anchor did:

- ``overshoot``: how far the anchor went past the last point, along the drag's direction (m);
- ``speed_ratio``: the anchor's highest speed after the first second over the drag's speed
  (the start from rest is a step in the pointer's speed);
- ``wander``: the RMS distance of the anchor from a still pointer's position, after the first
  second (m), beside the pointer's own (``pointer_wander``);
- ``error``: the RMS distance of the anchor from the pointer's path, at the tick's time (on
  time) or at the delay that fits best (late: followed behind the received path), after
  ``WARM_UP``; ``behind`` is that delay (s);
- ``wobble``: the RMS of the anchor's speed over the pointer's, minus 1, over the same ticks.
"""

from typing import Dict, List, NamedTuple, Optional, Sequence

import numpy as np

from test_support.lockstep_runs import Event, run, start_point, Trace
from test_support.stream_timing import RADIUS, schedule, SPEED, TAIL, WARM_UP

# The drag of the stop and slow-down scenarios (m/s), along +x from the held anchor.
DRAG_SPEED = 0.5
# The slow-down: from DRAG_SPEED to rest, at a constant deceleration, over this long (s).
SLOW_DOWN = 0.2
# A still pointer's jitter: uniform within this (m) in x and y.
JITTER = 0.002
# The anchor has settled this long (s) after a stop's last point was delivered.
STOP_TAIL = 0.4
# The delays (s) the scenarios are delivered late by.
DELAYS = (0.0, 0.1, 0.2)
STILL_DELAYS = (0.0, 0.08, 0.16, 0.24)


def line_events(rate_hz: float, delay: float, *, slow_down: bool,
                seconds: float = 2.0) -> List[Event]:
    """
    Return a drag along +x at DRAG_SPEED for ``seconds``, sampled at ``rate_hz``.

    Delivered ``delay`` late; with ``slow_down`` its last SLOW_DOWN seconds come to rest
    evenly, else it stops at once. No event follows the last one (a pointer at rest sends
    none).
    """
    start = start_point()
    cruise = seconds - (SLOW_DOWN if slow_down else 0.0)

    def distance(t: float) -> float:
        if t <= cruise:
            return DRAG_SPEED * t
        braking = min(t - cruise, SLOW_DOWN)
        return DRAG_SPEED * (cruise + braking - braking * braking / (2.0 * SLOW_DOWN))

    count = int(round(seconds * rate_hz))
    return [Event(k / rate_hz, k / rate_hz + delay,
                  tuple(start + (distance(k / rate_hz), 0.0, 0.0))) for k in range(count + 1)]


def browser_line_events(rate_hz: float, delay: float, seed: int,
                        seconds: float = 2.0) -> List[Event]:
    """
    Return the drag of ``line_events`` that stops at once, as a browser samples and sends it.

    Each event is stamped with its time, irregular as ``stream_timing.schedule`` makes it
    (within a fifth of a period of its slot, sent within half a period), and delivered
    ``delay`` after it was sent.
    """
    start = start_point()
    plan = schedule(rate_hz, seconds, seed)
    return [Event(float(event), float(send) + delay,
                  tuple(start + (DRAG_SPEED * float(event), 0.0, 0.0)))
            for event, send in zip(plan.events, plan.sends)]


def still_events(rate_hz: float, delay: float, seconds: float = 3.0,
                 seed: int = 4) -> List[Event]:
    """Return a still pointer at the held anchor, jittering within JITTER in x and y."""
    start = start_point()
    random = np.random.default_rng(seed)
    count = int(round(seconds * rate_hz))
    return [Event(k / rate_hz, k / rate_hz + delay,
                  tuple(start + (*random.uniform(-JITTER, JITTER, 2), 0.0)))
            for k in range(count + 1)]


def circle_events(rate_hz: float, delay: float, seconds: float, *, mixed: bool = False,
                  seed: int = 1) -> List[Event]:
    """
    Return a browser's drag round the 1 m/s circle (``stream_timing``).

    Delivered ``delay`` late besides the browser's own send delay; ``mixed``: every other
    point unstamped.
    """
    plan = schedule(rate_hz, seconds, seed)
    points = [circle_points(np.array([event]))[0] for event in plan.events]
    return [Event(float(event), float(send) + delay, tuple(point), not (mixed and k % 2 == 1))
            for k, (event, send, point) in enumerate(zip(plan.events, plan.sends, points))]


class Stop(NamedTuple):
    """What the anchor did at the end of a drag that stops."""

    overshoot: float
    speed_ratio: float


def stop_metrics(trace: Trace, events: Sequence[Event]) -> Stop:
    """Return the overshoot past the last point and the highest speed over the drag's."""
    final = max(events, key=lambda e: e.time)
    past = trace.anchors[:, 0] - final.point[0]
    after = trace.times >= final.time
    speeds = np.linalg.norm(np.diff(trace.anchors, axis=0), axis=1) / np.diff(trace.times)
    overshoot = max(0.0, past[after].max())
    # After the first second: the start from rest is a step in the pointer's speed.
    highest = speeds[trace.times[1:] > 1.0].max()
    return Stop(float(overshoot), float(highest / DRAG_SPEED))


class Still(NamedTuple):
    """How much a still pointer and the anchor wandered (m, RMS)."""

    wander: float
    pointer_wander: float


def still_metrics(trace: Trace, events: Sequence[Event]) -> Still:
    """Return the anchor's and the pointer's RMS distance from where the pointer rests."""
    rest = start_point()
    settled = trace.anchors[trace.times >= 1.0]
    pointer = np.array([e.point for e in events if e.time >= 1.0])
    return Still(_rms_distance(settled, rest), _rms_distance(pointer, rest))


def _rms_distance(points: np.ndarray, place: np.ndarray) -> float:
    """Return the RMS distance (m) of ``points`` (one a row) from ``place``."""
    return float(np.sqrt(np.mean(np.sum((points - place) ** 2, axis=1))))


class Follow(NamedTuple):
    """How the anchor followed a circle: RMS error (m), RMS speed wobble, the delay behind."""

    error: float
    wobble: float
    behind: float


def circle_points(times: np.ndarray) -> np.ndarray:
    """Return the pointer's positions on ``stream_timing.circle`` at ``times`` (s), one a row."""
    angles = SPEED / RADIUS * np.asarray(times, dtype=float)
    centre = start_point() - (RADIUS, 0.0, 0.0)
    return centre + RADIUS * np.stack([np.cos(angles), np.sin(angles), 0.0 * angles], axis=1)


def follow_metrics(trace: Trace, seconds: float, *, behind: Optional[float] = 0.0) -> Follow:
    """
    Return how closely the anchor followed the circle, at the tick's time less ``behind`` (s).

    ``behind`` None: at the delay that fits best (to the millisecond, up to 0.3 s).
    """
    if behind is None:
        behind = min((k * 1e-3 for k in range(301)),
                     key=lambda d: _follow(trace, seconds, d).error)
    return _follow(trace, seconds, behind)


def _follow(trace: Trace, seconds: float, behind: float) -> Follow:
    """Return ``follow_metrics`` at ``behind`` (s)."""
    times = trace.times
    anchors = trace.anchors
    inside = (times >= WARM_UP + behind) & (times <= seconds + behind - TAIL)
    truth = circle_points(times[inside] - behind)
    error = float(np.sqrt(np.mean(np.sum((anchors[inside] - truth) ** 2, axis=1))))
    steps = np.linalg.norm(np.diff(anchors, axis=0), axis=1) / np.diff(times)
    paired = inside[1:] & inside[:-1]
    wobble = float(np.sqrt(np.mean(np.square(steps[paired] / SPEED - 1.0))))
    return Follow(error, wobble, behind)


def stop_rows(rates: Sequence[float] = (20.0, 60.0), delays: Sequence[float] = DELAYS,
              *, slow_down: bool) -> List[Dict[str, float]]:
    """Return a row per rate and delay of a drag that stops (at once, or slowing down)."""
    rows = []
    for rate in rates:
        for delay in delays:
            events = line_events(rate, delay, slow_down=slow_down)
            stop = stop_metrics(run(events, events[-1].delivered + STOP_TAIL), events)
            rows.append({'rate_hz': rate, 'delay_s': delay, 'overshoot_mm': 1e3 * stop.overshoot,
                         'gap_mm': 1e3 * DRAG_SPEED / rate, 'speed_ratio': stop.speed_ratio})
    return rows


def browser_stop_rows(rate: float = 20.0, delay: float = 0.2,
                      seeds: Sequence[int] = (1, 2)) -> List[Dict[str, float]]:
    """Return a row per seed of a browser's drag that stops at once (``browser_line_events``)."""
    rows = []
    for seed in seeds:
        events = browser_line_events(rate, delay, seed)
        last = max(event.delivered for event in events)
        stop = stop_metrics(run(events, last + STOP_TAIL), events)
        rows.append({'rate_hz': rate, 'delay_s': delay, 'seed': seed,
                     'overshoot_mm': 1e3 * stop.overshoot, 'gap_mm': 1e3 * DRAG_SPEED / rate,
                     'speed_ratio': stop.speed_ratio})
    return rows


def still_rows(rate: float = 60.0, delays: Sequence[float] = STILL_DELAYS) -> List[dict]:
    """Return a row per delay of a still, jittering pointer."""
    rows = []
    for delay in delays:
        events = still_events(rate, delay)
        still = still_metrics(run(events, events[-1].delivered), events)
        rows.append({'rate_hz': rate, 'delay_s': delay, 'wander_mm': 1e3 * still.wander,
                     'pointer_mm': 1e3 * still.pointer_wander})
    return rows


def circle_row(rate: float, delay: float, *, mixed: bool = False, seconds: float = 4.0,
               behind: Optional[float] = 0.0) -> dict:
    """Return the row of a browser's circle at ``rate``, ``delay`` late, perhaps mixed."""
    events = circle_events(rate, delay, seconds, mixed=mixed)
    follow = follow_metrics(run(events, seconds + delay + 0.2), seconds, behind=behind)
    return {'rate_hz': rate, 'delay_s': delay, 'mixed': mixed, 'error_mm': 1e3 * follow.error,
            'wobble_pct': 100.0 * follow.wobble, 'behind_ms': 1e3 * follow.behind}
