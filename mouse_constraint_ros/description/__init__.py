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
The body from a URDF link (``robot_description``): its inertia, collision and visual geometry.

``urdf_link.body_model`` parses the URDF with yourdfpy and the meshes with trimesh into a
``urdf_link.BodyModel`` in the link frame: the physics takes its mass, inertia and COM and its
convex collision pieces (``physics.collision``); the grab, the view and the markers take its
surfaces. No ROS here beyond ``ament_index_python`` for ``package://`` paths.

``urdf_link`` imports the parser and trimesh, so it is imported where a URDF is first read, in
the function that reads it (docs/architecture.md, "Heavy libraries"): a process with the box
body neither loads them nor holds their memory.
"""

from .body_geometry import BodyGeometry

__all__ = ['BodyGeometry']
