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
How the mouse target moves: its velocity estimated from a stream, and a bounded-slew guide.

A mouse sends positions, not motions: a drag is a stream of points some 20 ms apart, a click a
single point that may land anywhere. Two pieces turn that into what the joint follows:

- ``TargetStream`` fits the stream's last points as a polynomial in time (the core's time,
  seconds of simulated time) and extrapolates it. How closely depends on what the times are:

  - *Arrival times* (the time a point reached the node, late by a varying delay): a
    least-squares fit over the last ``STREAM_SAMPLES`` points (a parabola from
    ``QUADRATIC_SAMPLES`` on), which averages the jitter of the arrival times instead of
    dividing by one noisy interval.
  - *Stamps* (the time the pointer was at the point, with the arrival time beside it): the
    times are exact, so the fit follows the curve instead of averaging: a polynomial of degree
    up to ``STAMPED_DEGREE`` over the points of the last ``STAMPED_WINDOW`` seconds (at most
    ``STAMPED_SAMPLES``), two points more than its coefficients. A parabola over 0.4 s of a
    circle turning 4 rad/s takes it for a flatter curve and extrapolates it outwards; a
    quartic does not (bench/stream_timing.py, docs/dragging.md).

  A point is part of the stream only if it comes within ``STREAM_GAP`` of the previous one,
  after it, timed the same way (stamps or arrivals), and implies a speed no greater than the
  guide may move (``TargetMotion.max_speed``); any other point (a click, a jump, a point after
  a pause, a point without a time) starts a new stream of velocity zero, so a jump is never
  mistaken for a huge velocity. The target is extrapolated along the fit until
  ``EXTRAPOLATION_INTERVALS`` of the stream's mean interval after the latest point arrived
  (``STAMPED_EXTRAPOLATION_INTERVALS`` for stamps, extrapolated from the stamp, over the
  point's delay too); after that the target is the last point again, at rest (a drag that
  stops ends where it was last sent).
- ``Guide`` is the point the joint actually pulls the anchor to: it follows the extrapolated
  target with its speed bounded by ``max_speed`` and its acceleration by ``max_acceleration``
  (time-optimal approach, exact in discrete time: it stops on the target without overshoot or
  chatter). A click then moves the hand like a hand, not a teleport: the body is carried over
  at a bounded speed and acceleration, whatever the joint's stiffness. Its velocity is known
  exactly, so a joint that feeds the target's velocity forward follows it without lag.

Both are plain float arithmetic (one small numpy least-squares solve per point), deterministic
for the same inputs.
"""

from collections import deque
from dataclasses import dataclass
import math
from typing import Deque, Optional, Tuple

import numpy as np

from .algebra import multiply, rotation_matrix, Vector3
from .polynomial import Curve, evaluate, polynomial
from .validation import scalar

# Points further apart in time than this (s) are not one stream: a pause ends a drag.
STREAM_GAP = 0.25
# Arrival-timed streams: the velocity is the least-squares slope over at most this many of the
# stream's last points.
STREAM_SAMPLES = 8
# From this many points on, the fit is a parabola: a curved drag is extrapolated along its curve
# (bench/mouse_feel.py: a circle at 1 m/s, 50 Hz, soft 7.5 Hz joint: 5 mm RMS error, against
# 19 mm with a line over as many points); eight points keep the parabola's slope as steady under
# arrival jitter as a two-point difference is not (3 times less error, test_mouse_feel).
QUADRATIC_SAMPLES = 4
# Stamped streams: a polynomial of at most this degree over the points of the last
# STAMPED_WINDOW seconds, at most STAMPED_SAMPLES of them (a browser's 20 Hz drag round a 1 m/s
# circle of radius 0.25 m: anchor 0.9 mm and speed 1.1 % RMS off, against 23 mm and 17 % with a
# parabola on the same stamps; ``python -m bench.stream_timing --estimators``). At most 4:
# ``polynomial`` lays it out as a quartic.
STAMPED_DEGREE = 4
STAMPED_WINDOW = 0.4
STAMPED_SAMPLES = 32
# Extrapolation runs on for at most this many of the stream's mean intervals after a point
# arrived; a stamped stream's arrivals jitter by the spread of their delays as well.
EXTRAPOLATION_INTERVALS = 1.5
STAMPED_EXTRAPOLATION_INTERVALS = 2.0
# A stamped stream's extrapolation goes over from the previous fit to the new one in this many
# mean intervals after a point arrived (``TargetStream.predict``).
BLEND_INTERVALS = 1.0
ZERO: Vector3 = (0.0, 0.0, 0.0)


@dataclass(frozen=True)
class TargetMotion:
    """
    How the target handed to the joint may move (defaults: as given, at once, no velocity).

    :param max_speed: the guide's speed bound (m/s); +inf with ``max_acceleration`` +inf for
        no guide (the joint pulls at the target itself). Also the fastest a stream may move.
    :param max_acceleration: the guide's acceleration bound (m/s^2); +inf for none.
    :param feed_forward: estimate the target's velocity from the stream (and extrapolate it
        between points) and let the joint follow it: J V - v_target in the constraint.
    """

    max_speed: float = math.inf
    max_acceleration: float = math.inf
    feed_forward: bool = False

    def __post_init__(self) -> None:
        """Validate every field; raise ValueError naming the first invalid one."""
        object.__setattr__(self, 'max_speed', scalar('max_target_speed', self.max_speed,
                                                     above=0.0, allow_inf=True))
        object.__setattr__(self, 'max_acceleration', scalar(
            'max_target_acceleration', self.max_acceleration, above=0.0, allow_inf=True))
        if not isinstance(self.feed_forward, bool):
            raise ValueError(f'feed_forward must be true or false, got {self.feed_forward!r}')

    @property
    def guided(self) -> bool:
        """Return True if the joint follows a bounded guide rather than the target itself."""
        return math.isfinite(self.max_speed) or math.isfinite(self.max_acceleration)


class TargetStream:
    """The last points of the target with their times; the fit and extrapolation of them."""

    def __init__(self) -> None:
        """Start empty."""
        self._points: Deque[Tuple[float, Vector3]] = deque(maxlen=STAMPED_SAMPLES)
        # The fit about the latest point (``evaluate``); None for none (no point, or one).
        self._curve: Optional[Curve] = None
        self._horizon = 0.0
        # (time, point) of the latest point; its arrival time; whether times are stamps.
        self._latest: Optional[Tuple[float, Vector3]] = None
        self._arrival = 0.0
        self._stamped = False
        # A stamped stream's previous fit, blended into the new one from the new point's
        # arrival over ``_blend_length`` (s); None when not blending.
        self._previous: Optional[Curve] = None
        self._blend_length = 0.0

    @property
    def velocity(self) -> Vector3:
        """Return the estimated velocity of the stream at its latest point (m/s), zero alone."""
        return ZERO if self._curve is None else self._curve[2][0]

    def clear(self) -> None:
        """Forget every point."""
        self._points.clear()
        self._curve = self._previous = None
        self._horizon = 0.0
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
        continues = False
        if time is not None and latest is not None and stamped == self._stamped:
            interval = time - latest[0]
            if 0.0 < interval <= STREAM_GAP:
                step = math.dist(point, latest[1])
                continues = step <= max_speed * interval
        previous = self._curve if continues and stamped else None
        if not continues:
            self._points.clear()
        if time is None:
            self._latest = self._curve = self._previous = None
            self._horizon = 0.0
            return False
        self._points.append((time, point))
        self._latest = (time, point)
        self._arrival = arrival if stamped else time
        self._stamped = stamped
        self._curve, interval = self._fit()
        self._horizon = interval * (STAMPED_EXTRAPOLATION_INTERVALS if stamped
                                    else EXTRAPOLATION_INTERVALS)
        self._previous = previous if self._curve is not None and BLEND_INTERVALS else None
        self._blend_length = BLEND_INTERVALS * interval
        return continues

    def _fit(self) -> Tuple[Optional[Curve], float]:
        """
        Return the stream's polynomial about its latest point, and its mean interval (s).

        Least squares in time relative to the latest point (so the linear coefficient is the
        velocity there): for arrival times a line through two or three of the last
        ``STREAM_SAMPLES`` points, a parabola through more; for stamps a polynomial of degree
        ``count - 2`` (at least 1, at most ``STAMPED_DEGREE``) through the ``count`` points of
        the last ``STAMPED_WINDOW``.
        """
        points = list(self._points)
        t_last, latest = points[-1]
        if self._stamped:
            points = [p for p in points if t_last - p[0] <= STAMPED_WINDOW]
            degree = min(STAMPED_DEGREE, max(1, len(points) - 2))
        else:
            points = points[-STREAM_SAMPLES:]
            degree = 2 if len(points) >= QUADRATIC_SAMPLES else 1
        count = len(points)
        if count < 2:
            return None, 0.0
        times = np.array([t - t_last for t, _ in points])
        # Offsets from the latest point: a still stream fits to exactly zero, and far
        # coordinates lose no digits. The extrapolation starts from the latest point itself.
        values = np.array([[p[i] - latest[i] for i in range(3)] for _, p in points])
        design = np.vander(times, degree + 1, increasing=True)
        solution = np.linalg.lstsq(design, values, rcond=None)[0]
        coefficients = tuple(tuple(float(c) for c in row) for row in solution[1:])
        return polynomial(t_last, latest, coefficients), float(-times[0] / (count - 1))

    def predict(self, time: float) -> Tuple[Vector3, Vector3]:
        """
        Return where the target is at ``time`` and its velocity, extrapolated (s).

        A stamped stream goes over from its previous fit to the new one in the
        ``BLEND_INTERVALS`` after a point arrived, with the smoothstep weight
        w = 3 s^2 - 2 s^3 of the fraction s of that time: position and velocity stay
        continuous where switching fits would jump (projective velocity blending, as in
        C. Murphy, "Believable Dead Reckoning for Networked Games", Game Engine Gems 2).
        """
        curve = self._curve
        if curve is None or time - self._arrival > self._horizon:
            # The stream stopped (or is a lone point): the target is where it was last sent.
            return self._latest[1], ZERO
        position, velocity = evaluate(curve, time)
        previous = self._previous
        if previous is None:
            return position, velocity
        fraction = (time - self._arrival) / self._blend_length
        if fraction >= 1.0:
            self._previous = None
            return position, velocity
        fraction = max(fraction, 0.0)
        weight = fraction * fraction * (3.0 - 2.0 * fraction)
        rate = 6.0 * fraction * (1.0 - fraction) / self._blend_length
        (ox, oy, oz), (ux, uy, uz) = evaluate(previous, time)
        (nx, ny, nz), (vx, vy, vz) = position, velocity
        return ((ox + (nx - ox) * weight, oy + (ny - oy) * weight, oz + (nz - oz) * weight),
                (ux + (vx - ux) * weight + (nx - ox) * rate,
                 uy + (vy - uy) * weight + (ny - oy) * rate,
                 uz + (vz - uz) * weight + (nz - oz) * rate))

    def has_points(self) -> bool:
        """Return True while a timed point is held (predict needs one)."""
        return self._latest is not None


class Guide:
    """A point that follows a goal with bounded speed and acceleration (module docstring)."""

    def __init__(self, position: Vector3, velocity: Vector3 = ZERO) -> None:
        """Start at ``position`` moving at ``velocity``."""
        self.position = position
        self.velocity = velocity

    def advance(self, goal: Vector3, goal_velocity: Vector3, h: float, max_speed: float,
                max_acceleration: float) -> None:
        """
        Move over one substep ``h`` toward ``goal``, which moves at ``goal_velocity``.

        The closing speed is the largest from which the guide can still stop on the goal in
        whole substeps of at most ``max_acceleration h`` change: a distance e allows
        s = a h (sqrt(1/4 + 2 e / (a h^2)) - 1/2) (the sum of s, s - a h, ... times h is e),
        and never more than e / h, so the last substep lands exactly. The guide's velocity
        goes toward goal_velocity + s (toward the goal), within max_speed, changing by at most
        max_acceleration h; then its position moves by h times the new velocity.
        """
        gx, gy, gz = self.position
        ex, ey, ez = goal[0] - gx, goal[1] - gy, goal[2] - gz
        distance = math.sqrt(ex * ex + ey * ey + ez * ez)
        wx, wy, wz = goal_velocity
        if distance > 0.0:
            closing = min(max_speed, distance / h)
            if math.isfinite(max_acceleration):
                ah = max_acceleration * h
                closing = min(closing, ah * (math.sqrt(0.25 + 2.0 * distance / (ah * h)) - 0.5))
            wx += ex / distance * closing
            wy += ey / distance * closing
            wz += ez / distance * closing
        speed = math.sqrt(wx * wx + wy * wy + wz * wz)
        if speed > max_speed:
            wx, wy, wz = (wx * max_speed / speed, wy * max_speed / speed, wz * max_speed / speed)
        ux, uy, uz = self.velocity
        dx, dy, dz = wx - ux, wy - uy, wz - uz
        change = math.sqrt(dx * dx + dy * dy + dz * dz)
        limit = max_acceleration * h
        if change > limit:
            dx, dy, dz = (dx * limit / change, dy * limit / change, dz * limit / change)
        u = (ux + dx, uy + dy, uz + dz)
        self.velocity = u
        self.position = (gx + h * u[0], gy + h * u[1], gz + h * u[2])


def pull_point(target: Optional[Vector3], motion: TargetMotion, stream: TargetStream,
               guide: Optional[Guide], anchor: Vector3, body: Tuple, time: float,
               h: float) -> Tuple[Optional[Tuple[Vector3, Optional[Vector3]]], Optional[Guide]]:
    """
    Return the point the joint pulls to over the substep from ``time`` and its velocity; the guide.

    The velocity is None unless ``motion`` feeds it forward. With a guide the point is the
    guide's position at ``time`` and the velocity the one that carries it over the substep,
    so that a rigid joint's error still decays as (1 - delta) per substep. A guide is started
    where the anchor is when there is none (None: no target, or no guide kept).

    :param body: the body's position (x, y, z), orientation, v and w.
    """
    if target is None:
        return None, guide
    (px, py, pz), q, v, w = body
    if motion.feed_forward and stream.has_points():
        goal, goal_velocity = stream.predict(time)
    else:
        goal, goal_velocity = target, (0.0, 0.0, 0.0)
    if not motion.guided:
        return (goal, (goal_velocity if motion.feed_forward else None)), None
    if guide is None:
        # Picked up where the anchor is, moving as it moves (within the speed bound).
        rx, ry, rz = multiply(anchor, rotation_matrix(q))
        ux, uy, uz = (v[0] + w[1] * rz - w[2] * ry, v[1] + w[2] * rx - w[0] * rz,
                      v[2] + w[0] * ry - w[1] * rx)
        speed = math.sqrt(ux * ux + uy * uy + uz * uz)
        if speed > motion.max_speed:
            ux, uy, uz = (c * motion.max_speed / speed for c in (ux, uy, uz))
        guide = Guide((px + rx, py + ry, pz + rz), (ux, uy, uz))
    position = guide.position
    guide.advance(goal, goal_velocity, h, motion.max_speed, motion.max_acceleration)
    return (position, (guide.velocity if motion.feed_forward else None)), guide
