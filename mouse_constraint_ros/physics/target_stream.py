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
A stream of targets, as a network delivers it: fitted, timed by its latency, presented smoothly.

A mouse sends positions, not motions: a drag is a stream of points some 20 ms apart, a click a
single point that may land anywhere. ``TargetStream`` fits the stream's last points as a
polynomial in time (the core's time, seconds of simulated time) and says where the target is
now (``predict``), which the guide and the joint's feed-forward follow. How closely depends on
what the times are:

- *Arrival times* (the time a point reached the node, late by a varying delay): a
  least-squares fit over the last ``STREAM_SAMPLES`` points (a parabola from
  ``QUADRATIC_SAMPLES`` on), which averages the jitter of the arrival times instead of
  dividing by one noisy interval. It is extrapolated for ``EXTRAPOLATION_INTERVALS`` of the
  stream's mean interval after the latest point arrived.
- *Stamps* (the time the pointer was at the point, with the arrival time beside it): the
  times are exact, so the fit follows the curve instead of averaging: a polynomial of degree
  up to ``STAMPED_DEGREE`` over the points of the last ``STAMPED_WINDOW`` seconds (at most
  ``STAMPED_SAMPLES``), two points more than its coefficients. A parabola over 0.4 s of a
  circle turning 4 rad/s takes it for a flatter curve and extrapolates it outwards; a
  quartic does not (bench/stream_timing.py, docs/dragging.md).

**Latency.** A stamped point's latency is its arrival minus its stamp. A pointer across a
network arrives 50-250 ms after its events; extrapolating the fit over all of that turns a stop
into a fling and a still pointer's jitter into a wander (docs/dragging.md). So the stream is
*presented at a delay*: at core time t the target is the fit at t - D, D the least latency of
the stream's points, the part of the latency every point has (transport, a remote clock's
offset). Beyond the latest stamp the fit is extrapolated only as far as a healthy stream needs
before its next point arrives, the ``horizon``: the longest interval between the window's
stamps plus the spread of their latencies above D. A stream on time (D about 0) is thus
followed without lag, its target running at most that horizon ahead of the latest point; a
late one is followed at its delay, smoothly behind the received path, and never flung. Valve's
Source engine renders remote entities in the past for the same reason (``cl_interp``) and
extrapolates only a capped time when packets are missing.

A late stream has time to spare: it is presented later still, by its ``Lag`` (``stream_lag``),
so that past its latest stamp it is extrapolated about one mean interval, not its whole horizon.

When no point comes within the horizon (the pointer stopped, or a point is late) the
extrapolation stops: the target eases back to the latest point over another horizon (a
smoothstep, at most 1.5 times the speed it had), where a stopped drag ends.

A point is part of the stream only if it comes within ``STREAM_GAP`` of the previous one,
after it, and implies a speed no greater than the guide may move (``TargetMotion.max_speed``);
any other point (a click, a jump, a point after a pause, a point without a time) starts a new
stream of velocity zero, so a jump is never mistaken for a huge velocity. Two time bases are
never mixed in one fit: a stamped point after arrival-timed ones, or one whose latency jumps by
more than ``LATENCY_JUMP`` out of the window's, starts a new stream; an unstamped point in a
stamped stream (two publishers, or a stamp the node could not use) is put on the stamps' base,
at its arrival less the stream's median latency, and shapes the fit without anchoring it.

Plain float arithmetic (one small numpy least-squares solve per point), deterministic for the
same inputs.
"""

from collections import deque
import math
from typing import Deque, Optional, Tuple

import numpy as np

from .algebra import Vector3
from .polynomial import around, cross_validated, Curve, evaluate, polynomial
from .stream_lag import jitter, Lag

# Points further apart in time than this (s) are not one stream: a pause ends a drag.
STREAM_GAP = 0.25
# Arrival-timed streams: the velocity is the least-squares slope over at most this many of the
# stream's last points.
STREAM_SAMPLES = 8
# From this many points on, the fit is a parabola: a curved drag is extrapolated along its curve
# (bench/mouse_feel.py: a circle at 1 m/s, 50 Hz, soft 7.5 Hz joint: 5 mm RMS error, against
# 19 mm with a line over as many points); eight points keep the parabola's slope as steady
# under arrival jitter as a two-point difference is not (test_mouse_feel).
QUADRATIC_SAMPLES = 4
# Stamped streams: a polynomial of at most this degree over the points of the last
# STAMPED_WINDOW seconds, at most STAMPED_SAMPLES of them (a browser's 20 Hz drag round a 1 m/s
# circle of radius 0.25 m: anchor 0.9 mm and speed 1.1 % RMS off, against 23 mm and 17 % with a
# parabola on the same stamps; ``python -m bench.stream_estimators``). At most 4:
# ``polynomial`` lays it out as a quartic.
STAMPED_DEGREE = 4
STAMPED_WINDOW = 0.4
STAMPED_SAMPLES = 32
# Arrival-timed streams are extrapolated for at most this many of their mean intervals after a
# point arrived (their times jitter by the arrivals' delays).
EXTRAPOLATION_INTERVALS = 1.5
# A stamped stream's extrapolation goes over from the previous fit to the new one in this many
# mean intervals after a point arrived (``TargetStream.predict``).
BLEND_INTERVALS = 1.0
# A stamped point whose latency lies farther than this (s) out of the range of the window's
# latencies starts a new stream: a latency that jumps is another path or another clock.
LATENCY_JUMP = 0.05
# The weight, in the stamped fit, of an unstamped point put on the stamps' base by its arrival:
# its time is off by as much as the latencies spread.
UNSTAMPED_WEIGHT = 0.25
ZERO: Vector3 = (0.0, 0.0, 0.0)
# Points closer in time than this (s) to the latest are at its time: they replace its point.
SAME_TIME = 1e-6


def _smoothstep(u: float) -> Tuple[float, float]:
    """Return 3 u^2 - 2 u^3 and its derivative, for u in [0, 1]."""
    return u * u * (3.0 - 2.0 * u), 6.0 * u * (1.0 - u)


class TargetStream:
    """The last points of the target with their times; the fit, the latency, the presentation."""

    def __init__(self) -> None:
        """Start empty."""
        # (time, point, exact): exact unless an unstamped point put on the stamps' base.
        self._points: Deque[Tuple[float, Vector3, bool]] = deque(maxlen=STAMPED_SAMPLES)
        # The latencies (s) of the latest stamped points, kept over a restart of the stream
        # (a pause, a jump, dropped ticks: the same path); a latency that jumps out of their
        # range, or a stream of arrival times, starts them again.
        self._latencies: Deque[float] = deque(maxlen=STAMPED_SAMPLES)
        # The least latency since they started (s).
        self._floor = math.inf
        # The fit about the anchoring point (``evaluate``); None for none (no point, or one).
        self._curve: Optional[Curve] = None
        # How far (s) past the latest stamp the fit is extrapolated, and the delay (s) the
        # stream is presented at, both before a late stream's lag.
        self._horizon = 0.0
        self._delay = 0.0
        # A late stream's lag behind that delay.
        self._lag = Lag()
        # The mean interval between the stream's points (s).
        self._interval = 0.0
        # (time, point) of the latest point; its arrival time; whether times are stamps.
        self._latest: Optional[Tuple[float, Vector3]] = None
        self._arrival = 0.0
        self._stamped = False
        # A stamped stream's previous fit, blended into the new one from the new point's
        # arrival over BLEND_INTERVALS mean intervals (``_interval``); None when not blending.
        self._previous: Optional[Curve] = None

    @property
    def velocity(self) -> Vector3:
        """Return the estimated velocity of the stream at its latest point (m/s), zero alone."""
        return ZERO if self._curve is None else self._curve[2][0]

    @property
    def delay(self) -> float:
        """Return the stream's presentation delay in seconds, as of its latest point."""
        return self._delay + self._lag.value

    @property
    def horizon(self) -> float:
        """Return how far (s) past its latest point's time the stream is extrapolated."""
        return self._horizon - self._lag.value

    def clear(self) -> None:
        """Forget every point."""
        self._points.clear()
        self._latencies.clear()
        self._floor = math.inf
        self._curve = None
        self._previous = None
        self._horizon = 0.0
        self._delay = 0.0
        self._lag.reset()
        self._latest = None

    def add(self, point: Vector3, time: Optional[float], max_speed: float,
            arrival: Optional[float] = None) -> bool:
        """
        Take ``point`` at ``time`` (s; None: not part of any stream).

        :param arrival: None if ``time`` is when the point arrived; else ``time`` is its stamp
            (when the pointer was there) and ``arrival`` when it arrived (s).
        :returns: True if it continues the stream, False if it starts a new one (a jump).
        """
        latest = self._latest
        stamped = arrival is not None
        exact = True
        if not stamped and time is not None and self._stamped and self._latencies:
            # An unstamped point in a stamped stream: on the stamps' base, by the latency.
            arrival, time, exact = time, time - self._median_latency(), False
            if latest is not None and time < latest[0]:
                # Placed before the latest point: it adds nothing to the fit, but it is the
                # newest point sent, where the target rests if the stream stops here.
                self._latest = (latest[0], point)
                return True
        jumped = stamped and (not self._stamped or self._latency_jumps(arrival - time))
        if (latest is not None and time is not None and (arrival is not None) == self._stamped
                and not jumped and 0.0 <= time - latest[0] < SAME_TIME):
            # No time after the latest point (a burst in one tick): the newest point sent
            # replaces it, where the target rests if the stream stops; the fit, whose times
            # would be degenerate, stays.
            self._latest = (latest[0], point)
            return True
        if jumped:
            self._latencies.clear()
            self._floor = math.inf
        continues = False
        if time is not None and latest is not None and (arrival is not None) == self._stamped:
            interval = time - latest[0]
            if 0.0 < interval <= STREAM_GAP:
                step = math.dist(point, latest[1])
                continues = step <= max_speed * interval and not jumped
        previous = self._curve if continues and self._stamped else None
        if not continues:
            self._points.clear()
        if time is None:
            # A jump: a new stream, its latencies (the same path's) kept.
            self._latest = self._curve = self._previous = None
            self._horizon = 0.0
            return False
        self._points.append((time, point, exact))
        if stamped:
            self._latencies.append(arrival - time)
            self._floor = min(self._floor, arrival - time)
        self._latest = (time, point)
        self._stamped = arrival is not None
        self._arrival = arrival if self._stamped else time
        self._curve, interval, longest = self._fit()
        if self._stamped:
            # The floor of the latencies since they started; one below zero is a node behind
            # its clock (dropped ticks), not a path faster than the stamps.
            self._delay = max(0.0, self._floor)
            spread = max(self._latencies) - self._delay
            self._horizon = longest + spread
            # What the horizon holds past one mean interval: the latencies' spread and the
            # stream's jitter of intervals.
            need = spread + jitter([t for t, _, exact in self._points if exact])
            self._lag.aim(arrival, delay=self._delay, need=need, continues=continues)
        else:
            self._delay = 0.0
            self._horizon = EXTRAPOLATION_INTERVALS * interval
            self._lag.reset()
        self._previous = previous if self._curve is not None and BLEND_INTERVALS else None
        self._interval = interval
        return continues

    def shift(self, seconds: float) -> None:
        """
        Move every time the stream holds by ``seconds``: its points, fits, latest arrival and lag.

        The node's clock and the core's time moved apart (ticks were dropped, the node was
        paused): a stamp mapped before now maps ``seconds`` later or earlier, and so do the
        stream's times; its latencies stay.
        """
        self._points = deque(((t + seconds, p, exact) for t, p, exact in self._points),
                             maxlen=STAMPED_SAMPLES)
        if self._latest is not None:
            self._latest = (self._latest[0] + seconds, self._latest[1])
        self._arrival += seconds
        self._lag.shift(seconds)
        if self._curve is not None:
            self._curve = (self._curve[0] + seconds, *self._curve[1:])
        if self._previous is not None:
            self._previous = (self._previous[0] + seconds, *self._previous[1:])

    def _median_latency(self) -> float:
        latencies = sorted(self._latencies)
        return latencies[len(latencies) // 2]

    def _latency_jumps(self, latency: float) -> bool:
        latencies = self._latencies
        return bool(latencies) and not (
            min(latencies) - LATENCY_JUMP <= latency <= max(latencies) + LATENCY_JUMP)

    def _fit(self) -> Tuple[Optional[Curve], float, float]:
        """
        Return the stream's polynomial, its mean interval and its longest interval (s).

        Least squares in time relative to the anchoring point, the latest exact one (so the
        linear coefficient is the velocity there): for arrival times a line through two or
        three of the last ``STREAM_SAMPLES`` points, a parabola through more; for stamps a
        polynomial of degree ``count - 2`` (at least 1, at most ``STAMPED_DEGREE``) through the
        ``count`` points of the last ``STAMPED_WINDOW``.
        """
        points = list(self._points)
        t_last = points[-1][0]
        if self._stamped:
            points = [p for p in points if t_last - p[0] <= STAMPED_WINDOW]
            degree = min(STAMPED_DEGREE, max(1, len(points) - 2))
        else:
            points = points[-STREAM_SAMPLES:]
            degree = 2 if len(points) >= QUADRATIC_SAMPLES else 1
        count = len(points)
        if count < 2:
            return None, 0.0, 0.0
        # The latest exact point anchors the fit (the latest, if the window holds none).
        t_anchor, anchor, _ = next((p for p in reversed(points) if p[2]), points[-1])
        times = np.array([t - t_anchor for t, _, _ in points])
        # Offsets from the anchoring point: a still stream fits to exactly zero, and far
        # coordinates lose no digits. The extrapolation starts from that point itself.
        values = np.array([[p[i] - anchor[i] for i in range(3)] for _, p, _ in points])
        if self._stamped:
            # A point put on the stamps' base by its arrival shapes the fit less.
            weights = np.sqrt([1.0 if exact else UNSTAMPED_WEIGHT for _, _, exact in points])
            solution = cross_validated(times, values, weights, degree)
        else:
            design = np.vander(times, degree + 1, increasing=True)
            solution = np.linalg.lstsq(design, values, rcond=None)[0]
        coefficients = tuple(tuple(float(c) for c in row) for row in solution[1:])
        if not coefficients:
            coefficients = (ZERO,)
        mean_interval = float((times[-1] - times[0]) / (count - 1))
        longest_interval = float(np.diff(times).max())
        return polynomial(t_anchor, anchor, coefficients), mean_interval, longest_interval

    def predict(self, time: float) -> Tuple[Vector3, Vector3]:
        """
        Return where the target is at core time ``time`` and its velocity.

        The stream is presented at ``time - delay`` (a late stream's lag moving it): the fit
        there, extrapolated at most ``horizon`` past the latest point, then eased back to it
        over as long.

        A stamped stream goes over from its previous fit to the new one in the
        ``BLEND_INTERVALS`` after a point arrived, with the smoothstep weight w = 3 s^2 - 2 s^3
        of the fraction s of that time: position and velocity stay continuous where switching
        fits would jump (projective velocity blending, as in C. Murphy, "Believable Dead
        Reckoning for Networked Games", Game Engine Gems 2).
        """
        curve, (t_latest, latest) = self._curve, self._latest
        if curve is None:
            return latest, ZERO
        lag = self._lag.at(time)
        presented = time - self._delay - lag
        past = presented - t_latest
        # At least half an interval: a lag aimed at a long interval held before the window.
        horizon = max(self._horizon - lag, 0.5 * self._interval)
        if past > horizon:
            if past >= 2.0 * horizon or horizon <= 0.0:
                # The stream stopped: the target is where it was last sent.
                return latest, ZERO
            # No point within the horizon: ease back from the extrapolation's end.
            (ex, ey, ez), _ = evaluate(curve, t_latest + horizon)
            ox, oy, oz = ex - latest[0], ey - latest[1], ez - latest[2]
            weight, rate = _smoothstep((past - horizon) / horizon)
            keep, rate = 1.0 - weight, -rate / horizon
            return ((latest[0] + ox * keep, latest[1] + oy * keep, latest[2] + oz * keep),
                    (ox * rate, oy * rate, oz * rate))
        position, velocity = around(curve, presented)
        previous = self._previous
        if previous is None:
            return position, velocity
        blend_length = BLEND_INTERVALS * self._interval
        fraction = (time - self._arrival) / blend_length
        if fraction >= 1.0:
            self._previous = None
            return position, velocity
        weight, rate = _smoothstep(max(fraction, 0.0))
        rate /= blend_length
        (ox, oy, oz), (ux, uy, uz) = around(previous, presented)
        (nx, ny, nz), (vx, vy, vz) = position, velocity
        return ((ox + (nx - ox) * weight, oy + (ny - oy) * weight, oz + (nz - oz) * weight),
                (ux + (vx - ux) * weight + (nx - ox) * rate,
                 uy + (vy - uy) * weight + (ny - oy) * rate,
                 uz + (vz - uz) * weight + (nz - oz) * rate))

    def has_points(self) -> bool:
        """Return True while a timed point is held (predict needs one)."""
        return self._latest is not None
