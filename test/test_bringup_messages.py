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
The TF and odometry builders: message contents, and the frames their twists are expressed in.

Expected values come from scipy's ``Rotation`` (not the package's own rotation code), and the
frame convention is checked against finite differences of the poses the builders publish for a
simulated spinning, moving body.
"""

from geometry_msgs.msg import TwistStamped
from nav_msgs.msg import Odometry
import numpy as np
import pytest
from scipy.spatial.transform import Rotation

from mouse_constraint_ros.physics import (BodyState, MouseConstraint, MouseSimulation, RigidBody,
                                          Settings)
from mouse_constraint_ros.wire.messages import (fill_odometry, fill_transform, fill_twist,
                                                odometry_message, stamp_nanoseconds,
                                                transform_message)

STEP = 1e-3


def random_states(count: int, seed: int):
    """Yield ``count`` random valid body states (unit quaternions, velocities of order 1-10)."""
    rng = np.random.default_rng(seed)
    for _ in range(count):
        yield BodyState(
            tuple(rng.uniform(-5.0, 5.0, 3).tolist()),
            tuple(Rotation.random(random_state=rng).as_quat().tolist()),
            tuple(rng.uniform(-3.0, 3.0, 3).tolist()),
            tuple(rng.uniform(-10.0, 10.0, 3).tolist()),
        ).validated()


def vector(message) -> np.ndarray:
    """Return the x, y, z fields of a ``Point`` or ``Vector3`` as an array."""
    return np.array([message.x, message.y, message.z])


def quaternion(message) -> np.ndarray:
    """Return a ``geometry_msgs/Quaternion`` as an (x, y, z, w) array."""
    return np.array([message.x, message.y, message.z, message.w])


@pytest.mark.parametrize('seed', range(3))
def test_transform_carries_the_com_pose_between_the_frames(seed):
    """TransformStamped: frame_id -> body frame, the COM position and the orientation."""
    for k, state in enumerate(random_states(20, seed)):
        nanoseconds = 1_700_000_000_123_456_789 + k * 1_000_003
        message = transform_message(state, frame_id='world', body_frame_id='body',
                                    nanoseconds=nanoseconds)
        assert message.header.frame_id == 'world'
        assert message.child_frame_id == 'body'
        assert stamp_nanoseconds(message.header.stamp) == nanoseconds
        np.testing.assert_array_equal(vector(message.transform.translation), state.position)
        np.testing.assert_array_equal(quaternion(message.transform.rotation), state.orientation)
        # The transform maps body-frame coordinates into world coordinates: the body-frame
        # point at the COM offset r lands at x + R r.
        r_body = np.array([0.2, -0.1, 0.05])
        mapped = (Rotation.from_quat(quaternion(message.transform.rotation)).apply(r_body)
                  + vector(message.transform.translation))
        np.testing.assert_allclose(
            mapped, np.add(state.position, Rotation.from_quat(state.orientation).apply(r_body)),
            rtol=0.0, atol=1e-12)


@pytest.mark.parametrize('seed', range(3))
def test_odometry_has_the_pose_in_the_parent_and_the_twist_in_the_child_frame(seed):
    """Odometry: COM pose in frame_id, v and w rotated into the body frame by R^T."""
    for k, state in enumerate(random_states(20, seed)):
        nanoseconds = 42_000_000_007 + k
        message = odometry_message(state, frame_id='map', body_frame_id='box',
                                   nanoseconds=nanoseconds)
        assert message.header.frame_id == 'map'
        assert message.child_frame_id == 'box'
        assert stamp_nanoseconds(message.header.stamp) == nanoseconds
        np.testing.assert_array_equal(vector(message.pose.pose.position), state.position)
        np.testing.assert_array_equal(quaternion(message.pose.pose.orientation),
                                      state.orientation)
        to_body = Rotation.from_quat(state.orientation).inv()
        np.testing.assert_allclose(vector(message.twist.twist.linear),
                                   to_body.apply(state.linear_velocity), rtol=0.0, atol=1e-12)
        np.testing.assert_allclose(vector(message.twist.twist.angular),
                                   to_body.apply(state.angular_velocity), rtol=0.0, atol=1e-12)
        # Rotating back recovers the world-frame velocities of the state.
        world = Rotation.from_quat(quaternion(message.pose.pose.orientation))
        np.testing.assert_allclose(world.apply(vector(message.twist.twist.linear)),
                                   state.linear_velocity, rtol=0.0, atol=1e-12)
        assert not any(message.pose.covariance) and not any(message.twist.covariance)


def test_fill_variants_reuse_one_message_and_keep_its_header():
    """``fill_transform`` / ``fill_odometry`` overwrite the body fields and leave the header."""
    states = list(random_states(5, 7))
    transform = transform_message(states[0], frame_id='world', body_frame_id='body',
                                  nanoseconds=5)
    odometry = odometry_message(states[0], frame_id='world', body_frame_id='body',
                                nanoseconds=5)
    for state in states[1:]:
        fill_transform(transform, state)
        fill_odometry(odometry, state)
        expected_transform = transform_message(state, frame_id='world', body_frame_id='body',
                                               nanoseconds=5)
        expected_odometry = odometry_message(state, frame_id='world', body_frame_id='body',
                                             nanoseconds=5)
        assert transform == expected_transform
        assert odometry == expected_odometry


def tumbling_simulation(with_target: bool) -> MouseSimulation:
    """
    Return a simulation of an asymmetric box that tumbles while it flies or is dragged.

    One substep per step, so that a step's position and orientation increments are exactly
    h v and, dragged, exp(h w) for the velocities the step ends with (free, the Cayley rotation
    of the midpoint velocity): finite differences of the poses then recover the published
    velocities to rounding, which makes the frame check sharp.
    """
    body = RigidBody.solid_box(2.0, (0.4, 0.2, 0.1))
    settings = Settings(body=body, constraint=MouseConstraint(anchor=(0.2, 0.1, 0.05)),
                        substeps=1)
    initial = BodyState(
        (0.0, 0.0, 1.0),
        tuple(Rotation.from_rotvec([0.7, -1.1, 0.4]).as_quat().tolist()),
        (0.8, -0.3, 2.0),
        (3.0, 1.5, -6.0),
    ).validated()
    simulation = MouseSimulation(settings, initial)
    if with_target:
        simulation.target = (0.5, 0.2, 1.2)
    return simulation


@pytest.mark.parametrize('with_target', [False, True], ids=['free', 'dragged'])
def test_twist_frames_match_finite_differences_of_the_published_poses(with_target):
    """
    The ``twist`` topic is the world-frame velocity, odometry's twist the body-frame one.

    From two successive published odometry poses: v_world = (x1 - x0) / h, w_world the rotation
    vector of R1 R0^T over h, and their body-frame versions R1^T v_world and R1^T w_world (equal
    to the rotation vector of R0^T R1 over h). Each is compared with what the builders published
    at the second pose; the world and body values differ by far more than the tolerance, so a
    twist in the wrong frame fails.
    """
    simulation = tumbling_simulation(with_target)
    odometry, twist = Odometry(), TwistStamped()
    previous = previous_body_w = None
    smallest_frame_gap = np.inf
    for _ in range(400):
        state = simulation.step(STEP)
        fill_odometry(odometry, state)
        fill_twist(twist, state)
        position = vector(odometry.pose.pose.position)
        rotation = Rotation.from_quat(quaternion(odometry.pose.pose.orientation))
        if previous is not None:
            previous_position, previous_rotation = previous
            v_world = (position - previous_position) / STEP
            w_world = (rotation * previous_rotation.inv()).as_rotvec() / STEP
            w_body_increment = (previous_rotation.inv() * rotation).as_rotvec() / STEP
            v_body = rotation.inv().apply(v_world)
            w_body = rotation.inv().apply(w_world)
            np.testing.assert_allclose(w_body_increment, w_body, rtol=0.0, atol=1e-7)

            np.testing.assert_allclose(vector(twist.twist.linear), v_world, rtol=0.0, atol=1e-7)
            np.testing.assert_allclose(vector(odometry.twist.twist.linear), v_body, rtol=0.0,
                                       atol=1e-7)
            if with_target:
                np.testing.assert_allclose(vector(twist.twist.angular), w_world, rtol=0.0,
                                           atol=1e-7)
                np.testing.assert_allclose(vector(odometry.twist.twist.angular), w_body,
                                           rtol=0.0, atol=1e-7)
            else:
                # A free body turns by the Cayley rotation of its midpoint velocity, the mean
                # of the body-frame velocities before and after (docs/math.md), so that its
                # angular momentum is kept: the increment is that rotation, and the published
                # twists are the world and body frame of the same velocity.
                midpoint = 0.5 * (previous_body_w + vector(odometry.twist.twist.angular))
                turn = 2.0 * np.arctan(0.5 * STEP * np.linalg.norm(midpoint)) / STEP
                np.testing.assert_allclose(
                    w_body_increment, turn * midpoint / np.linalg.norm(midpoint), rtol=0.0,
                    atol=1e-7)
                np.testing.assert_allclose(rotation.apply(vector(odometry.twist.twist.angular)),
                                           vector(twist.twist.angular), rtol=0.0, atol=1e-12)
            smallest_frame_gap = min(smallest_frame_gap,
                                     np.linalg.norm(v_world - v_body),
                                     np.linalg.norm(w_world - w_body))
        previous = (position, rotation)
        previous_body_w = vector(odometry.twist.twist.angular)
    assert smallest_frame_gap > 0.1
