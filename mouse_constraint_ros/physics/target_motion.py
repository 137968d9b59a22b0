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
How the mouse target moves: what the joint is handed, and the bounded-slew guide it pulls to.

A stream of targets is fitted, timed by its latency and presented by ``TargetStream``
(``target_stream``). ``Guide`` is the point the joint actually pulls the anchor to: it follows
the stream's presented target with its speed bounded by ``max_speed`` and its acceleration by
``max_acceleration`` (time-optimal approach, exact in discrete time: it stops on the target
without overshoot or chatter). A click then moves the hand like a hand, not a teleport: the
body is carried over at a bounded speed and acceleration, whatever the joint's stiffness. Its
velocity is known exactly, so a joint that feeds the target's velocity forward follows it
without lag. ``pull_point`` says where the joint pulls in a substep.

Plain float arithmetic, deterministic for the same inputs.
"""

from dataclasses import dataclass
import math
from typing import Optional, Tuple

from .algebra import multiply, rotation_matrix, Vector3
from .target_stream import TargetStream
from .validation import scalar

# The guide slows down up to this many times faster than it speeds up: a stream that stops (a
# drag let go of at speed) stops the hand within 1 / (2 BRAKING) of the distance it started in,
# while a click is still carried over on the smooth time-optimal profile of max_acceleration.
BRAKING = 2.0

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


def _bounded_change(velocity: Vector3, change: Vector3, size: float,
                    limit: float) -> Vector3:
    """
    Return ``change`` (of norm ``size`` > ``limit``) within the guide's bounds.

    The part against ``velocity`` (slowing down) is bounded by ``BRAKING`` times ``limit``, the
    rest (speeding up, turning) by ``limit``.
    """
    ux, uy, uz = velocity
    speed = math.sqrt(ux * ux + uy * uy + uz * uz)
    dx, dy, dz = change
    along = (dx * ux + dy * uy + dz * uz) / speed if speed > 0.0 else 0.0
    if along >= 0.0:
        return (dx * limit / size, dy * limit / size, dz * limit / size)
    ax, ay, az = ux / speed * along, uy / speed * along, uz / speed * along
    px, py, pz = dx - ax, dy - ay, dz - az
    across = math.sqrt(px * px + py * py + pz * pz)
    if across > limit:
        px, py, pz = px * limit / across, py * limit / across, pz * limit / across
    if -along > BRAKING * limit:
        ax, ay, az = (c * BRAKING * limit / -along for c in (ax, ay, az))
    return (ax + px, ay + py, az + pz)


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
        max_acceleration h, and slowing by up to ``BRAKING`` times that (``_bounded_change``);
        then its position moves by h times the new velocity.
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
            dx, dy, dz = _bounded_change((ux, uy, uz), (dx, dy, dz), change, limit)
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
