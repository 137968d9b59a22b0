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
Exact reference motions for the physics tests and the accuracy benchmark (numpy + scipy).

The corner pendulum is a rigid body on an ideal ball joint: Euler's equations about the pivot in
the body frame, integrated by scipy's DOP853 at tight tolerances. Nothing here shares code with
the solver under test except the body's inertia numbers.
"""

from typing import Tuple

import numpy as np
from scipy.integrate import solve_ivp
from scipy.linalg import eigh
from scipy.spatial.transform import Rotation

GRAVITY = 9.81


def inertia_matrix(inertia6) -> np.ndarray:
    """Return the 3x3 matrix of an inertia in URDF order (ixx, ixy, ixz, iyy, iyz, izz)."""
    xx, xy, xz, yy, yz, zz = inertia6
    return np.array([[xx, xy, xz], [xy, yy, yz], [xz, yz, zz]])


def hanging_rotation(anchor: np.ndarray) -> Rotation:
    """Return the orientation in which the COM hangs straight below an anchor (body frame)."""
    up = np.array([0.0, 0.0, 1.0])
    rotation, _ = Rotation.align_vectors([up], [anchor / np.linalg.norm(anchor)])
    return rotation


def pivot_inertia(mass: float, inertia6, anchor: np.ndarray) -> np.ndarray:
    """Return the body-frame inertia about the anchor (parallel-axis theorem)."""
    d = np.asarray(anchor, dtype=float)
    return inertia_matrix(inertia6) + mass * (d @ d * np.eye(3) - np.outer(d, d))


def pendulum_com_path(mass: float, inertia6, anchor, pivot, orientation0: Rotation,
                      times: np.ndarray, gravity: float = GRAVITY) -> np.ndarray:
    """
    Return the COM positions at ``times`` of a body on a ball joint, released at rest.

    :param anchor: the joint's position in the body frame, from the COM.
    :param pivot: the joint's fixed world position.
    :param orientation0: the initial orientation.
    """
    anchor = np.asarray(anchor, dtype=float)
    pivot = np.asarray(pivot, dtype=float)
    inertia = pivot_inertia(mass, inertia6, anchor)
    inverse = np.linalg.inv(inertia)
    weight = np.array([0.0, 0.0, -mass * gravity])

    def derivative(_t, y):
        q = y[:4] / np.linalg.norm(y[:4])
        w = y[4:]
        rotation = Rotation.from_quat(q).as_matrix()
        # Torque about the pivot of the weight at the COM, x_com - pivot = -R anchor.
        torque = np.cross(-anchor, rotation.T @ weight)
        w_dot = inverse @ (torque - np.cross(w, inertia @ w))
        x, y_, z, s = q
        wx, wy, wz = w
        # dq/dt = q (x) (w_body, 0) / 2, quaternions as (x, y, z, w).
        q_dot = 0.5 * np.array([
            s * wx + y_ * wz - z * wy,
            s * wy + z * wx - x * wz,
            s * wz + x * wy - y_ * wx,
            -x * wx - y_ * wy - z * wz,
        ])
        return np.concatenate([q_dot, w_dot])

    y0 = np.concatenate([orientation0.as_quat(), np.zeros(3)])
    solution = solve_ivp(derivative, (times[0], times[-1]), y0, method='DOP853',
                         t_eval=times, rtol=1e-12, atol=1e-12)
    assert solution.success, solution.message
    rotations = Rotation.from_quat((solution.y[:4] / np.linalg.norm(solution.y[:4], axis=0)).T)
    return pivot - rotations.apply(anchor)


def small_oscillation_modes(mass: float, inertia6, anchor,
                            gravity: float = GRAVITY) -> Tuple[np.ndarray, np.ndarray]:
    """
    Return the periods (s) and world rotation-vector shapes of the two swinging modes.

    Linearized about hanging, with the COM a distance d below the pivot, small rotations theta
    obey I_p theta'' = -m g d diag(1, 1, 0) theta, with I_p the pivot inertia in the world frame;
    the generalized eigenproblem gives omega^2 (and the zero-frequency yaw).
    """
    anchor = np.asarray(anchor, dtype=float)
    hanging = hanging_rotation(anchor).as_matrix()
    inertia_world = hanging @ pivot_inertia(mass, inertia6, anchor) @ hanging.T
    stiffness = mass * gravity * np.linalg.norm(anchor) * np.diag([1.0, 1.0, 0.0])
    omega_squared, shapes = eigh(stiffness, inertia_world)
    swinging = omega_squared > 1e-9
    return 2.0 * np.pi / np.sqrt(omega_squared[swinging]), shapes[:, swinging].T
