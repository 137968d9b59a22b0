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

"""The mouse constraint's Jacobian, effective mass and gains against first principles."""

import math

import numpy as np
import pytest
from scipy.spatial.transform import Rotation

from mouse_constraint_ros.physics.algebra import rotation_matrix
from mouse_constraint_ros.physics.body import RigidBody
from mouse_constraint_ros.physics.mouse_joint import effective_mass
from mouse_constraint_ros.physics.mouse_joint import MouseConstraint
from mouse_constraint_ros.physics.mouse_joint import soft_gains
from test_support.physics_reference import box2d_soft_gains
from test_support.physics_reference import jacobian
from test_support.physics_reference import solve_effective_mass


def random_body(rng: np.random.Generator) -> RigidBody:
    """Return a body with a random realizable inertia, rotated off its principal axes."""
    while True:
        moments = rng.uniform(0.05, 2.0, 3)
        if moments.sum() >= 2.0 * moments.max():
            break
    axes = Rotation.random(random_state=rng).as_matrix()
    m = axes @ np.diag(moments) @ axes.T
    return RigidBody(rng.uniform(0.1, 10.0), (m[0, 0], m[0, 1], m[0, 2], m[1, 1], m[1, 2],
                                              m[2, 2]))


def symmetric(s) -> np.ndarray:
    """Return the 3x3 of a symmetric 6-tuple."""
    xx, xy, xz, yy, yz, zz = s
    return np.array([[xx, xy, xz], [xy, yy, yz], [xz, yz, zz]])


def test_jacobian_is_the_derivative_of_the_position_error():
    """Test 1: J V against a central difference of C(t) = x(t) + R(t) r_local - x_mouse."""
    rng = np.random.default_rng(1)
    step = 1e-5
    for _ in range(200):
        r_local = rng.uniform(-1.0, 1.0, 3)
        x0, v, w = rng.normal(size=(3, 3))
        rotation0 = Rotation.random(random_state=rng)
        target = rng.normal(size=3)

        def error(t):
            rotation = Rotation.from_rotvec(w * t) * rotation0
            return x0 + v * t + rotation.apply(r_local) - target

        numeric = (error(step) - error(-step)) / (2.0 * step)
        r = rotation0.apply(r_local)
        analytic = jacobian(r) @ np.concatenate([v, w])
        assert np.linalg.norm(analytic - numeric) <= 1e-6 * np.linalg.norm(numeric)
        # Eq. 1.3 as printed computes v + r x w, which misses whenever w is not parallel to r.
        printed = v + np.cross(r, w)
        assert np.linalg.norm(printed - numeric) > 1e-3 * np.linalg.norm(numeric)


def test_effective_mass_matches_the_assembled_product():
    """Test 2: eq. 1.10 equals J M^-1 J^T from the 6x6 M^-1 of eq. 1.8; symmetric, SPD."""
    rng = np.random.default_rng(2)
    for _ in range(200):
        body = random_body(rng)
        rotation = Rotation.random(random_state=rng)
        matrix = tuple(rotation.as_matrix().ravel())
        r = rotation.apply(rng.uniform(-1.0, 1.0, 3))
        inverse_inertia_world = body.world_inverse_inertia(matrix)
        inverse_mass_matrix = np.zeros((6, 6))
        inverse_mass_matrix[:3, :3] = np.eye(3) / body.mass
        inverse_mass_matrix[3:, 3:] = (rotation.as_matrix() @ np.linalg.inv(
            symmetric(body.inertia)) @ rotation.as_matrix().T)
        j = jacobian(tuple(r))
        assembled = j @ inverse_mass_matrix @ j.T
        k = symmetric(effective_mass(body.inverse_mass, inverse_inertia_world, tuple(r)))
        np.testing.assert_allclose(k, assembled, rtol=1e-12, atol=1e-12 * np.abs(assembled).max())
        np.testing.assert_array_equal(k, k.T)
        assert np.linalg.eigvalsh(k).min() > 0.0
        b = rng.normal(size=3)
        np.testing.assert_allclose(k @ solve_effective_mass(tuple(k[np.triu_indices(3)]), b), b,
                                   rtol=1e-10, atol=1e-12)


def test_world_inverse_inertia_is_the_rotated_inverse():
    """I_w^-1 = R I_b^-1 R^T, with rotation_matrix agreeing with scipy's (x, y, z, w) order."""
    rng = np.random.default_rng(3)
    for _ in range(50):
        body = random_body(rng)
        rotation = Rotation.random(random_state=rng)
        matrix = rotation_matrix(tuple(rotation.as_quat()))
        np.testing.assert_allclose(np.reshape(matrix, (3, 3)), rotation.as_matrix(), atol=1e-15)
        expected = (rotation.as_matrix() @ np.linalg.inv(symmetric(body.inertia))
                    @ rotation.as_matrix().T)
        np.testing.assert_allclose(symmetric(body.world_inverse_inertia(matrix)), expected,
                                   rtol=1e-12, atol=1e-12)


def soft_step_map(gains, h):
    """Return the soft step's linear map on (error, velocity) for a point mass."""
    a, b = gains
    return np.array([[1.0 - h * b, h * (1.0 - a)], [-b, 1.0 - a]])


@pytest.mark.parametrize('frequency, damping_ratio, h', [
    (5.0, 0.1, 1e-3), (5.0, 0.0, 1e-3), (2.0, 1.0, 1e-3), (30.0, 3.0, 1 / 60), (200.0, 0.5, 1e-2)])
def test_soft_gains_place_the_discrete_roots_exactly(frequency, damping_ratio, h):
    """
    The soft step's eigenvalues are exp(s h) for the continuous spring's roots s.

    Compared through the characteristic polynomial (trace, determinant): a double root, as at
    critical damping, is too sensitive to rounding to compare one by one.
    """
    omega = 2.0 * math.pi * frequency
    expected = np.exp(np.roots([1.0, 2.0 * damping_ratio * omega, omega * omega]) * h)
    step_map = soft_step_map(soft_gains(frequency, damping_ratio, h), h)
    assert np.trace(step_map) == pytest.approx(expected.sum().real, rel=1e-12, abs=1e-14)
    assert np.linalg.det(step_map) == pytest.approx(expected.prod().real, rel=1e-12, abs=1e-14)
    assert np.abs(np.linalg.eigvals(step_map)).max() <= 1.0 + 1e-7


def test_soft_gains_agree_with_box2d_to_first_order():
    """As h omega -> 0 the exact gains approach b2MakeSoft's; the gap shrinks like h omega."""
    gaps = []
    for h in (1e-2, 1e-3, 1e-4):
        ours = np.array(soft_gains(5.0, 0.7, h))
        box2d = np.array(box2d_soft_gains(5.0, 0.7, h))
        gaps.append(np.abs(ours / box2d - 1.0).max())
    assert gaps[0] > gaps[1] > gaps[2]
    assert gaps[2] < 5e-3
    assert gaps[1] / gaps[2] == pytest.approx(10.0, rel=0.1)


def test_rigid_gains_are_the_corrected_baumgarte_impulse():
    """Rigid mode is eq. 1.5 with -delta/h: gains (1, delta / h)."""
    constraint = MouseConstraint(baumgarte=0.3)
    assert constraint.rigid
    assert constraint.gains(0.002) == (1.0, 0.3 / 0.002)
    assert not MouseConstraint(frequency_hz=1.0).rigid
