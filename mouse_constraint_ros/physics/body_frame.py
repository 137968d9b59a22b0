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
The published body frame and the physics' one: a URDF link's frame and its COM.

The physics steps the body about its COM (``BodyState``'s origin); a URDF link's frame, which
``robot_state_publisher`` and RViz's RobotModel expect on TF and a user reads in ``pose``, has
the COM at ``com`` (the ``<inertial>`` origin). Points and states cross between the two here,
and nowhere else.
"""

from typing import NamedTuple

from .algebra import Vector3
from .state import BodyState


class BodyFrame(NamedTuple):
    """Where the published body frame (the link's) has the COM: ``com`` (m, in that frame)."""

    com: Vector3 = (0.0, 0.0, 0.0)

    @property
    def at_com(self) -> bool:
        """Return whether the frame's origin is the COM (nothing to move)."""
        return not any(self.com)

    def physics_point(self, point: Vector3) -> Vector3:
        """Return a body-frame point (link frame) from the COM, as the physics takes it."""
        return tuple(point) if self.at_com else tuple(p - c for p, c in zip(point, self.com))

    def link_point(self, point: Vector3) -> Vector3:
        """Return a point from the COM (physics) in the link frame."""
        return tuple(point) if self.at_com else tuple(p + c for p, c in zip(point, self.com))

    def physics_state(self, link: BodyState) -> BodyState:
        """Return the COM's state for the link frame's ``link``."""
        return link if self.at_com else link.moved(self.com)

    def link_state(self, physics: BodyState) -> BodyState:
        """Return the link frame's state for the COM's ``physics``."""
        return physics if self.at_com else physics.moved(tuple(-c for c in self.com))
