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
config/haptic.yaml: inside the stability and passivity bounds, and what a hand feels through it.

Through ROS in lockstep, a device's stream of PoseStamped on target_pose, the force read on
force: held still, the weight; pushed at a constant acceleration a, m (g - a); hung by the
corner and swinging, the reaction of the exact physical pendulum at its pivot. Each within 1 %
of the weight.
"""

import math
from pathlib import Path

from geometry_msgs.msg import PoseStamped
import numpy as np
import pytest
from rclpy.node import Node
from scipy.spatial.transform import Rotation
import yaml

from mouse_constraint_ros.physics import RigidBody
from mouse_constraint_ros.physics.coupling_stability import (Device, largest_stable_stiffness,
                                                             passive_stiffness)
from mouse_constraint_ros.testing import SimulatedBody
from mouse_constraint_ros.wire.interface import TARGET_POSE_TOPIC, TARGET_QOS
from mouse_constraint_ros.wire.messages import set_stamp
from test_support.haptic_listener import StateListener
from test_support.reference_dynamics import hanging_rotation, pendulum_com_path

PRESET = yaml.safe_load((Path(__file__).resolve().parent.parent / 'config' / 'haptic.yaml')
                        .read_text())['/**']['ros__parameters']
MASS = PRESET['mass']
G = 9.80665
GRAVITY = np.array([0.0, 0.0, -G])
WEIGHT = MASS * G
T = 1.0 / PRESET['rate_hz']
ANCHOR = np.array(PRESET['anchor'])
# The handles the preset is made for, each held by a hand (100 N/m, 1 N s/m), and the margin.
HAND = {'hand_stiffness': 100.0, 'hand_damping': 1.0}
DEVICES = {'Touch-like': Device(0.045, 0.05, **HAND), 'omega.3-like': Device(0.2, 0.05, **HAND)}
MARGIN = 2.0


def preset_body(**overrides) -> SimulatedBody:
    """Return the body of config/haptic.yaml with ``overrides``."""
    return SimulatedBody(**{**PRESET, **overrides})


@pytest.mark.parametrize('name', DEVICES)
@pytest.mark.parametrize('delay', [0, 1])
def test_the_preset_is_within_half_of_both_bounds(name, delay):
    """Stable (the loop's polynomial) and passive (Colgate and Brown, with delay) twice over."""
    device = DEVICES[name]
    stiffness = PRESET['coupling_stiffness']
    stable = largest_stable_stiffness(damping=PRESET['coupling_damping'], mass=MASS,
                                      device=device, period=T, substeps=PRESET['substeps'],
                                      delay=delay)
    passive = passive_stiffness(device_damping=device.damping + device.hand_damping,
                                damping=PRESET['coupling_damping'], mass=MASS, period=T,
                                substeps=PRESET['substeps'], delay=delay)
    assert stiffness * MARGIN <= stable
    assert stiffness * MARGIN <= passive


def test_the_preset_s_initial_pose_hangs_below_the_corner():
    rotation = Rotation.from_quat(PRESET['initial_orientation'])
    up = rotation.apply(ANCHOR / np.linalg.norm(ANCHOR))
    np.testing.assert_allclose(up, (0.0, 0.0, 1.0), atol=1e-15)
    np.testing.assert_allclose(hanging_rotation(ANCHOR).as_quat(),
                               PRESET['initial_orientation'], atol=1e-15)


def listening(body: SimulatedBody) -> StateListener:
    """Return a listener of pose, twist and force added to ``body``."""
    return body.add_node(StateListener(context=body.context))


@pytest.mark.ros
def test_held_still_the_hand_feels_the_weight():
    with preset_body() as body:
        listener = listening(body)
        body.step(1000)
        forces = np.array([force for _, force in listener.forces])
        error = np.abs(forces - (0.0, 0.0, -WEIGHT)).max()
        assert error <= 0.01 * WEIGHT, error


class PushingHand(Node):
    """Streams the pose of a hand that lifts the anchor at a constant acceleration."""

    def __init__(self, *, context, start, acceleration) -> None:
        """Publish on target_pose, stamped, after each pose of the body."""
        super().__init__('pushing_hand', context=context, start_parameter_services=False)
        self.start, self.acceleration = np.array(start), np.array(acceleration)
        self.publisher = self.create_publisher(PoseStamped, TARGET_POSE_TOPIC, TARGET_QOS)

    def send(self, time: float) -> None:
        """Send where the hand is at ``time`` (s of simulated time)."""
        message = PoseStamped()
        set_stamp(message.header.stamp, round(time * 1e9))
        point = self.start + 0.5 * self.acceleration * time * time
        message.pose.position.x, message.pose.position.y, message.pose.position.z = point
        message.pose.orientation.w = 1.0
        self.publisher.publish(message)


@pytest.mark.ros
@pytest.mark.parametrize('acceleration', [(0.0, 0.0, 3.0), (0.0, 0.0, -4.0)])
def test_pushed_at_a_constant_acceleration_the_hand_feels_m_g_minus_a(acceleration):
    """From 0.5 s on, once the coupling's start has died away: m (g - a) within 1 %."""
    with preset_body() as body:
        listener = listening(body)
        # The hand starts where the corner hangs: (0, 0, |anchor|) above the COM at the origin.
        start = (0.0, 0.0, float(np.linalg.norm(ANCHOR)))
        hand = body.add_node(PushingHand(context=body.context, start=start,
                                         acceleration=acceleration))
        for _ in range(800):
            hand.send(body.time)
            body.step()
        forces = np.array([force for _, force in listener.forces])[500:]
        expected = MASS * (GRAVITY - acceleration)
        assert np.linalg.norm(expected) < PRESET['max_force']
        error = np.abs(forces - expected).max()
        assert error <= 0.01 * WEIGHT, error


@pytest.mark.ros
def test_swinging_the_hand_feels_the_pendulum_s_reaction():
    """Released 10 deg from hanging, the hand still: m (g - a_com) of the exact pendulum, 1 %."""
    tilt = Rotation.from_rotvec((math.radians(10.0), 0.0, 0.0))
    orientation = tilt * Rotation.from_quat(PRESET['initial_orientation'])
    pivot = np.array(PRESET['initial_position']) + Rotation.from_quat(
        PRESET['initial_orientation']).apply(ANCHOR)
    start = pivot - orientation.apply(ANCHOR)
    ticks = 2000
    with preset_body(initial_orientation=orientation.as_quat().tolist(),
                     initial_position=start.tolist()) as body:
        listener = listening(body)
        body.step(ticks)
        forces = np.array([force for _, force in listener.forces])
    inertia = RigidBody.solid_box(MASS, PRESET['box_size']).inertia
    # The tick's force is the mean over it, centred half a tick (and half a substep) back.
    fine = 1e-5
    times = np.arange(0.0, ticks * T + 2 * fine, fine)
    path = pendulum_com_path(MASS, inertia, ANCHOR, pivot, orientation, times, gravity=G)
    acceleration = (path[2:] - 2.0 * path[1:-1] + path[:-2]) / fine ** 2
    centres = (np.arange(1, ticks + 1) - 0.5) * T - 0.25 * T
    index = np.rint(centres / fine).astype(int) - 1
    expected = MASS * (GRAVITY - acceleration[index])
    error = np.abs(forces - expected).max()
    assert error <= 0.01 * WEIGHT, error
    # A swing: the reaction turns and varies by a tenth of the weight and more.
    assert np.ptp(expected, axis=0).max() > 0.1 * WEIGHT
