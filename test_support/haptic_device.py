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
A simulated haptic device as a downstream node: it reads the force, moves, sends its pose.

Each ``force`` message (one per tick) is held over the next tick on a point mass m_d with
damping b_d, pulled by a hand (spring and damper) toward a reference; the mass moves exactly
(``Device.matrices``) along x, and its position goes out on ``target_pose`` as a
``PoseStamped``, as a device driver publishes its handle. In lockstep it is taken before the
next tick and acts from it; ``delay`` ticks more hold it back in a queue first.
"""

from collections import deque
from typing import Callable, List

from geometry_msgs.msg import PoseStamped, WrenchStamped
import numpy as np
from rclpy.node import Node

from mouse_constraint_ros.physics.coupling_stability import Device
from mouse_constraint_ros.wire.interface import (FORCE_QOS, FORCE_TOPIC, TARGET_POSE_TOPIC,
                                                 TARGET_QOS)


class DeviceNode(Node):
    """
    The device, moving along x from ``origin`` (its state relative to it).

    :param device: mass, damping and the hand's gains.
    :param period: the tick (s) over which each force is held.
    :param origin: where the handle starts, and the hand's reference's zero (m, world).
    :param reference: the hand's reference along x (m from ``origin``) at a time (s).
    :param delay: ticks the position waits before it goes out (0: lockstep).
    """

    def __init__(self, *, context, device: Device, period: float, origin,
                 reference: Callable[[float], float], delay: int = 0) -> None:
        """Start at rest at ``origin``."""
        super().__init__('haptic_device', context=context, start_parameter_services=False)
        self._phi, self._gamma = device.matrices(period)
        self._device = device
        self._origin = np.array(origin, dtype=float)
        self._reference = reference
        self._state = np.zeros(2)
        self._queue = deque([0.0] * delay)
        self.forces: List[float] = []
        self._message = PoseStamped()
        self._message.pose.orientation.w = 1.0
        self._publisher = self.create_publisher(PoseStamped, TARGET_POSE_TOPIC, TARGET_QOS)
        self.create_subscription(WrenchStamped, FORCE_TOPIC, self._on_force, FORCE_QOS)

    def reset(self) -> None:
        """Back at rest at the origin, the queue at the origin too, no forces."""
        self._state = np.zeros(2)
        self._queue = deque([0.0] * len(self._queue))
        self.forces = []

    @property
    def position(self) -> float:
        """Return the handle's position along x from the origin (m)."""
        return float(self._state[0])

    def energy(self) -> float:
        """Return the handle's kinetic energy and the hand spring's (J)."""
        x, v = self._state
        return 0.5 * self._device.mass * v * v + 0.5 * self._device.hand_stiffness * x * x

    def _on_force(self, message: WrenchStamped) -> None:
        force = message.wrench.force.x
        self.forces.append(force)
        stamp = message.header.stamp
        time = stamp.sec + stamp.nanosec * 1e-9
        pull = force + self._device.hand_stiffness * self._reference(time)
        self._state = self._phi @ self._state + self._gamma * pull
        self._queue.append(float(self._state[0]))
        self._message.header.stamp = stamp
        position = self._message.pose.position
        position.x, position.y, position.z = self._origin + (self._queue.popleft(), 0.0, 0.0)
        self._publisher.publish(self._message)
