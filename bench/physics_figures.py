#!/usr/bin/env python3
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
The physics figures the docs quote, computed on the core: no ROS, no peers, a few seconds.

``python -m bench.physics_figures`` (from the repository's root) prints them; the suite runs it
as its first section.

- Corner pendulum: the box (2 kg, 0.4 x 0.2 x 0.1 m) hung rigidly by its corner, released at
  rest 20 degrees from hanging, stepped at h = 1 ms for 5 s, against the exact motion
  (``test_support.reference_dynamics``, scipy DOP853 at 1e-12): COM RMS error with the leapfrog
  start (``MouseSimulation`` moves the given velocities back half a step before its first
  step) and without it. "Without" is the same run started from the state whose velocities are
  those the exact motion has at t = h / 2 (to first order in h: the angular acceleration at
  rest times h / 2): moved back half a step they are the rest velocities, so the solver then
  starts with v(-h / 2) = v(0), as a leapfrog started without the half step does.
- Gyroscopic step: a free box (1 kg, 0.4 x 0.25 x 0.1 m) spinning at 6 rad/s (and 50 rad/s)
  about its intermediate axis, with 0.01 rad/s about each of the others (the body frame
  angular velocity (0.01, 6, 0.01) of the tests), 10 s at h = 1 ms: the kinetic energy
  lost with one backward-Euler step per substep (Bullet's and Bounce's, written out below) and
  with the implicit midpoint rule of ``physics.gyroscopic``.
- Soft gains: a spring of 5 Hz and damping ratio 0.1 at h = 1 ms. The anchor error of a point
  mass under one soft step is the linear map e' = e + h v', v' = (1 - a) v - b e; the damping
  ratio it realizes is measured from the decay of its free ringing (the logarithmic decrement
  over successive peaks), for Box2D's ``b2MakeSoft`` gains
  (``test_support.physics_reference.box2d_soft_gains``) and for the core's exact gains, and for
  the core itself (a ``MouseSimulation`` with the anchor at the COM, its error along x).
"""

import json
import math
import sys
import time

import numpy as np
from scipy.spatial.transform import Rotation

from mouse_constraint_ros.physics import BodyState, MouseConstraint, MouseSimulation
from mouse_constraint_ros.physics import RigidBody, Settings
from mouse_constraint_ros.physics.gyroscopic import gyroscopic_step
from mouse_constraint_ros.physics.mouse_joint import soft_gains
from test_support.physics_reference import box2d_soft_gains
from test_support.reference_dynamics import GRAVITY
from test_support.reference_dynamics import hanging_rotation
from test_support.reference_dynamics import pendulum_com_path
from test_support.reference_dynamics import pivot_inertia

H = 0.001
PENDULUM_BOX = RigidBody.solid_box(2.0, (0.4, 0.2, 0.1))
CORNER = np.array([0.2, 0.1, 0.05])
PIVOT = np.array([0.0, 0.0, 1.0])
TILT_DEGREES = 20.0
PENDULUM_SECONDS = 5.0
SPIN_BOX = RigidBody.solid_box(1.0, (0.4, 0.25, 0.1))
# The spin of the intermediate-axis test: about body y, with 0.01 rad/s about x and z.
OFF_AXIS_SPIN = 0.01
SPIN_SECONDS = 10.0
SPINS = (6.0, 50.0)
SPRING_HZ = 5.0
SPRING_DAMPING_RATIO = 0.1


def pendulum_rms_mm(staggered_start: bool) -> float:
    """Return the corner pendulum's COM RMS error (mm) over 5 s, with or without the start."""
    orientation = (Rotation.from_rotvec([math.radians(TILT_DEGREES), 0.0, 0.0])
                   * hanging_rotation(CORNER))
    position = PIVOT - orientation.apply(CORNER)
    velocity, spin = np.zeros(3), np.zeros(3)
    if not staggered_start:
        # The velocities at t = h / 2 to first order: I_p w' = torque of the weight about the
        # pivot (body frame), and the COM turns about the pivot.
        inertia = pivot_inertia(PENDULUM_BOX.mass, PENDULUM_BOX.inertia, CORNER)
        weight = orientation.inv().apply([0.0, 0.0, -PENDULUM_BOX.mass * GRAVITY])
        spin = orientation.apply(0.5 * H * np.linalg.solve(inertia, np.cross(-CORNER, weight)))
        velocity = np.cross(spin, position - PIVOT)
    settings = Settings(PENDULUM_BOX, MouseConstraint(anchor=tuple(CORNER)),
                        gravity=(0.0, 0.0, -GRAVITY))
    simulation = MouseSimulation(settings, BodyState(tuple(position), tuple(orientation.as_quat()),
                                                     tuple(velocity), tuple(spin)))
    simulation.target = tuple(PIVOT)
    ticks = int(round(PENDULUM_SECONDS / H))
    path = [simulation.state.position] + [simulation.step(H).position for _ in range(ticks)]
    exact = pendulum_com_path(PENDULUM_BOX.mass, PENDULUM_BOX.inertia, CORNER, PIVOT,
                              orientation, H * np.arange(ticks + 1))
    return 1e3 * float(np.sqrt(np.mean(np.sum((np.array(path) - exact) ** 2, axis=1))))


def _skew(v: np.ndarray) -> np.ndarray:
    return np.array([[0.0, -v[2], v[1]], [v[2], 0.0, -v[0]], [-v[1], v[0], 0.0]])


def backward_euler_gyroscopic(inertia: np.ndarray, w: np.ndarray, h: float) -> np.ndarray:
    """
    Return one backward-Euler step of I dw/dt + w x (I w) = 0, linearized at w (Bullet, Bounce).

    w1 = w0 - J^-1 h (w0 x I w0), with J = I + h ([w0]x I - [I w0]x).
    """
    jacobian = inertia + h * (_skew(w) @ inertia - _skew(inertia @ w))
    return w - np.linalg.solve(jacobian, h * np.cross(w, inertia @ w))


def spin_energy_lost(spin: float) -> dict:
    """Return the fraction of kinetic energy each gyroscopic step loses over 10 s at h."""
    xx, xy, xz, yy, yz, zz = SPIN_BOX.inertia
    inertia = np.array([[xx, xy, xz], [xy, yy, yz], [xz, yz, zz]])
    w0 = np.array([OFF_AXIS_SPIN, spin, OFF_AXIS_SPIN])
    steps = int(round(SPIN_SECONDS / H))
    energy0 = 0.5 * w0 @ inertia @ w0
    backward, midpoint = w0.copy(), tuple(w0)
    for _ in range(steps):
        backward = backward_euler_gyroscopic(inertia, backward, H)
        midpoint = gyroscopic_step(SPIN_BOX.inertia, midpoint, H)
    midpoint = np.array(midpoint)
    return {'backward_euler': 1.0 - 0.5 * backward @ inertia @ backward / energy0,
            'implicit_midpoint': 1.0 - 0.5 * midpoint @ inertia @ midpoint / energy0}


def damping_ratio_of(errors: np.ndarray) -> float:
    """Return the damping ratio of a free damped ringing from its successive positive peaks."""
    inner = errors[1:-1]
    peaks = np.flatnonzero((inner > errors[:-2]) & (inner >= errors[2:]) & (inner > 0.0)) + 1
    decrement = float(np.mean(np.diff(np.log(errors[peaks])))) * -1.0
    return decrement / math.sqrt(4.0 * math.pi ** 2 + decrement ** 2)


def map_ringing(gains, seconds: float = 1.0) -> np.ndarray:
    """Return the anchor error of a point mass under the soft step's map, released at e = 1."""
    a, b = gains
    e, v, errors = 1.0, 0.0, []
    for _ in range(int(round(seconds / H))):
        v = (1.0 - a) * v - b * e
        e += H * v
        errors.append(e)
    return np.array(errors)


def core_ringing(seconds: float = 1.0) -> np.ndarray:
    """Return the x error of the core's soft anchor at the COM, released 1 cm off, no gravity."""
    constraint = MouseConstraint(frequency_hz=SPRING_HZ, damping_ratio=SPRING_DAMPING_RATIO)
    simulation = MouseSimulation(Settings(RigidBody.solid_box(1.0, (0.1, 0.1, 0.1)), constraint,
                                          gravity=(0.0, 0.0, 0.0)))
    simulation.target = (0.01, 0.0, 0.0)
    return np.array([simulation.step(H).position[0] - 0.01
                     for _ in range(int(round(seconds / H)))])


def figures() -> dict:
    """Return every figure, keyed by name."""
    spins = {spin: spin_energy_lost(spin) for spin in SPINS}
    return {
        'pendulum_rms_mm_leapfrog_start': pendulum_rms_mm(True),
        'pendulum_rms_mm_no_leapfrog_start': pendulum_rms_mm(False),
        **{f'energy_lost_backward_euler_{spin:g}_rad_s': lost['backward_euler']
           for spin, lost in spins.items()},
        **{f'energy_lost_implicit_midpoint_{spin:g}_rad_s': lost['implicit_midpoint']
           for spin, lost in spins.items()},
        'damping_ratio_box2d_gains': damping_ratio_of(map_ringing(
            box2d_soft_gains(SPRING_HZ, SPRING_DAMPING_RATIO, H))),
        'damping_ratio_exact_gains': damping_ratio_of(map_ringing(
            soft_gains(SPRING_HZ, SPRING_DAMPING_RATIO, H))),
        'damping_ratio_core': damping_ratio_of(core_ringing()),
    }


def run(quick: bool = False) -> dict:
    """Return the section (``quick`` changes nothing: it takes seconds)."""
    start = time.perf_counter()
    values = figures()
    command = 'python -m bench.physics_figures'
    rows = [
        {'figure': f'corner pendulum, {TILT_DEGREES:g} deg, {PENDULUM_SECONDS:g} s at h = 1 ms: '
                   'COM RMS error vs the exact motion, leapfrog start',
         'value': f'{values["pendulum_rms_mm_leapfrog_start"]:.4f} mm'},
        {'figure': 'the same without the leapfrog start (velocities taken as half-step ones)',
         'value': f'{values["pendulum_rms_mm_no_leapfrog_start"]:.4f} mm'},
        {'figure': 'ratio without / with',
         'value': f'{values["pendulum_rms_mm_no_leapfrog_start"] / values["pendulum_rms_mm_leapfrog_start"]:.0f}x'},  # noqa: E501
    ]
    for spin in SPINS:
        rows.append({
            'figure': f'free box at {spin:g} rad/s near its intermediate axis, '
                      f'{SPIN_SECONDS:g} s at h = 1 ms: kinetic energy lost, one backward-Euler '
                      'gyroscopic step',
            'value': f'{100 * values[f"energy_lost_backward_euler_{spin:g}_rad_s"]:.1f} %'})
        rows.append({
            'figure': f'the same at {spin:g} rad/s, implicit midpoint (the core)',
            'value': f'{values[f"energy_lost_implicit_midpoint_{spin:g}_rad_s"]:.1e}'})
    rows += [
        {'figure': f'soft spring {SPRING_HZ:g} Hz, damping ratio {SPRING_DAMPING_RATIO:g}, '
                   'h = 1 ms: effective damping ratio, Box2D b2MakeSoft gains',
         'value': f'{values["damping_ratio_box2d_gains"]:.4f}'},
        {'figure': 'the same, the exact gains (soft_gains)',
         'value': f'{values["damping_ratio_exact_gains"]:.4f}'},
        {'figure': 'the same, measured on MouseSimulation',
         'value': f'{values["damping_ratio_core"]:.4f}'},
    ]
    return {
        'title': 'Physics figures quoted by the docs (the core, no ROS)',
        'text': f'`{command}`; see its docstring for how each is computed.',
        'columns': [['figure', 'figure', ''], ['value', 'value', '']],
        'rows': rows,
        'figures': values,
        'elapsed_s': time.perf_counter() - start,
    }


def main() -> int:
    """Print the figures as a table, then as JSON."""
    from bench.common import section_markdown
    section = run()
    print(section_markdown(section))
    print(json.dumps(section['figures'], indent=1))
    return 0


if __name__ == '__main__':
    sys.exit(main())
