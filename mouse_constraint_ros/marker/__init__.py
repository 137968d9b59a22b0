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
``mouse_marker``: the body as an RViz interactive marker, dragged with RViz's Interact tool.

- ``drag``: what a press, a move and a release of the marker send to the node (no ROS);
- ``updates``: the interactive marker and the updates that keep RViz's copy of it;
- ``presence``: which feedback publishers a drag hangs on, and whether one left;
- ``node``: the ``mouse_marker`` node's wiring; ``command``: its arguments and ``main``.
"""
