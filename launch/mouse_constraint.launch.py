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

``urdf:=path`` makes the body that URDF's link (``body_link:=name``, or its only link): the
file's text is the node's ``robot_description``, which the node offers, latched, on the
``robot_description`` topic for RViz's RobotModel. Both override the parameters file's (without
``urdf:=``, the body is the box of ``box_size``).

``/tf`` is one topic for every namespace, so two instances must not publish the same child
frame: under a namespace ``body_frame_id`` defaults to the body's frame name under it
(``robot/body`` for ``namespace:=/robot``, or ``robot/<link>`` with a URDF; then RViz's
RobotModel needs the namespace as its TF Prefix) and overrides the parameters file's; without
one it is the node's own (``body``, or the link's name). The parent frame (``frame_id``,
default ``world``) stays shared, the world both bodies move in.
"""

import os
from xml.etree import ElementTree

from ament_index_python.packages import get_package_share_directory
from launch import LaunchDescription
from launch.actions import DeclareLaunchArgument
from launch.conditions import IfCondition
from launch.substitution import Substitution
from launch.substitutions import (FileContent, IfElseSubstitution, LaunchConfiguration,
                                  NotEqualsSubstitution, SubstitutionFailure)
from launch.utilities import perform_substitutions
from launch_ros.actions import Node
from launch_ros.parameter_descriptions import ParameterValue

PACKAGE = 'mouse_constraint_ros'
NODE_NAME = 'mouse_constraint'
MARKER_NAME = 'mouse_marker'
# The topics (and the service) the RViz configuration names, absolute as for an empty
# namespace. RViz runs in the launch namespace with each remapped to its relative name, so that
# under namespace:=/robot it shows /robot/pose, publishes clicks on /robot/target and
# /robot/grab, and drags the interactive marker of /robot/mouse_marker.
RVIZ_TOPICS = ('pose', NODE_NAME + '/markers', 'grab', 'target', MARKER_NAME + '/update',
               MARKER_NAME + '/feedback', MARKER_NAME + '/get_interactive_markers',
               'robot_description')
# The spellings a boolean argument takes: IfCondition reads true/false in any case, and the
# node's use_sim_time gets the argument parsed as YAML, where these four are booleans.
BOOLEAN = ['true', 'false', 'True', 'False']


class NamespacedFrame(Substitution):
    """
    The body's frame under the launch namespace, or empty (the node's own name) without one.

    ``robot/body`` for /robot, ``robot/<link>`` with a URDF: the link ``body_link`` names, or the
    URDF's only link (read here with the standard library: the node checks the rest).
    """

    def describe(self) -> str:
        """Return what ``ros2 launch -s`` shows as the default."""
        return ("'<namespace>/<body>' (<body>: the URDF's link, or 'body'); without a "
                "namespace, the node's own")

    def perform(self, context) -> str:
        """Return the frame under the namespace, without a leading slash (tf2's convention)."""
        namespace = perform_substitutions(context, [LaunchConfiguration('namespace')])
        namespace = namespace.strip('/')
        if not namespace:
            return ''
        link = perform_substitutions(context, [LaunchConfiguration('body_link')])
        urdf = perform_substitutions(context, [LaunchConfiguration('urdf')])
        if not link and urdf:
            try:
                links = ElementTree.parse(urdf).getroot().findall('link')
            except (OSError, ElementTree.ParseError) as error:
                raise SubstitutionFailure(f'urdf {urdf!r} cannot be read: {error}') from None
            link = links[0].get('name', '') if len(links) == 1 else ''
        return f'{namespace}/{link or "body"}'


def generate_launch_description() -> LaunchDescription:
    """Return the node, its arguments and the RViz process started when ``rviz`` is true."""
    share = get_package_share_directory(PACKAGE)
    namespace = LaunchConfiguration('namespace')
    use_sim_time = LaunchConfiguration('use_sim_time')
    # The URDF file's text, or empty without one (FileContent is not evaluated then).
    urdf = LaunchConfiguration('urdf')
    urdf_text = IfElseSubstitution(NotEqualsSubstitution(urdf, ''), FileContent(urdf), '')
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
            'urdf', default_value='',
            description='URDF file of the body (its text is robot_description); empty: the box '
                        'of params_file. Overrides params_file.'),
        DeclareLaunchArgument(
            'body_link', default_value='',
            description="The URDF's link that is the body; empty: its only link."),
        DeclareLaunchArgument(
            'body_frame_id', default_value=NamespacedFrame(),
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
                         'body_frame_id': LaunchConfiguration('body_frame_id'),
                         'robot_description': ParameterValue(urdf_text, value_type=str),
                         # Mesh paths relative to the URDF file resolve against it.
                         'robot_description_file': ParameterValue(urdf, value_type=str),
                         'body_link': LaunchConfiguration('body_link')}]),
        Node(
            package=PACKAGE, executable='mouse_marker', name=MARKER_NAME, namespace=namespace,
            output='screen', parameters=[{'use_sim_time': use_sim_time}],
            condition=IfCondition(LaunchConfiguration('marker'))),
    ])
