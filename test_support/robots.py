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

"""Robots for the tests: a double pendulum written here, and real robots' URDFs as shipped."""

import math
import os
import pathlib
import site
from typing import Optional, Tuple

import numpy as np

G = 9.80665


def rod_link(name: str, mass: float, length: float, *, extra: str = '') -> str:
    """Return a slender rod hanging along -z from its joint: COM at length / 2."""
    moment = mass * length * length / 12.0
    return (f'<link name="{name}"><inertial><origin xyz="0 0 {-length / 2}"/>'
            f'<mass value="{mass}"/><inertia ixx="{moment}" iyy="{moment}" izz="1e-6" ixy="0" '
            f'ixz="0" iyz="0"/></inertial><collision><origin xyz="0 0 {-length / 2}"/>'
            f'<geometry><box size="0.04 0.04 {length}"/></geometry></collision>{extra}</link>')


def double_pendulum(length: Tuple[float, float] = (0.5, 0.5),
                    mass: Tuple[float, float] = (1.0, 1.0), *, kind: str = 'continuous',
                    damping: float = 0.0, limit: str = '') -> str:
    """Return a URDF of two rods on joints about y, ``shoulder`` and ``elbow``, and a ``tip``."""
    dynamics = f'<dynamics damping="{damping}"/>' if damping else ''
    return (
        f'<robot name="double_pendulum"><link name="base"/>'
        f'{rod_link("upper", mass[0], length[0])}{rod_link("lower", mass[1], length[1])}'
        '<link name="tip"/>'
        f'<joint name="shoulder" type="{kind}"><parent link="base"/><child link="upper"/>'
        f'<axis xyz="0 1 0"/>{limit}{dynamics}</joint>'
        f'<joint name="elbow" type="{kind}"><parent link="upper"/><child link="lower"/>'
        f'<origin xyz="0 0 {-length[0]}"/><axis xyz="0 1 0"/>{limit}{dynamics}</joint>'
        '<joint name="tip_joint" type="fixed"><parent link="lower"/><child link="tip"/>'
        f'<origin xyz="0 0 {-length[1]}"/></joint></robot>')


def double_pendulum_tip(times: np.ndarray, start: float, length=(0.5, 0.5), mass=(1.0, 1.0),
                        gravity: float = G) -> np.ndarray:
    """
    Return the tip's (x, z) at ``times``: scipy on the closed equations of two rods.

    Absolute angles phi1, phi2 from the downward vertical (a turn about +y takes -z to -x):
    Lagrange's equations of two uniform rods of masses m_i, lengths l_i, COMs at l_i / 2 and
    moments m_i l_i^2 / 12, written out here, independent of any robot library.
    """
    from scipy.integrate import solve_ivp
    (l1, l2), (m1, m2) = length, mass
    c1, c2 = l1 / 2, l2 / 2
    i1, i2 = m1 * l1 * l1 / 12, m2 * l2 * l2 / 12

    def rates(_t, y):
        p1, p2, w1, w2 = y
        a11, a12, a22 = m1 * c1 * c1 + i1 + m2 * l1 * l1, m2 * l1 * c2 * math.cos(p1 - p2), \
            m2 * c2 * c2 + i2
        b1 = -m2 * l1 * c2 * math.sin(p1 - p2) * w2 * w2 - (m1 * c1 + m2 * l1) * gravity \
            * math.sin(p1)
        b2 = m2 * l1 * c2 * math.sin(p1 - p2) * w1 * w1 - m2 * c2 * gravity * math.sin(p2)
        det = a11 * a22 - a12 * a12
        return [w1, w2, (a22 * b1 - a12 * b2) / det, (a11 * b2 - a12 * b1) / det]

    solution = solve_ivp(rates, (0.0, float(times[-1])), [start, start, 0.0, 0.0],
                         t_eval=times, rtol=1e-11, atol=1e-12, method='DOP853')
    p1, p2 = solution.y[0], solution.y[1]
    return np.stack([-l1 * np.sin(p1) - l2 * np.sin(p2), -l1 * np.cos(p1) - l2 * np.cos(p2)], 1)


def robot_collection() -> Optional[pathlib.Path]:
    """Return the public robot-description collection's prefix (example-robot-data), or None."""
    for root in site.getsitepackages() + [site.getusersitepackages()]:
        prefix = pathlib.Path(root) / 'cmeel.prefix'
        if (prefix / 'share' / 'example-robot-data' / 'robots').is_dir():
            return prefix
    return None


def collection_urdf(relative: str) -> pathlib.Path:
    """Return a URDF of the collection, e.g. ``panda_description/urdf/panda.urdf``."""
    prefix = robot_collection()
    assert prefix is not None, 'example-robot-data is not installed (requirements/test.txt)'
    return prefix / 'share' / 'example-robot-data' / 'robots' / relative


def collection_environment() -> dict:
    """Return os.environ with the collection's ament index on AMENT_PREFIX_PATH."""
    environment = dict(os.environ)
    prefix = str(robot_collection())
    current = environment.get('AMENT_PREFIX_PATH')
    environment['AMENT_PREFIX_PATH'] = prefix + (os.pathsep + current if current else '')
    return environment
