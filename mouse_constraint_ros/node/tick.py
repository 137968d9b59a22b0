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
One tick of the node, and the record of the ticks run: the object its four drivers share.

A tick at stamp t applies the input that arrived (the newest target that waited for the tick
is taken, a target older than ``target_timeout`` is let go, the wrench scheduled up to t is put
in effect or expires), steps the physics by one dt, publishes ``/clock`` when the node is the
clock, and pose, twist, TF and odometry on the ticks that publish (``PublishTicks``), all
stamped t (a robot's joint_states and links' TF too). Four drivers call ``Tick.run``: the
node's timer on its own clock (``tick_loop.NodeClockTicks``), the simulated clock's pacer
(``clock_ticks.ClockTicks``), a caller that steps the node itself (``Ticker.step``, which
``mouse_constraint_ros.testing`` drives in lockstep), and a device's poses
(``Ticker.device_tick``, ``tick_source: target_pose``); ``ticker.Ticker`` says which runs.

The tick writes its stamp and count in the ``TickRecord`` that the inputs and monitors read.
"""

from typing import Optional

from rclpy.publisher import Publisher
from rosgraph_msgs.msg import Clock as ClockMessage

from .target_input import TargetInput
from .tick_record import TickRecord
from .wrench_input import WrenchInput
from ..physics import MouseSimulation
from ..timing.publish_ticks import PublishTicks
from ..wire.messages import set_stamp
from ..wire.state_publishers import StatePublishers


class Tick:
    """
    One tick: the inputs at its stamp, one physics step, the outputs of its stamp.

    :param simulation: the body; stepped by ``record.dt`` each tick.
    :param target: the target input, let go of when it times out.
    :param wrench: the wrench input, put in effect or removed at the tick's stamp.
    :param state_publishers: pose, twist, TF and odometry.
    :param record: written with the tick's stamp and count.
    """

    def __init__(self, *, simulation: MouseSimulation, target: TargetInput, wrench: WrenchInput,
                 state_publishers: StatePublishers, record: TickRecord) -> None:
        """Publish every tick at 1 kHz until ``configure`` says otherwise; no /clock."""
        self._simulation = simulation
        self._target = target
        self._wrench = wrench
        self._state_publishers = state_publishers
        self._record = record
        self._publish_ticks = PublishTicks(1000.0, 0.0)
        # /clock, published by the tick while the node is the clock (set by ``ClockTicks``); which
        # driver runs, and whether the node is the clock, is ``Ticker``'s to say.
        self.clock_publisher: Optional[Publisher] = None
        # A robot's joint_states and links' TF (``wire.robot_outputs``), or None for one body.
        self.robot_outputs = None
        self._clock_message = ClockMessage()

    def configure(self, *, rate_hz: float, publish_rate_hz: float) -> None:
        """Step 1 / ``rate_hz`` per tick; publish the state at ``publish_rate_hz`` (0: all)."""
        self._record.dt = 1.0 / rate_hz
        self._publish_ticks = PublishTicks(rate_hz, publish_rate_hz)

    def run(self, stamp: int, tick: Optional[int] = None, force_stamp: Optional[int] = None
            ) -> None:
        """
        Run one tick stamped ``stamp`` (ns).

        :param stamp: the tick's time: the stamp of /clock and of the state.
        :param tick: the tick's number on its grid, for ``PublishTicks``; None publishes (a
            single step: ``~/step``, or a caller stepping the node).
        :param force_stamp: the force's stamp if not ``stamp``: the pose's that ran the tick.
        """
        record = self._record
        self._target.tick()
        self._target.expire(stamp)
        self._wrench.apply(stamp)
        state = self._simulation.step(record.dt)
        clock = self.clock_publisher
        if clock is not None:
            set_stamp(self._clock_message.clock, stamp)
            clock.publish(self._clock_message)
        record.stamp_ns = stamp
        record.ticks_run += 1
        publish_ticks = self._publish_ticks
        if tick is None or publish_ticks.every_tick or publish_ticks.due(tick):
            publishers = self._state_publishers
            publishers.force_muted = self._target.device.silent(stamp)
            publishers.publish(stamp, state, force_stamp=force_stamp)
            if self.robot_outputs is not None:
                self._publish_robot(stamp)

    def _publish_robot(self, stamp: int) -> None:
        """Publish the robot's joint_states (and its links' TF) of the tick stamped ``stamp``."""
        robot = self._simulation.robot
        outputs = self.robot_outputs
        outputs.publish(stamp, robot.joint_positions(), robot.joint_velocities(),
                        robot.joint_efforts(), robot.link_poses() if outputs.tf_on else None)

    def publish_state(self, stamp: int) -> None:
        """
        Publish the state as it stands at ``stamp`` (after a reset), the latest stamp; no force.

        No tick ran: there is no reaction to send (a zero force would say the body let go).
        """
        self._record.stamp_ns = stamp
        self._state_publishers.publish(stamp, self._simulation.state, force=False)
        if self.robot_outputs is not None:
            self._publish_robot(stamp)
