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

"""A viewer beside a simulated body: every marker array it draws, and its poses by stamp."""

from typing import Dict, List, Tuple

from geometry_msgs.msg import PoseStamped
from rclpy.node import Node
from visualization_msgs.msg import MarkerArray

from mouse_constraint_ros.wire.messages import stamp_nanoseconds

MARKERS_TOPIC = '/mouse_constraint/markers'


def marker_viewer(body) -> Tuple[List[MarkerArray], Dict[int, PoseStamped]]:
    """
    Add a viewer node to ``body`` (a ``SimulatedBody``); return what it receives as it comes.

    :returns: the marker arrays in order, and the poses keyed by their stamp (ns), so that a
        marker array can be checked against the pose of its own stamp.
    """
    viewer = Node('viewer', context=body.context)
    arrays, poses = [], {}
    viewer.create_subscription(MarkerArray, MARKERS_TOPIC, arrays.append, 10)
    viewer.create_subscription(PoseStamped, 'pose', lambda p: poses.__setitem__(
        stamp_nanoseconds(p.header.stamp), p), 1000)
    body.add_node(viewer)
    return arrays, poses
