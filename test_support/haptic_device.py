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

``measure_largest_stable`` bisects the loop's stiffness in lockstep (test_haptic_stability.py
and bench/haptic_stability.py): a trial of 600 ticks is unstable when the peak of the force's
second difference over its last 250 ticks exceeds the peak over the 250 before. The second
difference scales the slow modes (the hand's) down by (w T)^2 and keeps the fast one that goes
unstable, so once the other fast modes have died (in the first 100 ticks) that growth is the
largest root's modulus to the 250th power, measured (test_haptic_stability holds each of its
15 trials to it within 0.02).
"""

from collections import deque
import math
from typing import Callable, List, Tuple

from geometry_msgs.msg import PoseStamped, WrenchStamped
import numpy as np
from rclpy.node import Node

from mouse_constraint_ros.physics.coupling_stability import Device, spectral_radius
from mouse_constraint_ros.testing import SimulatedBody
from mouse_constraint_ros.wire.interface import (FORCE_QOS, FORCE_TOPIC, TARGET_POSE_TOPIC,
                                                 TARGET_QOS)

PERIOD = 0.001
MASS = 0.2
SUBSTEPS = 2
# The body of the loop: held at its COM, weightless, the joint at the target itself, unbounded.
LOOP_BODY = {'mass': MASS, 'anchor': [0.0, 0.0, 0.0], 'gravity': [0.0, 0.0, 0.0],
             'max_target_speed': math.inf, 'max_target_acceleration': math.inf,
             'target_feed_forward': False, 'max_force': math.inf,
             'max_force_per_weight': math.inf, 'angular_friction': 0.0, 'publish_force': True,
             'substeps': SUBSTEPS, 'marker_rate_hz': 0.0, 'diagnostics_rate_hz': 0.0}
ORIGIN = (0.0, 0.0, 1.0)
HAND = {'hand_stiffness': 100.0, 'hand_damping': 1.0}
TRIAL_TICKS = 600
WINDOW = 250


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


def coupling(damping: float, delay: int) -> dict:
    """Return the coupling's arguments but the stiffness, for LOOP_BODY (``passive_stiffness``)."""
    return {'damping': damping, 'mass': MASS, 'period': PERIOD, 'substeps': SUBSTEPS,
            'delay': delay}


def loop(device: Device, damping: float, delay: int) -> dict:
    """Return the arguments of the loop's polynomial but the stiffness, for LOOP_BODY."""
    return {**coupling(damping, delay), 'device': device}


def trial(stiffness: float, damping: float, device: Device, delay: int) -> Tuple[bool, float]:
    """Run the loop at ``stiffness`` for TRIAL_TICKS; return (stable, growth over WINDOW)."""
    with SimulatedBody(coupling_stiffness=stiffness, coupling_damping=damping,
                       **LOOP_BODY) as body:
        node = body.add_node(DeviceNode(context=body.context, device=device, period=PERIOD,
                                        origin=ORIGIN, reference=lambda _: 0.01, delay=delay))
        body.step(TRIAL_TICKS)
        assert len(node.forces) == TRIAL_TICKS
        change = np.abs(np.diff(node.forces, 2))
        growth = float(change[-WINDOW:].max() / change[-2 * WINDOW:-WINDOW].max())
        return growth < 1.0, growth


def measure_largest_stable(predicted: float, damping: float, device: Device, delay: int,
                           halvings: int = 5):
    """
    Bisect between 0.75 and 1.3 times ``predicted``; return (low, high, trials).

    Each trial is (stiffness, measured growth, the predicted one: the largest root's modulus
    to the WINDOW-th power).
    """
    low, high, trials = 0.75 * predicted, 1.3 * predicted, []
    for _ in range(halvings):
        middle = math.sqrt(low * high)
        stable, growth = trial(middle, damping, device, delay)
        radius = spectral_radius(stiffness=middle, **loop(device, damping, delay))
        trials.append((middle, growth, radius ** WINDOW))
        low, high = (middle, high) if stable else (low, middle)
    return low, high, trials
