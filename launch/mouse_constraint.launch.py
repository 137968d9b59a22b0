"""
Launch the mouse_constraint node with the installed parameters, and optionally RViz.

  ros2 launch mouse_constraint_ros mouse_constraint.launch.py
  ros2 launch mouse_constraint_ros mouse_constraint.launch.py namespace:=/robot rviz:=true
  ros2 launch mouse_constraint_ros mouse_constraint.launch.py -s   # the arguments

The default parameters file and the RViz configuration are looked up in the package's installed
share directory (ament index) when the launch file is loaded, so they are the installed copies.
"""

import os

from ament_index_python.packages import get_package_share_directory
from launch import LaunchDescription
from launch.actions import DeclareLaunchArgument
from launch.conditions import IfCondition
from launch.substitutions import LaunchConfiguration
from launch_ros.actions import Node

PACKAGE = 'mouse_constraint_ros'
NODE_NAME = 'mouse_constraint'
# The topics the RViz configuration names, absolute as for an empty namespace. RViz runs in the
# launch namespace with each remapped to its relative name, so that under namespace:=/robot it
# shows /robot/pose and publishes clicks on /robot/target and /robot/grab.
RVIZ_TOPICS = ('pose', NODE_NAME + '/markers', 'grab', 'target')


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
            'use_sim_time', default_value='false', choices=['true', 'false'],
            description='Follow /clock instead of the system clock.'),
        DeclareLaunchArgument(
            'rviz', default_value='false', choices=['true', 'false'],
            description='Also start rviz2 with the installed mouse_constraint.rviz.'),
        # RViz first: where rviz2 is not installed, rviz:=true then fails before the node starts
        # (launch stops at the failing action and does not stop processes it already started).
        Node(
            package='rviz2', executable='rviz2', name='rviz2', namespace=namespace,
            arguments=['-d', os.path.join(share, 'rviz', 'mouse_constraint.rviz')],
            parameters=[{'use_sim_time': use_sim_time}],
            remappings=[('/' + topic, topic) for topic in RVIZ_TOPICS],
            condition=IfCondition(LaunchConfiguration('rviz'))),
        Node(
            package=PACKAGE, executable='mouse_constraint_node', name=NODE_NAME,
            namespace=namespace, output='screen', emulate_tty=True,
            parameters=[LaunchConfiguration('params_file'), {'use_sim_time': use_sim_time}]),
    ])
