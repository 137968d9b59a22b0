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
The body's shape as the node's parameters give it: a URDF link, or the box of ``box_size``.

``BodyShape`` reads it from the parameters ``mouse_marker`` follows, as the node reads them
(``robot_description``, ``body_link``, ``density``; without a URDF, ``box_size``): the link's
geometry in the link frame (``description.body_model``), whose pieces the marker draws and
whose collision pieces its press is tested on. It parses the URDF, and loads its meshes, only
when one of those parameters changed. A URDF the node took but this process cannot read (a
``package://`` mesh of a workspace not sourced here) is said in one warning, and the body is the
box of ``box_size`` until those parameters change.
"""

from typing import Callable, Optional, Tuple

from ..description import body_model, BodyGeometry
from ..pointer.node_readouts import ViewParameters


class BodyShape:
    """
    The body's geometry of the latest parameters, parsed once per change.

    :param warn: called with one line when a URDF cannot be read here.
    """

    def __init__(self, warn: Callable[[str], None]) -> None:
        """Start with no geometry known."""
        self._warn = warn
        self._key: Optional[Tuple] = None
        self._geometry: Optional[BodyGeometry] = None

    def geometry(self, parameters: ViewParameters) -> BodyGeometry:
        """Return the body's geometry of ``parameters``: the URDF link's, or the box's."""
        key = (parameters.robot_description, parameters.body_link, parameters.density,
               parameters.box_size)
        if key != self._key or self._geometry is None:
            self._key = key
            self._geometry = self._read(parameters)
        return self._geometry

    def _read(self, parameters: ViewParameters) -> BodyGeometry:
        box = BodyGeometry.box(parameters.box_size)
        if not parameters.robot_description:
            return box
        try:
            return body_model(parameters.robot_description, parameters.body_link,
                              density=parameters.density).geometry
        except ValueError as error:
            self._warn(f"the node's robot_description cannot be read here ({error}): the "
                       f'marker draws and tests presses on the box of box_size '
                       f'{tuple(parameters.box_size)} instead')
            return box
