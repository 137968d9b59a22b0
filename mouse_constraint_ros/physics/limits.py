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
The ranges of the physical settings, each derived from what the float arithmetic of a step needs.

A float holds magnitudes from about 2.2e-308 (the smallest normal number) to 1.8e308. The step
forms products and quotients of the settings, so each setting is bounded where one of those
stops being a finite, normal, well-conditioned float at some step size h in
[MIN_STEP, MAX_STEP]. Every bound is decades beyond any physical use; within them the
quantities named below stay finite with margins of 1e30 and more.

The step's largest velocities come from the position correction, b |C| per substep with
b <= 4 / h (soft mode; delta / h <= 1 / h rigid) and the anchor error |C| up to about
3 MAX_DISTANCE when a target is set (the body, its anchor and the target each within
MAX_DISTANCE of the origin): ``MAX_CORRECTION_SPEED``. The bounds below keep the impulses,
forces and energies of such a correction finite.
"""

# Step sizes outside [MIN_STEP, MAX_STEP] seconds are rejected: below, the gains b ~ 1 / h
# overflow; above, the step is no simulation step.
MIN_STEP = 1e-9
MAX_STEP = 1.0

# The farthest a length may reach (m): the anchor from the COM, a box edge, the initial position
# and the workspace radius. Positions are floats, whose resolution at 1e12 m is 1.2e-4 m, the
# coarsest at which dragging a body by a point still means anything.
MAX_DISTANCE = 1e12

# The largest velocity change one position correction can ask for (m/s): b |C| with b <= 4 / h.
MAX_CORRECTION_SPEED = 4.0 / MIN_STEP * 3.0 * MAX_DISTANCE

# The largest condition number accepted for the inertia (largest over smallest principal moment)
# and for the effective mass K = m^-1 I3 + [r]x I_w^-1 [r]x^T, which is at most
# 1 + m |r|^2 / I_min. The step factors K by Cholesky (its body-frame form, once per settings);
# rounding perturbs K by some 1e-16 of its largest eigenvalue, which must stay far below its
# smallest, 1 / m, or a pivot goes negative (a math domain error) or zero (a division by zero).
# 1e12 leaves a factor 1e4 and solves K to 1e-4 at worst.
MAX_CONDITION = 1e12

# Principal moments of inertia (kg m^2). The gyroscopic step inverts its Jacobian
# J = I + (h / 2) ([w]x I - [I w]x) by Cramer's rule: the determinant is a product of three
# moments, which must be a normal float and nonzero. Within [1e-90, 1e90] it lies within
# [1e-270, 1e270], leaving 1e38 on either side for the velocity terms of J; 1 / I <= 1e90.
MIN_MOMENT = 1e-90
MAX_MOMENT = 1e90

# Mass (kg). The effective mass K is up to MAX_CONDITION / m, at most 1e112; the impulse of a
# correction, m b |C| <= m MAX_CORRECTION_SPEED, its force (the impulse over h) and the kinetic
# energy it gives, m MAX_CORRECTION_SPEED^2 / 2, stay below 1e145; and the angular speed it can
# give, MAX_CORRECTION_SPEED sqrt(m / I_min) <= 1e118 rad/s, keeps its square (the orientation
# update takes |w|) below 1e236.
MIN_MASS = 1e-100
MAX_MASS = 1e100

# Gravity (m/s^2): about the surface gravity of a neutron star, the strongest a body can rest
# in. It adds at most 1e12 m/s per substep, far below MAX_CORRECTION_SPEED, so the bounds on
# mass hold with it; a free fall at it takes 1e148 s to leave the float range.
MAX_ACCELERATION = 1e12

# The floor's Coulomb coefficient: beyond any material (rubber on rubber is about 1 to 2), and
# low enough that mu times a normal impulse stays finite.
MAX_FRICTION = 1e6
# Sequential-impulse sweeps over the floor's contacts per substep: each sweep costs about a
# microsecond per contact in plain Python.
MAX_CONTACT_ITERATIONS = 1000
