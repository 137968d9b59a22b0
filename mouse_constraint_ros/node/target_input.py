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
The node's target and grab input: what it takes, how a stamp times it, when it times out.

A target is taken when ``TargetGate`` takes it (frame, finite, workspace); it comes as a point
(``target``, PointStamped) or as a pose (``target_pose``, PoseStamped: its position, as a haptic
device's driver publishes its handle; the orientation is not used), the two alike. ``TargetTiming``
times it by its header stamp where that is usable and the node has ticked (mapped onto the
core's time through the latest tick of the ``TickRecord``), else by its arrival. A grab takes
the same gate, then ``grab`` says where on the body it lands; the node's own ``anchor``
parameter is set to that point (``set_anchor``, validated as any parameter change) and the
point becomes the target, untimed.

A target the gate takes is taken at once when it is the first since the latest tick; the
ones after it wait for the next tick, which takes the newest of them (``OnePerTick``, ``tick``):
a flood of targets costs the node one stream fit a tick, not one a target. A grab, a release,
a reset or a new configuration takes the target that waits first, in the order they came.

A pose on ``target_pose`` is a device's: in ``device_frame_id`` (empty: ``frame_id``), mapped
into ``frame_id`` (``device_scale``, ``device_pose``) before the gate's finite and workspace
checks. Once a pose came, the device is silent while no valid pose came for ``device_timeout``
(``device_silent``): the force it is sent is then zero, and the node logs a line when it
falls silent and when it comes back. When it clocks the ticks, the poses it sent that never
came are counted from the gaps in their stamps (``device_lost``, ``inputs.pose_gaps``).

A user target older than ``target_timeout`` is let go at the first tick after (``expire``).
Every refusal goes to the node's ``RefusalLog``: a throttled warning, counted.
"""

import math
from typing import Callable, NamedTuple, Optional

from geometry_msgs.msg import PointStamped, PoseStamped

from .parameters import NodeConfig
from .tick_record import TickRecord
from ..inputs.grab import Grab, grab
from ..inputs.input_timeouts import input_age, target_release_text, timed_out
from ..inputs.one_per_tick import OnePerTick
from ..inputs.pose_gaps import back_text, PoseGaps, silent_text
from ..inputs.target_gate import apart, Refusal, TargetGate
from ..inputs.target_stamps import TargetTiming
from ..inputs.throttle import RefusalLog
from ..physics import MouseSimulation
from ..physics.algebra import Vector3
from ..physics.target_stream import STREAM_GAP
from ..timing.device_clock import DeviceClock
from ..wire.messages import point_from_message, point_from_pose, stamp_nanoseconds


class Arrival(NamedTuple):
    """A target the gate took: its point, its header stamp and the node's time it came at (ns)."""

    point: Vector3
    stamp_ns: int
    now_ns: int


class TargetInput:
    """
    The ``target`` and ``grab`` callbacks, the user target's age, ``~/release``'s effect.

    :param simulation: the body whose target is set.
    :param config: the node's configuration (``configure`` replaces it).
    :param record: the ticks' record: the latest stamp, tick length and count.
    :param now_ns: the node's time (ns).
    :param set_anchor: sets the node's ``anchor`` parameter; returns None or why it could not.
    :param refuse: counts and warns about a refused target or grab.
    :param log: logs a line at INFO.
    :param device_pose: called with its stamp (ns) after each valid pose on ``target_pose`` is
        taken (the ticker's ``device_tick``: the tick it runs when the device clocks the ticks).
    :param device_clock: the ticker's device clock: while on, it says whether the device is
        silent.
    """

    def __init__(self, *, simulation: MouseSimulation, config: NodeConfig, record: TickRecord,
                 now_ns: Callable[[], int], set_anchor: Callable[[Vector3], Optional[str]],
                 refuse: RefusalLog, log: Callable[[str], None],
                 device_pose: Callable[[int], None] = lambda _stamp: None,
                 device_clock: Optional[DeviceClock] = None) -> None:
        """Hold the initial anchor when configured to; no user target yet."""
        self._simulation = simulation
        self._record = record
        self._now_ns = now_ns
        self._set_anchor = set_anchor
        self._refuse = refuse
        self._log = log
        self._device_pose = device_pose
        self._device_clock = device_clock
        self._timing = TargetTiming(STREAM_GAP)
        # Targets taken: the first after a tick at once, the newest of the rest at the next.
        self._arrivals: OnePerTick[Arrival] = OnePerTick()
        # Whether the target is one a user gave (not the held initial anchor), and when (ns).
        self.user_target = False
        self.last_target_ns = 0
        # Whether a pose came on target_pose, and when the last valid one came (ns).
        self.device_heard = False
        self.last_device_ns = 0
        # The device's poses lost (gaps in their stamps), and since when it is silent (ns).
        self._gaps = PoseGaps()
        self._silent_since: Optional[int] = None
        self.configure(config)
        self.hold_initial_anchor()

    def configure(self, config: NodeConfig) -> None:
        """Take a new configuration: the gate, the grab's box and margin, the timeout."""
        self._flush()
        self._config = config
        gate = getattr(self, '_gate', None)
        if gate is None or (gate.frame_id, gate.workspace_radius) != (
                config.frame_id, config.workspace_radius):
            self._gate = TargetGate(config.frame_id, config.workspace_radius)
        # The device's frame (and finite coordinates) first; the workspace once mapped.
        self._device_gate = TargetGate(config.device.pose_frame(config.frame_id), math.inf,
                                       config.frame_id)
        self._device = config.device
        self._timeout = config.target_timeout
        self._gaps.configure(on=config.device.tick_source == 'target_pose',
                             rate_hz=config.rate_hz, timeout=config.device.timeout)

    @property
    def gate(self) -> TargetGate:
        """Return the gate targets and grabs pass."""
        return self._gate

    def hold_initial_anchor(self) -> None:
        """Hold the anchor where it starts, or free the body, as configured; no user target."""
        self._flush()
        config = self._config
        self.user_target = False
        self._simulation.target = (config.initial_anchor() if config.hold_initial_anchor
                                   else None)

    def release(self) -> bool:
        """Let go of the target: the body flies free; return whether there was one."""
        self._flush()
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
        self._flush()
        if self.user_target:
            self.last_target_ns = now_ns

    def on_target(self, message: PointStamped) -> None:
        """Take a target: timed by its stamp where usable, else by its arrival."""
        self._offer(message, point_from_message(message))

    def on_target_pose(self, message: PoseStamped) -> None:
        """Take a device pose's position, mapped into ``frame_id``, as a target."""
        now = self._now_ns()
        if not self.device_heard:
            self.device_heard, self.last_device_ns = True, now
        stamp = stamp_nanoseconds(message.header.stamp)
        self._gaps.take(stamp)
        point = point_from_pose(message)
        refusal = self._device_gate.refusal(message.header.frame_id, point)
        if refusal is not None:
            self._refuse(refusal, f'ignoring target pose {refusal.reason}')
            return
        if self._offer(message, self._device.mapping.to_world(point), ''):
            self.last_device_ns = now
            self._device_pose(stamp)

    def device_age(self, now_ns: int) -> Optional[float]:
        """Return how long ago (s) the last valid pose came (or the first pose), None unheard."""
        return input_age(self.last_device_ns, now_ns) if self.device_heard else None

    @property
    def device_lost(self) -> Optional[int]:
        """Return the device's poses lost so far (``PoseGaps``), None unless it clocks ticks."""
        return self._gaps.lost if self._gaps.on else None

    def device_silent(self, now_ns: int) -> bool:
        """
        Return whether a device was heard and no valid pose came for ``device_timeout``.

        Once the device's poses clock the ticks, its silence is counted in the node's own ticks
        held back since its last pose (``DeviceClock.silent``): on a simulated clock the node's
        time stands still without ticks. Before (every pose refused), in the node's time. The
        node logs a line when the device falls silent, and one when it comes back.
        """
        clock = self._device_clock
        if clock is not None and clock.heard:
            silent = clock.silent
        else:
            silent = self.device_heard and timed_out(self.last_device_ns, now_ns,
                                                     self._device.timeout)
        if silent != (self._silent_since is not None):
            now = self._now_ns()
            if silent:
                self._silent_since = now
                self._log(silent_text(self._device.timeout))
            else:
                self._log(back_text(input_age(self._silent_since, now)))
                self._silent_since = None
        return silent

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

    def _flush(self) -> None:
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

    def on_grab(self, message: PointStamped) -> None:
        """Make a point on the body the anchor and the target; ignore (and say) any other."""
        point = point_from_message(message)
        refusal = self._gate.refusal(message.header.frame_id, point)
        if refusal is not None:
            self._refuse(refusal._replace(key='grab ' + refusal.key),
                         f'ignoring grab {refusal.reason}')
            return
        config = self._config
        if config.robot is not None:
            # A robot: the grab lands on the nearest of its links (``RobotBody.land``).
            link, local, distance = self._simulation.land(point)
            landed = Grab(local, distance)
        else:
            landed = grab(config.body_frame.link_state(self._simulation.state), config.geometry,
                          point)
        margin = config.grab_margin
        if not landed.taken(margin):
            off, bound = apart(landed.distance, margin)
            reason = (f'{point}: {off} m off the body, farther than grab_margin {bound} m from '
                      'its shape')
            self._refuse(Refusal('grab off body', reason), f'ignoring grab {reason}')
            return
        self._flush()  # a target that came before the grab goes before it
        if config.robot is not None:
            self._simulation.hold(link)
        failure = self._set_anchor(landed.anchor)
        if failure is not None:
            self._refuse(Refusal('grab anchor', f'{point}: {failure}'),
                         f'ignoring grab {point}: {failure}')
            return
        # Untimed: a grab starts a new stream of targets (nothing moves: the target is where
        # the anchor is).
        self._simulation.target = point
        self.user_target = True
        self.last_target_ns = self._now_ns()
