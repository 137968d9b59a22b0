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
The owner of the node's time: which driver runs the ticks, paused or running, the rate.

One of three drivers (``Driver``) runs ``Tick.run``: the node's own clock
(``tick_loop.NodeClockTicks``, a timer on system time or on ``/clock`` with use_sim_time), the
simulated clock paced by a steady-clock timer (``clock_ticks.ClockTicks``, ``publish_clock``),
or a caller that steps the node (``stepped``; ``mouse_constraint_ros.testing`` does, in
lockstep); beside it, a device's poses run ticks too (below): four callers of ``Tick.run`` in
all. With the last two drivers the node is the clock: it publishes ``/clock`` and its stamps
are the simulated time.

With ``tick_source: target_pose`` the device clocks the ticks (``timing.device_clock``): each
valid pose runs one tick at once (``device_tick``: a tick of the simulated clock when the node
is the clock, else the tick of its clock's grid one period after the latest), its force stamped
with the pose's stamp; the driver's own ticks are held back while poses come, and run again
after ``device_timeout`` without one. A paced simulated clock
(``publish_clock`` without a caller) keeps its own ticks: it paces simulated time itself.

``Ticker`` answers every question about time the node's parts ask: what time it is, whether
the node is the clock, whether a clock it waits for has come, whether it is paused; and it
carries out every change of time: pause, resume, one step, a new rate, real-time factor, publish
rate or clock. Nothing else keeps a copy of the rate or of the pause state: the drivers read
them here, and the tick length, the publishing schedule and the simulated clock's grid are set
from here, together.
"""

import enum
import time
from typing import Callable, Optional, Tuple

from rclpy.clock import Clock, ClockType
from rclpy.node import Node

from .clock_ticks import ClockTicks
from .device_ticks import OwnTicks
from .parameters import NodeConfig
from .tick import Tick
from .tick_loop import NodeClockTicks
from .tick_record import TickRecord
from ..timing.device_clock import DEVICE_LAG_CAUSE, DeviceClock
from ..timing.tick_grid import drop_text

# Period (s, steady clock) of the check that a clock the node waits for has started.
CLOCK_WATCH_PERIOD = 1.0


class Driver(enum.Enum):
    """What runs the ticks."""

    NODE_CLOCK = 'node clock'
    SIMULATED_CLOCK = 'simulated clock'
    CALLER = 'caller'


class Ticker:
    """
    Which driver runs the tick, and when: the node's time, its pause, its rates.

    :param node: the node whose clock, timers and /clock publisher are used.
    :param config: the configuration the ticks start with (rates, clock, real-time factor).
    :param record: the ticks' record (late and dropped ticks, clock restarts, the tick length).
    :param stepped: a caller runs the ticks, one ``step`` each; no timer does.
    :param warn: ``warn(key, message())``, throttled per key.
    :param loop: the node's spin loop makes the node clock's calls on system time
        (``run_due``), not an rclpy timer (``MouseConstraintNode``'s ``loop_ticks``).
    """

    def __init__(self, node: Node, *, config: NodeConfig, record: TickRecord, stepped: bool,
                 warn: Callable[[str, Callable[[], str]], None], loop: bool = False) -> None:
        """Create the drivers, idle until ``start``; watch for a clock that does not come."""
        self.record = record
        # The clock of the timers that must run while a simulated clock stands still.
        self.steady_clock = Clock(clock_type=ClockType.STEADY_TIME)
        self.paused = False
        # How many times the ticks resumed: a rate window across a pause measures nothing.
        self.resumes = 0
        self.driver: Optional[Driver] = None
        self._node = node
        self._config = config
        self._stepped = stepped
        self._warn = warn
        self._tick: Optional[Tick] = None
        self._own: Optional[OwnTicks] = None
        self.device_clock = DeviceClock()
        self._node_clock = NodeClockTicks(node, self, record, warn=warn, loop=loop)
        self._simulated = ClockTicks(node, self, rate_hz=config.rate_hz,
                                     real_time_factor=config.real_time_factor)
        node.create_timer(CLOCK_WATCH_PERIOD, self._watch_clock, clock=self.steady_clock)

    # What time it is, and who keeps it.

    @property
    def is_clock(self) -> bool:
        """Return whether the node is the clock: it publishes /clock, its stamps are simulated."""
        return self.driver is not None and self.driver is not Driver.NODE_CLOCK

    @property
    def rate_hz(self) -> float:
        """Return the tick rate (Hz)."""
        return self._config.rate_hz

    @property
    def publish_rate_hz(self) -> float:
        """Return the rate (Hz) the state is published at; 0: every tick."""
        return self._config.publish_rate_hz

    @property
    def substeps(self) -> int:
        """Return the physics substeps per tick (a tick's cost, named when ticks are dropped)."""
        return self._config.settings.substeps

    def now_ns(self) -> int:
        """Return the node's time (ns): the simulated clock's when the node is the clock."""
        if self.is_clock:
            return self._simulated.now_ns
        return self._node.get_clock().now().nanoseconds

    def waiting_for_clock(self) -> Optional[str]:
        """
        Return ``'/clock on <topic>'`` while the node's clock waits for a first /clock message.

        With use_sim_time the node's clock reads zero until then and no timer on it fires: no
        tick, no pose. None when the node is the clock or its clock runs.
        """
        if self.is_clock:
            return None
        return self._node_clock.waiting_for_clock()

    def stands_still(self) -> Optional[int]:
        """
        Return the node's time (ns) while its clock reads the latest stamp or before, else None.

        A single step (``step_once``) is stamped with the node's clock: one that stands still
        (use_sim_time, a /clock that stopped) would stamp a second state with the stamp of the
        tick before it (or of the reset after it, 1 ns on). None when the node is the clock: its
        step moves the clock on.
        """
        if self.is_clock or self.record.ticks_run == 0:
            return None
        now = self._node_clock.now_ns()
        return now if now <= self.record.stamp_ns else None

    @property
    def timer(self):
        """Return the timer that runs the ticks now, or None (a caller steps the node)."""
        if self.is_clock:
            return self._simulated.timer
        return self._node_clock.timer

    def run_due(self) -> Optional[float]:
        """
        Run the ticks due now when the spin loop drives them; return the time (s) to the next.

        The ``pace`` of ``timing.spin.spin_until``: None when no tick is the loop's to run (an
        rclpy timer or a caller runs them, or the node clock runs on /clock).
        """
        if self.driver is not Driver.NODE_CLOCK:
            return None
        return self._node_clock.run_due()

    def pacing(self) -> Tuple[Optional[float], float]:
        """
        Return the simulated clock's pacing since the last call: (achieved factor, slipped s).

        The achieved factor is None before a second call, or while the node is not the clock.
        """
        achieved, slipped = self._simulated.pacing.sample(time.monotonic_ns(),
                                                          self._simulated.sim_clock)
        return (achieved if self.is_clock else None), slipped

    # What changes it.

    def start(self, tick: Tick) -> None:
        """Run ``tick`` from now on, driven as the configuration says."""
        self._tick = tick
        self._apply_rates(self._config)
        self._start_driver()

    def configure(self, config: NodeConfig) -> bool:
        """
        Take a new configuration: a new rate, clock, real-time factor or publish rate.

        A new rate or clock starts a new grid (the simulated clock goes on from the time it
        reached); a new real-time factor paces from now on; a new publish rate keeps the grid on
        a timer of the new batch, no tick lost.

        :returns: whether the node's time changed base (the node became or stopped being the
            clock): ages measured in the old base mean nothing in the new one.
        """
        previous, self._config = self._config, config
        self._apply_rates(config)
        if (config.rate_hz, config.publish_clock) != (previous.rate_hz, previous.publish_clock):
            self._simulated.set_pacing(config.rate_hz, config.real_time_factor)
            self._start_driver()
            return config.publish_clock != previous.publish_clock
        if config.real_time_factor != previous.real_time_factor:
            self._simulated.set_real_time_factor(config.real_time_factor)
        elif config.publish_rate_hz != previous.publish_rate_hz and not self.is_clock:
            self._node_clock.retime(config.rate_hz, config.publish_rate_hz)
        return False

    def set_paused(self, pause: bool) -> bool:
        """
        Pause or resume the ticks; return whether that changed anything.

        Resuming catches nothing up: the simulated clock paces on from where it stood, the
        node-clock grid starts again at the next timer call.
        """
        if pause == self.paused:
            return False
        self.paused = pause
        if pause:
            self._simulated.sim_clock.pause()
        else:
            self._simulated.sim_clock.resume()
            self._node_clock.resume()
            self.resumes += 1
        return True

    def step_once(self) -> None:
        """Run one tick now and publish it (``~/step``): of the simulated clock, or now."""
        if self.is_clock:
            self._simulated.step(on_grid=False)
        else:
            self._tick.run(self._node_clock.now_ns())

    def step(self) -> bool:
        """
        Run one tick of the simulated clock now, unless paused; return whether it ran.

        :raises RuntimeError: the node is not stepped by its caller.
        """
        if self.driver is not Driver.CALLER:
            raise RuntimeError('step() runs the ticks of a node made with stepped=True; this '
                               'one runs them on a timer of its own')
        if self.paused or not self.device_clock.own_tick():
            return False
        self._simulated.step()
        return True

    def device_tick(self, pose_stamp_ns: int) -> None:
        """
        Run one tick now for a device pose just taken, when the device clocks the ticks.

        Stamped one period after the latest tick (of the simulated clock when the node is the
        clock, else on its clock's grid: ``device_grid_tick``); its force carries the pose's
        stamp, ``pose_stamp_ns``.
        """
        clock = self.device_clock
        if not clock.on or self.paused or self._tick is None:
            return
        clock.take(time.monotonic_ns())
        if self.is_clock:
            self._simulated.step(on_grid=False, force_stamp=pose_stamp_ns)
        else:
            self._tick.run(self._device_stamp(), force_stamp=pose_stamp_ns)

    def _device_stamp(self) -> int:
        """Return the stamp of a device tick on the node's clock's grid; count ticks dropped."""
        record = self.record
        stamp, dropped = self._own.device_stamp(self._node_clock.now_ns(), record)
        if dropped:
            record.drop(dropped, DEVICE_LAG_CAUSE)
            self._warn('rate', lambda: drop_text(self.rate_hz, dropped, record.dropped_ticks,
                                                 DEVICE_LAG_CAUSE))
        return stamp

    def publish_state(self) -> None:
        """
        Publish the state as it stands (a reset while paused), at a stamp of its own; no force.

        The node as the clock moves its clock on one tick for it (``ClockTicks.skip``); on the
        node's clock it is the clock's reading, or 1 ns after the latest tick if the clock stands
        still. A reader keyed by stamp (tf2) drops a state whose stamp repeats one it has.
        """
        if self.is_clock:
            stamp = self._simulated.skip()
        else:
            stamp = max(self._node_clock.now_ns(), self.record.stamp_ns + 1)
        self._tick.publish_state(stamp)

    def stop(self) -> None:
        """Stop every tick timer (before shutdown): no tick runs after."""
        self._node_clock.stop()
        self._simulated.stop()

    def _apply_rates(self, config: NodeConfig) -> None:
        self._tick.configure(rate_hz=config.rate_hz, publish_rate_hz=config.publish_rate_hz)
        paced = config.publish_clock and not self._stepped
        self.device_clock.configure(on=config.device.tick_source == 'target_pose' and not paced,
                                    rate_hz=config.rate_hz, timeout=config.device.timeout)

    def _start_driver(self) -> None:
        config = self._config
        if config.publish_clock:
            self.driver = Driver.CALLER if self._stepped else Driver.SIMULATED_CLOCK
            self._node_clock.stop()
            self._simulated.start(self._tick, paced=not self._stepped)
        else:
            self.driver = Driver.NODE_CLOCK
            self._simulated.stop()
            self._own = OwnTicks(self._tick, self.device_clock, lambda: self._node_clock.grid)
            self._node_clock.start(self._own, config.rate_hz, config.publish_rate_hz)

    def _watch_clock(self) -> None:
        waiting = self.waiting_for_clock()
        if waiting is not None:
            self._warn('clock', lambda: (
                f'waiting for {waiting}: use_sim_time is true and no clock message has come; '
                'no tick runs until one does'))
