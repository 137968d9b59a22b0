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
The node's target input: what it takes, how a stamp times it, when it times out.

A target is taken when ``TargetGate`` takes it (frame, finite, workspace); it comes as a point
(``target``, PointStamped) or as a pose (``target_pose``, PoseStamped: its position, as a haptic
device's driver publishes its handle; the orientation is not used), the two alike. ``TargetTiming``
times it by its header stamp where that is usable and the node has ticked (mapped onto the
core's time through the latest tick of the ``TickRecord``), else by its arrival. A grab
(``grab_input``) passes the same gate and makes its point the target, untimed (``hold``).

A target the gate takes is taken at once when it is the first since the latest tick; the
ones after it wait for the next tick, which takes the newest of them (``OnePerTick``, ``tick``):
a flood of targets costs the node one stream fit a tick, not one a target. A grab, a release,
a reset or a new configuration takes the target that waits first, in the order they came.

A pose on ``target_pose`` is a device's: in ``device_frame_id`` (empty: ``frame_id``), mapped
into ``frame_id`` (``device_scale``, ``device_pose``) before the gate's finite and workspace
checks. Whether the device is heard or silent, and the poses it lost, are its ``DeviceWatch``'s
to say (``device_watch``): it is told of every pose and of every pose taken.

A user target older than ``target_timeout`` is let go at the first tick after (``expire``).
Every refusal goes to the node's ``RefusalLog``: a throttled warning, counted.
"""

import math
from typing import Callable, NamedTuple, Optional

from geometry_msgs.msg import PointStamped, PoseStamped

from .device_watch import DeviceWatch
from .parameters import NodeConfig
from .tick_record import TickRecord
from ..inputs.input_timeouts import input_age, target_release_text, timed_out
from ..inputs.one_per_tick import OnePerTick
from ..inputs.target_gate import TargetGate
from ..inputs.target_stamps import TargetTiming
from ..inputs.throttle import RefusalLog
from ..physics import MouseSimulation
from ..physics.algebra import Vector3
from ..physics.target_stream import STREAM_GAP
from ..wire.messages import point_from_message, point_from_pose, stamp_nanoseconds


class Arrival(NamedTuple):
    """A target the gate took: its point, its header stamp and the node's time it came at (ns)."""

    point: Vector3
    stamp_ns: int
    now_ns: int


class TargetInput:
    """
    The ``target`` and ``target_pose`` callbacks, the user target's age, ``~/release``'s effect.

    :param simulation: the body whose target is set.
    :param config: the node's configuration (``configure`` replaces it).
    :param record: the ticks' record: the latest stamp, tick length and count.
    :param now_ns: the node's time (ns).
    :param refuse: counts and warns about a refused target.
    :param log: logs a line at INFO.
    :param device: the device on ``target_pose``: told of each pose that came and was taken
        (``configure`` configures it too).
    """

    def __init__(self, *, simulation: MouseSimulation, config: NodeConfig, record: TickRecord,
                 now_ns: Callable[[], int], refuse: RefusalLog, log: Callable[[str], None],
                 device: DeviceWatch) -> None:
        """Hold the initial anchor when configured to; no user target yet."""
        self._simulation = simulation
        self._record = record
        self._now_ns = now_ns
        self._refuse = refuse
        self._log = log
        self.device = device
        self._timing = TargetTiming(STREAM_GAP)
        # Targets taken: the first after a tick at once, the newest of the rest at the next.
        self._arrivals: OnePerTick[Arrival] = OnePerTick()
        # Whether the target is one a user gave (not the held initial anchor), and when (ns).
        self.user_target = False
        self.last_target_ns = 0
        self.configure(config)
        self.hold_initial_anchor()

    def configure(self, config: NodeConfig) -> None:
        """Take a new configuration: the gate, the device's frame and map, the timeout."""
        self.flush()
        self._config = config
        gate = getattr(self, '_gate', None)
        if gate is None or (gate.frame_id, gate.workspace_radius) != (
                config.frame_id, config.workspace_radius):
            self._gate = TargetGate(config.frame_id, config.workspace_radius)
        # The device's frame (and finite coordinates) first; the workspace once mapped.
        self._device_gate = TargetGate(config.device.pose_frame(config.frame_id), math.inf,
                                       config.frame_id)
        self._device_config = config.device
        self._timeout = config.target_timeout
        self.device.configure(config)

    @property
    def gate(self) -> TargetGate:
        """Return the gate targets and grabs pass."""
        return self._gate

    def hold(self, point: Vector3) -> None:
        """
        Make ``point`` the user target, untimed, from now: a grab's.

        A grab starts a new stream of targets; nothing moves, the target is where the anchor is.
        The targets that came before it are to be taken first (``flush``).
        """
        self._simulation.target = point
        self.user_target = True
        self.last_target_ns = self._now_ns()

    def hold_initial_anchor(self) -> None:
        """Hold the anchor where it starts, or free the body, as configured; no user target."""
        self.flush()
        config = self._config
        self.user_target = False
        self._simulation.target = (config.initial_anchor() if config.hold_initial_anchor
                                   else None)

    def release(self) -> bool:
        """Let go of the target: the body flies free; return whether there was one."""
        self.flush()
        had_target = self._simulation.target is not None
        self._simulation.target = None
        self.user_target = False
        return had_target

    def expire(self, now_ns: int) -> None:
        """Let go of a user target older than ``target_timeout`` at ``now_ns``."""
        if self.user_target and timed_out(self.last_target_ns, now_ns, self._timeout):
            self.release()
            self._log(target_release_text(self._timeout))

    def age(self, now_ns: int) -> Optional[float]:
        """Return how old the user target is (s), or None without one."""
        return input_age(self.last_target_ns, now_ns) if self.user_target else None

    def restart_age(self, now_ns: int) -> None:
        """Count the user target's age from ``now_ns`` (the node's time changed base)."""
        self.flush()
        if self.user_target:
            self.last_target_ns = now_ns

    def on_target(self, message: PointStamped) -> None:
        """Take a target: timed by its stamp where usable, else by its arrival."""
        self._offer(message, point_from_message(message))

    def on_target_pose(self, message: PoseStamped) -> None:
        """Take a device pose's position, mapped into ``frame_id``, as a target."""
        now = self._now_ns()
        stamp = stamp_nanoseconds(message.header.stamp)
        self.device.came(stamp, now)
        point = point_from_pose(message)
        refusal = self._device_gate.refusal(message.header.frame_id, point)
        if refusal is not None:
            self._refuse(refusal, f'ignoring target pose {refusal.reason}')
            return
        if self._offer(message, self._device_config.mapping.to_world(point), ''):
            self.device.taken(stamp, now)

    def tick(self) -> None:
        """Take the newest target that waited for this tick, if one did (``OnePerTick``)."""
        arrival = self._arrivals.tick()
        if arrival is not None:
            self._take(arrival)

    @property
    def held_over(self) -> int:
        """Return how many targets a newer one replaced before a tick took them."""
        return self._arrivals.held_over

    def _offer(self, message, point: Vector3, frame: Optional[str] = None) -> bool:
        """
        Offer ``point``, the target of ``message``: refused, taken, or held for the tick.

        :param frame: the frame it is in, when not the message's (a mapped device pose's).
        :returns: whether it was taken or held (not refused).
        """
        refusal = self._gate.refusal(message.header.frame_id if frame is None else frame, point)
        if refusal is not None:
            self._refuse(refusal, f'ignoring target {refusal.reason}')
            return False
        arrival = self._arrivals.offer(
            Arrival(point, stamp_nanoseconds(message.header.stamp), self._now_ns()))
        if arrival is not None:
            self._take(arrival)
        return True

    def flush(self) -> None:
        """Take the target that waits for the tick now, if one does: it came first."""
        arrival = self._arrivals.flush()
        if arrival is not None:
            self._take(arrival)

    def _take(self, arrival: 'Arrival') -> None:
        """Take a target as it came: timed by its stamp where usable, else by its arrival."""
        record = self._record
        self._timing.take(self._simulation, arrival.point, stamp_ns=arrival.stamp_ns,
                          now_ns=arrival.now_ns, tick_stamp_ns=record.stamp_ns,
                          tick_s=record.dt, ticked=record.ticks_run > 0)
        self.user_target = True
        self.last_target_ns = arrival.now_ns
