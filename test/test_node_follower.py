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


"""``NodeFollower``: the node's parameters are known once the node answered, not when asked."""

from rcl_interfaces.srv import GetParameters
from rclpy.parameter import Parameter

from mouse_constraint_ros.node.mouse_constraint_node import MouseConstraintNode
from mouse_constraint_ros.pointer.node_follower import NodeFollower


def test_the_parameters_are_known_once_the_node_answered(ros):
    """
    Asked, not yet answered: not known (an owner drawing then would draw the defaults).

    The owner first hears of them known, with the node's values.
    """
    ros.add(MouseConstraintNode(context=ros.context, parameter_overrides=[
        Parameter('frame_id', value='map'), Parameter('box_size', value=[0.3, 0.3, 0.3])]))
    heard = []
    follower = NodeFollower(ros.probe, topic='/pose', discovery_seconds=0.0,
                            on_parameters=lambda p: heard.append((follower.parameters_known, p)))
    service = ros.probe.create_client(GetParameters, 'mouse_constraint/get_parameters')
    assert ros.spin_until(lambda: ros.probe.count_publishers('/pose') > 0
                          and service.service_is_ready())
    follower.look()  # asks
    assert follower.present and not follower.parameters_known
    assert ros.spin_until(lambda: follower.parameters_known)
    known, parameters = heard[0]
    assert known and parameters.frame_id == 'map' and parameters.box_size == (0.3, 0.3, 0.3)
    follower.look()  # known: not asked again
    ros.spin_for(0.2)
    assert len(heard) == 1
