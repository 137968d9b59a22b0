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
Launch the mouse_constraint node with the installed parameters, and optionally RViz.

  ros2 launch mouse_constraint_ros mouse_constraint.launch.py
  ros2 launch mouse_constraint_ros mouse_constraint.launch.py namespace:=/robot rviz:=true
  ros2 launch mouse_constraint_ros mouse_constraint.launch.py -s   # the arguments

With ``rviz:=true`` it also starts ``mouse_marker`` (``marker``, by default as ``rviz``), the
body as an interactive marker that RViz's Interact tool drags.

The default parameters file and the RViz configuration are looked up in the package's installed
share directory (ament index) when the launch file is loaded, so they are the installed copies.

``/tf`` is one topic for every namespace, so two instances must not publish the same child
frame: ``body_frame_id`` defaults to ``body`` under the namespace (``robot/body`` for
``namespace:=/robot``, ``body`` for none) and overrides the parameters file's; the parent frame
(``frame_id``, default ``world``) stays shared, the world both bodies move in.
"""

import os

from ament_index_python.packages import get_package_share_directory
from launch import LaunchDescription
from launch.actions import DeclareLaunchArgument
from launch.conditions import IfCondition
from launch.substitution import Substitution
from launch.substitutions import LaunchConfiguration
from launch.utilities import perform_substitutions
from launch_ros.actions import Node

PACKAGE = 'mouse_constraint_ros'
NODE_NAME = 'mouse_constraint'
MARKER_NAME = 'mouse_marker'
# The topics (and the service) the RViz configuration names, absolute as for an empty
# namespace. RViz runs in the launch namespace with each remapped to its relative name, so that
# under namespace:=/robot it shows /robot/pose, publishes clicks on /robot/target and
# /robot/grab, and drags the interactive marker of /robot/mouse_marker.
RVIZ_TOPICS = ('pose', NODE_NAME + '/markers', 'grab', 'target', MARKER_NAME + '/update',
               MARKER_NAME + '/feedback', MARKER_NAME + '/get_interactive_markers')
# The spellings a boolean argument takes: IfCondition reads true/false in any case, and the
# node's use_sim_time gets the argument parsed as YAML, where these four are booleans.
BOOLEAN = ['true', 'false', 'True', 'False']


class NamespacedFrame(Substitution):
    """A frame name under the launch namespace: ``robot/body`` for /robot, ``body`` for none."""

    def __init__(self, frame: str) -> None:
        """Name ``frame`` (without namespace)."""
        super().__init__()
        self.frame = frame

    def describe(self) -> str:
        """Return what ``ros2 launch -s`` shows as the default."""
        return f"'<namespace>/{self.frame}' ('{self.frame}' without a namespace)"

    def perform(self, context) -> str:
        """Return the frame under the namespace, without a leading slash (tf2's convention)."""
        namespace = perform_substitutions(context, [LaunchConfiguration('namespace')])
        namespace = namespace.strip('/')
        return f'{namespace}/{self.frame}' if namespace else self.frame


def generate_launch_description() -> LaunchDescription:
    """Return the node, its arguments and the RViz process started when ``rviz`` is true."""
    share = get_package_share_directory(PACKAGE)
    namespace = LaunchConfiguration('namespace')
    use_sim_time = LaunchConfiguration('use_sim_time')
    return LaunchDescription([
        DeclareLaunchArgument(
            'namespace', default_value='',
            description='ROS namespace of the node (and of RViz): empty or e.g. /robot.'),
        DeclareLaunchArgument(
            'params_file', default_value=os.path.join(share, 'config', 'params.yaml'),
            description='Parameters file of the node.'),
        DeclareLaunchArgument(
            'use_sim_time', default_value='false', choices=BOOLEAN,
            description='Follow /clock instead of the system clock.'),
        DeclareLaunchArgument(
            'rviz', default_value='false', choices=BOOLEAN,
            description='Also start rviz2 with the installed mouse_constraint.rviz.'),
        DeclareLaunchArgument(
            'body_frame_id', default_value=NamespacedFrame('body'),
            description='Child frame of the body on /tf and odom; overrides params_file.'),
        DeclareLaunchArgument(
            'marker', default_value=LaunchConfiguration('rviz'), choices=BOOLEAN,
            description='Also start mouse_marker, the body as an interactive marker to drag '
                        "in RViz (default: as 'rviz')."),
        # RViz first: where rviz2 is not installed, rviz:=true makes launch fail at this action
        # (package not found) and shut down, exit code 1, before the node starts. (After a
        # failing action launch shuts down what it started, too.)
        Node(
            package='rviz2', executable='rviz2', name='rviz2', namespace=namespace,
            output='screen',
            arguments=['-d', os.path.join(share, 'rviz', 'mouse_constraint.rviz')],
            parameters=[{'use_sim_time': use_sim_time}],
            remappings=[('/' + topic, topic) for topic in RVIZ_TOPICS],
            condition=IfCondition(LaunchConfiguration('rviz'))),
        Node(
            package=PACKAGE, executable='mouse_constraint_node', name=NODE_NAME,
            namespace=namespace, output='screen', emulate_tty=True,
            parameters=[LaunchConfiguration('params_file'),
                        {'use_sim_time': use_sim_time,
                         'body_frame_id': LaunchConfiguration('body_frame_id')}]),
        Node(
            package=PACKAGE, executable='mouse_marker', name=MARKER_NAME, namespace=namespace,
            output='screen', parameters=[{'use_sim_time': use_sim_time}],
            condition=IfCondition(LaunchConfiguration('marker'))),
    ])
