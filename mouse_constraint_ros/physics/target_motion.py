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

- ``TargetStream`` estimates the target's velocity from the points and their arrival times (in
  the core's time, seconds of simulated time). The estimate is a least-squares fit over the
  last ``STREAM_SAMPLES`` points (a parabola from ``QUADRATIC_SAMPLES`` on), which averages the
  jitter of irregular arrival times instead of dividing by one noisy interval. A point is part
  of the stream only if it arrived within ``STREAM_GAP`` of the previous one and implies a
  speed no greater than the guide may move (``TargetMotion.max_speed``); any other point (a
  click, a jump, a point after a pause, a point without a time) starts a new stream of
  velocity zero, so a jump is never mistaken for a huge velocity. Between points the target is
  extrapolated along the fit for at most 1.5 of the stream's mean interval; after that the
  target is the last point again, at rest (a drag that stops ends where it was last sent).
- ``Guide`` is the point the joint actually pulls the anchor to: it follows the extrapolated
  target with its speed bounded by ``max_speed`` and its acceleration by ``max_acceleration``
  (time-optimal approach, exact in discrete time: it stops on the target without overshoot or
  chatter). A click then moves the hand like a hand, not a teleport: the body is carried over
  at a bounded speed and acceleration, whatever the joint's stiffness. Its velocity is known
  exactly, so a joint that feeds the target's velocity forward follows it without lag.

Both are plain float arithmetic, deterministic for the same inputs.
"""

from collections import deque
from dataclasses import dataclass
import math
from typing import Deque, Optional, Tuple

import numpy as np

from .algebra import Vector3
from .validation import scalar

# Points further apart in time than this (s) are not one stream: a pause ends a drag.
STREAM_GAP = 0.25
# The velocity is the least-squares slope over at most this many of the stream's last points.
STREAM_SAMPLES = 8
# From this many points on, the fit is a parabola: a curved drag is extrapolated along its curve
# (bench/mouse_feel.py: a circle at 1 m/s, 50 Hz, soft 7.5 Hz joint: 5 mm RMS error, against
# 19 mm with a line over as many points); eight points keep the parabola's slope as steady under
# arrival jitter as a two-point difference is not (3 times less error, test_mouse_feel).
QUADRATIC_SAMPLES = 4
# Extrapolation runs on for at most this many of the stream's mean intervals after a point.
EXTRAPOLATION_INTERVALS = 1.5
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
    """The last points of the target with their times; its velocity and extrapolation."""

    def __init__(self) -> None:
        """Start empty."""
        self._points: Deque[Tuple[float, Vector3]] = deque(maxlen=STREAM_SAMPLES)
        self._velocity: Vector3 = ZERO
        self._acceleration: Vector3 = ZERO
        self._horizon = 0.0
        self._latest: Optional[Tuple[float, Vector3]] = None

    @property
    def velocity(self) -> Vector3:
        """Return the estimated velocity of the stream (m/s), zero for a lone point."""
        return self._velocity

    def clear(self) -> None:
        """Forget every point."""
        self._points.clear()
        self._velocity = ZERO
        self._acceleration = ZERO
        self._horizon = 0.0
        self._latest = None

    def add(self, point: Vector3, time: Optional[float], max_speed: float) -> bool:
        """
        Take ``point`` that arrived at ``time`` (s; None: not part of any stream).

        :returns: True if it continues the stream, False if it starts a new one (a jump).
        """
        latest = self._latest
        continues = False
        if time is not None and latest is not None:
            interval = time - latest[0]
            if 0.0 < interval <= STREAM_GAP:
                step = math.dist(point, latest[1])
                continues = step <= max_speed * interval
        if not continues:
            self._points.clear()
        if time is None:
            self._latest = None
            self._velocity = self._acceleration = ZERO
            self._horizon = 0.0
            return False
        self._points.append((time, point))
        self._latest = (time, point)
        self._velocity, self._acceleration, self._horizon = self._fit()
        return continues

    def _fit(self) -> Tuple[Vector3, Vector3, float]:
        """
        Return the stream's velocity and acceleration at its latest point, and the horizon.

        Least squares over the points held: a line through two or three, a parabola through
        more, both in time relative to the latest point (so the slope is the velocity there).
        """
        points = self._points
        count = len(points)
        if count < 2:
            return ZERO, ZERO, 0.0
        t_last = points[-1][0]
        times = np.array([t - t_last for t, _ in points])
        degree = 2 if count >= QUADRATIC_SAMPLES else 1
        design = np.vander(times, degree + 1, increasing=True)
        # Offsets from the latest point: a still stream fits to exactly zero, and far
        # coordinates lose no digits.
        latest = points[-1][1]
        values = np.array([[p[i] - latest[i] for i in range(3)] for _, p in points])
        coefficients = np.linalg.lstsq(design, values, rcond=None)[0]
        velocity = tuple(float(c) for c in coefficients[1])
        acceleration = (tuple(float(2.0 * c) for c in coefficients[2]) if degree == 2 else ZERO)
        interval = -times[0] / (count - 1)
        return velocity, acceleration, EXTRAPOLATION_INTERVALS * float(interval)

    def predict(self, time: float) -> Tuple[Vector3, Vector3]:
        """Return where the target is at ``time`` and its velocity, extrapolated (s)."""
        t0, p = self._latest
        ahead = max(time - t0, 0.0)
        if ahead > self._horizon:
            # The stream stopped: the target is where it was last sent.
            return p, ZERO
        v, acc = self._velocity, self._acceleration
        half = 0.5 * ahead * ahead
        return (tuple(p[i] + v[i] * ahead + acc[i] * half for i in range(3)),
                tuple(v[i] + acc[i] * ahead for i in range(3)))

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
