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
The physics core: one rigid body held by the mouse constraint. Imports numpy only, never rclpy.

The constraint is Irlan Robson's, from his note "The Mouse Constraint (and its Jacobian)" (the
"seed" note of the docstrings); the ``constraint`` module states the two sign corrections made
to it, and ``limits`` the ranges of the settings.
"""

from .body import RigidBody
from .floor import Floor
from .mouse_joint import MouseConstraint
from .settings import Settings, STANDARD_GRAVITY
from .simulation import MouseSimulation
from .state import BodyState

__all__ = ['BodyState', 'Floor', 'MouseConstraint', 'MouseSimulation', 'RigidBody', 'Settings',
           'STANDARD_GRAVITY']
