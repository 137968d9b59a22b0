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

"""A device as its driver publishes it: its QoS, its frame and scale, its force message."""

import math

from geometry_msgs.msg import PoseStamped
import numpy as np
import pytest
from rclpy.node import Node
from rclpy.qos import qos_profile_sensor_data
from scipy.spatial.transform import Rotation
from std_msgs.msg import Float64MultiArray

from mouse_constraint_ros.node.device_parameters import device_from
from mouse_constraint_ros.node.parameters import DEFAULTS
from mouse_constraint_ros.physics.device_map import device_map, DeviceMap
from mouse_constraint_ros.testing import SimulatedBody
from mouse_constraint_ros.wire.interface import (FORCE_ARRAY_TOPIC, FORCE_QOS, FORCE_TOPIC,
                                                 TARGET_POSE_TOPIC, TARGET_QOS)
from mouse_constraint_ros.wire.messages import set_stamp
from test_support.haptic_listener import StateListener

# A y-up device frame, turned a quarter about world x, its origin at the held corner's start.
Y_UP = Rotation.from_euler('x', 90.0, degrees=True)
START = np.array([0.2, 0.1, 1.05])


class Device(Node):
    """Publishes handle poses on target_pose with a QoS and frame of its own."""

    def __init__(self, *, context, qos=TARGET_QOS, frame_id: str = '') -> None:
        """Create the pose publisher."""
        super().__init__('device', context=context, start_parameter_services=False)
        self.frame_id = frame_id
        self.publisher = self.create_publisher(PoseStamped, TARGET_POSE_TOPIC, qos)

    def send(self, point, nanoseconds: int) -> None:
        """Publish the handle at ``point`` (device frame), stamped ``nanoseconds``."""
        message = PoseStamped()
        message.header.frame_id = self.frame_id
        set_stamp(message.header.stamp, nanoseconds)
        p = message.pose.position
        p.x, p.y, p.z = (float(c) for c in point)
        message.pose.orientation.w = 1.0
        self.publisher.publish(message)


class ArrayListener(Node):
    """Records every force_array message's data."""

    def __init__(self, *, context) -> None:
        """Subscribe to force_array."""
        super().__init__('array_listener', context=context, start_parameter_services=False)
        self.arrays = []
        self.create_subscription(Float64MultiArray, FORCE_ARRAY_TOPIC,
                                 lambda m: self.arrays.append(np.array(m.data)), FORCE_QOS)


def test_the_map_and_its_force_back_are_transposes():
    """The map o + s R p_d and f R^T F back: the power f_d . v_d is (f / s) F . v, any motion."""
    rotation = Y_UP * Rotation.from_euler('z', 30.0, degrees=True)
    mapping = DeviceMap(0.5, (1.0, -2.0, 0.25), tuple(rotation.as_quat()), 0.5)
    p_d, v_d = np.array([0.03, -0.02, 0.01]), np.array([0.4, 0.1, -0.3])
    expected = np.array([1.0, -2.0, 0.25]) + 0.5 * rotation.apply(p_d)
    np.testing.assert_allclose(mapping.to_world(tuple(p_d)), expected, rtol=0, atol=1e-15)
    velocity = (np.array(mapping.to_world(tuple(p_d + 1e-3 * v_d))) - expected) / 1e-3
    force = np.array([1.5, -0.5, 2.0])
    f_d = np.array(mapping.to_device(tuple(force)))
    np.testing.assert_allclose(f_d, 0.5 * rotation.inv().apply(force), rtol=0, atol=1e-15)
    assert f_d @ v_d == pytest.approx(force @ velocity, rel=1e-9)
    assert mapping.felt_stiffness(300.0) == 75.0


@pytest.mark.parametrize('change, words', [
    ({'device_scale': 0.0}, 'device_scale must be >= 1e-06'),
    ({'device_force_scale': math.inf}, 'device_force_scale must be finite'),
    ({'device_pose': [0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0]}, 'unit quaternion, got norm 0'),
    ({'device_pose': [0.0, 0.0, math.nan, 0.0, 0.0, 0.0, 1.0]}, 'device_pose must be finite'),
    ({'device_pose': [0.0, 0.0, 1.0]}, 'device_pose must have 7 elements'),
    ({'force_output': 'wrenches'}, 'force_output must be one of wrench, array, both'),
    ({'device_frame_id': 3}, 'device_frame_id must be a string'),
    ({'device_timeout': -1.0}, 'device_timeout must be >= 0.0'),
])
def test_a_device_parameter_that_means_nothing_is_refused_by_name(change, words):
    with pytest.raises(ValueError, match=words.replace('(', r'\(')):
        device_from({**DEFAULTS, **change})


def test_a_rotation_written_with_few_digits_is_normalised():
    mapping = device_map(1.0, [0.0, 0.0, 0.0, 0.7071, 0.0, 0.0, 0.7071], 1.0)
    assert math.fsum(c * c for c in mapping.rotation) == pytest.approx(1.0, abs=1e-15)


@pytest.mark.ros
def test_a_best_effort_driver_drives_the_body():
    """A driver publishing with sensor QoS (BEST_EFFORT) matches target_pose and moves the body."""
    with SimulatedBody() as body:
        device = body.add_node(Device(context=body.context, qos=qos_profile_sensor_data))
        for tick in range(400):
            device.send(START + (0.0, 0.0, 0.1), round(body.time * 1e9))
            body.step()
        assert body.node.refusals == (0, None)
        assert body.node.simulation.target == pytest.approx(tuple(START + (0.0, 0.0, 0.1)))
        assert body.node.simulation.anchor_position()[2] > 1.1


def stream(mapped: bool, ticks: int = 300, **parameters):
    """
    Lift the held corner 5 cm over 0.3 s by a device stream, as world points or device points.

    Mapped: the device is y-up, its centimetre-scale points scaled by 10 into the world, its
    origin at the corner's start, stamped ``haptic_base``. Returns the listener.
    """
    if mapped:
        parameters.update(device_frame_id='haptic_base', device_scale=10.0,
                          device_pose=[*START, *Y_UP.as_quat()], device_force_scale=0.5)
    body = SimulatedBody(publish_force=True, force_output='both', **parameters)
    with body:
        listener = body.add_node(StateListener(context=body.context))
        arrays = body.add_node(ArrayListener(context=body.context))
        device = body.add_node(Device(context=body.context,
                                      frame_id='haptic_base' if mapped else ''))
        for tick in range(ticks):
            world = START + (0.0, 0.0, 0.05 * min(tick, 300) / 300)
            point = Y_UP.inv().apply(world - START) / 10.0 if mapped else world
            device.send(point, round(body.time * 1e9))
            body.step()
        assert body.node.refusals == (0, None)
    return listener, arrays


@pytest.mark.ros
def test_a_mapped_device_moves_the_body_as_world_points_do_and_feels_the_force_mapped_back():
    """Same world targets: the same motion; the force f R^T F, on both outputs, every tick."""
    world, world_arrays = stream(False)
    mapped, mapped_arrays = stream(True)
    poses = np.array([p for _, p in world.poses])
    np.testing.assert_allclose(np.array([p for _, p in mapped.poses]), poses, rtol=0, atol=1e-12)
    assert np.ptp(poses[:, 2]) > 0.03
    forces = np.array([f for _, f in world.forces])
    expected = 0.5 * Y_UP.inv().apply(forces)
    assert len(mapped.forces) == len(mapped_arrays.arrays) == 300
    np.testing.assert_allclose(np.array([f for _, f in mapped.forces]), expected, rtol=0,
                               atol=1e-9)
    np.testing.assert_array_equal(np.array(mapped_arrays.arrays),
                                  np.array([f for _, f in mapped.forces]))
    np.testing.assert_array_equal(np.array(world_arrays.arrays), forces)


@pytest.mark.ros
def test_force_output_chooses_the_force_s_messages():
    """Each output's publisher is made when first chosen and kept, silent, when left."""
    with SimulatedBody(publish_force=True, force_output='array') as body:
        assert (body.node.count_publishers(FORCE_TOPIC),
                body.node.count_publishers(FORCE_ARRAY_TOPIC)) == (0, 1)
        body.set_parameters(force_output='both')
        assert (body.node.count_publishers(FORCE_TOPIC),
                body.node.count_publishers(FORCE_ARRAY_TOPIC)) == (1, 1)
        body.set_parameters(publish_force=False, force_output='wrench')
        assert (body.node.count_publishers(FORCE_TOPIC),
                body.node.count_publishers(FORCE_ARRAY_TOPIC)) == (1, 1)
