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
The prepare stage of a step: what its substeps take from the settings, computed once per change.

As Box2D splits a joint into a prepare and a solve stage, ``MouseSimulation.step`` takes a
``StepPlan`` made once per settings and substep length: the kernel's coefficients
(``kernel.coefficients``), the floor's (``floor.coefficients``), and whether the joint's target
moves within a step (a guide or the feed-forward: ``target_motion.pull_point`` then runs every
substep). The settings are immutable, so a plan made for the same settings object and the same
substep still holds.
"""

from typing import NamedTuple, Optional, Tuple

from .floor import coefficients as floor_coefficients
from .kernel import coefficients
from .limits import MIN_STEP
from .settings import Settings


class StepPlan(NamedTuple):
    """What the substeps of ``h`` take from ``settings``."""

    settings: Settings
    h: float
    coefficients: Tuple[float, ...]
    moving_target: bool
    floor: Optional[Tuple]


def step_plan(settings: Settings, dt: float) -> StepPlan:
    """
    Return the plan of a step of ``dt`` in ``settings.substeps`` substeps.

    :raises ValueError: a substep shorter than ``MIN_STEP``.
    """
    substeps = settings.substeps
    h = dt / substeps
    if h < MIN_STEP:
        raise ValueError(f'dt / substeps must be >= {MIN_STEP} s, got {dt!r} / {substeps}')
    motion = settings.target_motion
    return StepPlan(settings, h, coefficients(settings, h),
                    motion.feed_forward or motion.guided, floor_coefficients(settings.floor))
