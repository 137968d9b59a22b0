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

"""Setup script for the mouse_constraint_ros ament_python package."""

from glob import glob

from setuptools import find_packages, setup

package_name = 'mouse_constraint_ros'

setup(
    name=package_name,
    version='0.1.0',
    packages=find_packages(include=[package_name, package_name + '.*']),
    data_files=[
        ('share/ament_index/resource_index/packages', ['resource/' + package_name]),
        ('share/' + package_name, ['package.xml']),
        ('share/' + package_name + '/config',
         sorted(glob('config/*.yaml') + glob('config/*.xml') + glob('config/*.urdf')
                + glob('config/*.stl'))),
        ('share/' + package_name + '/launch', sorted(glob('launch/*.launch.py'))),
        ('share/' + package_name + '/rviz', sorted(glob('rviz/*.rviz'))),
    ],
    # The ROS 2 Python packages (rclpy, message packages) are deliberately NOT
    # listed here: on an apt ROS install they come from the system, and for a
    # plain venv they are pinned in requirements/ros.txt.
    install_requires=['setuptools', 'numpy'],
    extras_require={
        'test': ['pytest', 'scipy', 'hypothesis'],
        # The whole robot (a robot_description of several links): Pinocchio's dynamics.
        'robot': ['pin'],
    },
    zip_safe=True,
    maintainer='mouse_constraint_ros maintainers',
    maintainer_email='maintainer@example.com',
    description=(
        'A ROS 2 node serving one rigid body dragged by a mouse constraint: subscribes '
        'to a geometry_msgs/PointStamped target, publishes PoseStamped/TwistStamped.'
    ),
    license='Apache-2.0',
    entry_points={
        'console_scripts': [
            'mouse_constraint_node = mouse_constraint_ros.node.console:main',
            'mouse_target = mouse_constraint_ros.cli.target:main',
            'mouse_record = mouse_constraint_ros.cli.record:main',
            'mouse_wrench = mouse_constraint_ros.cli.wrench:main',
            'mouse_ctl = mouse_constraint_ros.cli.console:ctl',
            'mouse_view = mouse_constraint_ros.view.command:main',
            'mouse_marker = mouse_constraint_ros.marker.command:main',
        ],
        # The fixtures of mouse_constraint_ros.testing, for any package that installs this one.
        'pytest11': [
            'mouse_constraint_ros = mouse_constraint_ros.testing.pytest_plugin',
        ],
    },
)
