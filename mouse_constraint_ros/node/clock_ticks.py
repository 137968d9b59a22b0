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
The driver of the tick when the node is the clock (``publish_clock``): simulated time.

``SimulatedClock`` keeps the simulated time on the tick grid and says how many ticks are due
at a wall time; ``ClockPacer`` runs them from a timer on the steady clock, each ``Tick.run``
publishing ``/clock`` first. A node that is stepped by its caller has no pacing timer: each
``step`` runs one tick of the simulated clock, and nothing else advances it. ``ticker.Ticker``
owns this driver and says when it runs.

The simulated clock is made once: turning ``publish_clock`` off and on again goes on from the
simulated time reached.
"""

import time
from typing import Optional

from rclpy.node import Node
from rosgraph_msgs.msg import Clock as ClockMessage

from .tick import Tick
from ..timing.sim_clock import ClockPacer, PacingMeter, SimulatedClock
from ..timing.tick_grid import MAX_CATCH_UP_SECONDS
from ..wire.interface import CLOCK_QOS, CLOCK_TOPIC
from ..wire.messages import set_stamp


class ClockTicks:
    """
    Runs a tick on the simulated clock, paced by a steady-clock timer or by ``step`` calls.

    :param node: the node that publishes /clock and owns the timer.
    :param ticker: the owner of time (its steady clock).
    :param rate_hz: the tick rate the simulated clock starts with.
    :param real_time_factor: simulated seconds per wall second (0: as fast as it runs).
    """

    def __init__(self, node: Node, ticker, *, rate_hz: float, real_time_factor: float) -> None:
        """Create the simulated clock at 0; it runs once ``start`` is called."""
        self._node = node
        self._ticker = ticker
        self.sim_clock = SimulatedClock(rate_hz, real_time_factor,
                                        max_lag=MAX_CATCH_UP_SECONDS)
        # What the pacing achieved between two diagnostics calls.
        self.pacing = PacingMeter()
        self._tick: Optional[Tick] = None
        self._publisher = None
        self._timer = None
        self._pacer: Optional[ClockPacer] = None

    @property
    def now_ns(self) -> int:
        """Return the simulated time: that of the last tick run (ns)."""
        return self.sim_clock.now_ns

    @property
    def timer(self):
        """Return the pacing timer, or None (stopped, or stepped by the caller)."""
        return self._timer

    def start(self, tick: Tick, *, paced: bool) -> None:
        """Run ``tick``, which publishes /clock from now on; pace it by a timer if ``paced``."""
        if self._publisher is None:
            self._publisher = self._node.create_publisher(ClockMessage, CLOCK_TOPIC, CLOCK_QOS)
        self._tick = tick
        tick.clock_publisher = self._publisher
        self._destroy_timer()
        if paced:
            self._start_timer()

    def stop(self) -> None:
        """Stop pacing and publishing /clock: the node's clock drives the ticks again."""
        self._destroy_timer()
        if self._tick is not None:
            self._tick.clock_publisher = None
        publisher, self._publisher = self._publisher, None
        if publisher is not None:
            self._node.destroy_publisher(publisher)

    def set_pacing(self, rate_hz: float, real_time_factor: float) -> None:
        """Go on from the simulated time reached on a new grid of ``rate_hz``, paced anew."""
        self.sim_clock.set_rate(rate_hz)
        self.set_real_time_factor(real_time_factor)

    def set_real_time_factor(self, factor: float) -> None:
        """Pace by ``factor`` from now on."""
        self.sim_clock.set_real_time_factor(factor)
        if self._timer is not None:
            self._start_timer()

    def step(self, *, on_grid: bool = True, force_stamp: Optional[int] = None) -> int:
        """
        Run one tick of the simulated clock now; return its stamp (ns).

        :param on_grid: publish the state as the publish rate says; False: publish it (a
            single step asked for by ``~/step``, a device's tick).
        :param force_stamp: the force's stamp, if not the tick's (a device pose's).
        """
        clock = self.sim_clock
        stamp = clock.advance()
        self._tick.run(stamp, clock.ticks if on_grid else None, force_stamp=force_stamp)
        return stamp

    def skip(self) -> int:
        """
        Move the simulated clock on one tick without running it; return its stamp (ns).

        ``/clock`` says so at once. A reset while paused takes it: a state of a stamp of its own.
        """
        stamp = self.sim_clock.advance()
        if self._publisher is not None:
            message = ClockMessage()
            set_stamp(message.clock, stamp)
            self._publisher.publish(message)
        return stamp

    def _start_timer(self) -> None:
        self._destroy_timer()
        clock = self.sim_clock
        self._pacer = ClockPacer(clock.rate_hz, clock.real_time_factor)
        self._timer = self._node.create_timer(self._pacer.period, self._on_timer,
                                              clock=self._ticker.steady_clock)

    def _destroy_timer(self) -> None:
        if self._timer is not None:
            self._node.destroy_timer(self._timer)
            self._timer = None

    def _on_timer(self) -> None:
        pacer = self._pacer
        started = pacer.start()
        if started is None:
            # Clears the events queued while one tick outlasted the period (many substeps).
            return
        clock = self.sim_clock
        due = clock.due(time.monotonic_ns())
        if due == 0:
            return
        pacer.run(clock, self._tick.run, due, started)
