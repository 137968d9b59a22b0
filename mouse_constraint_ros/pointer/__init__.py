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
What ``mouse_view`` and ``mouse_marker`` share: the pointer on the body, and the node it drags.

The ray on the box and the camera plane (``geometry``), the body's shape of the node's
parameters and a ray on it (``body_shape``), a whole robot's links placed from its joints and a
ray on them (``robot_shape``), what a press, a drag and a release send
(``gestures``), at most so many pushes a second (``push_throttle``), the newest pose taken on
demand (``newest_message``), whether the node is there and the parameters a client draws with
(``node_follower``, ``node_readouts``). Neither tool imports the other: both import this.
"""
