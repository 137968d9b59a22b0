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
The node's ROS interface: its name, topic and service names, and QoS, shared by node and CLIs.

Names are relative (namespaces and remaps apply) except ``/diagnostics``, the absolute topic
that ``rqt_runtime_monitor`` and ``diagnostic_aggregator`` read. Importing this module loads no
node, executor or physics, so a CLI that talks to the node imports only this.

QoS: the target subscription is RELIABLE so that ``ros2 topic pub``, RViz's Publish Point tool
and ``mouse_target`` (all RELIABLE) connect and a one-shot target is acknowledged; depth 1
because only the newest target matters. Pose and twist are RELIABLE, which any subscriber,
RELIABLE or BEST_EFFORT, can match, with depth 100 so that a catch-up burst (up to 0.1 s of
ticks at 1 kHz) is not overwritten in the writer's history before a reliable reader has it.
"""

from rclpy.qos import DurabilityPolicy, HistoryPolicy, QoSProfile, ReliabilityPolicy

NODE_NAME = 'mouse_constraint'

TARGET_TOPIC = 'target'
POSE_TOPIC = 'pose'
TWIST_TOPIC = 'twist'
MARKERS_TOPIC = '~/markers'
DIAGNOSTICS_TOPIC = '/diagnostics'
# The node's /diagnostics statuses are named '<fully qualified node name><suffix>'; the
# simulator's says under PAUSED_KEY whether the node is paused ('true' or 'false').
SIMULATOR_STATUS_SUFFIX = ': simulator'
PAUSED_KEY = 'paused'

RESET_SERVICE = '~/reset'
RELEASE_SERVICE = '~/release'

TARGET_QOS = QoSProfile(history=HistoryPolicy.KEEP_LAST, depth=1,
                        reliability=ReliabilityPolicy.RELIABLE)
STATE_QOS = QoSProfile(history=HistoryPolicy.KEEP_LAST, depth=100,
                       reliability=ReliabilityPolicy.RELIABLE)
# Markers and diagnostics: a few per second, latest first.
MONITOR_DEPTH = 10

# A point on the body (PointStamped, QoS and frame as ``target``): it becomes the anchor.
GRAB_TOPIC = 'grab'
# nav_msgs/Odometry of the body, when publish_odometry is true (same QoS as pose and twist).
ODOM_TOPIC = 'odom'
# Simulator controls. /clock is absolute: the one clock use_sim_time nodes follow, whatever the
# node's namespace. It is RELIABLE (which rclpy's and rclcpp's BEST_EFFORT clock readers match)
# with depth 1: a time source only needs the newest reading. The wrench is like the target:
# RELIABLE, only the newest matters.
CLOCK_TOPIC = '/clock'
# The force the pointer feels (WrenchStamped), when publish_force is true: with pose's QoS, as
# pose's companion, one per pose with the pose's stamp. A haptic driver's force input is
# remapped to it.
FORCE_TOPIC = 'force'
FORCE_QOS = STATE_QOS
# The force as std_msgs/Float64MultiArray [fx, fy, fz] (``force_output``), for a ros2_control
# forward command controller's ``commands``: as ``force``, from the same tick.
FORCE_ARRAY_TOPIC = 'force_array'
# A target as a pose (PoseStamped: its position), as haptic device drivers publish their
# handle. BEST_EFFORT: drivers publish with sensor QoS (BEST_EFFORT) or RELIABLE, and a
# BEST_EFFORT reader matches both, where a RELIABLE one leaves a BEST_EFFORT writer unmatched.
# Depth 200, 0.2 s of a device's poses at 1 kHz: with tick_source target_pose, poses that queue
# while the node is held up (a loaded machine deschedules it for tens of milliseconds) each run
# their own tick, in order, none lost; twice device_timeout's default and the catch-up bound,
# so that a node that cannot keep up answers at most that late, not ever later. On the node's
# clock a tick takes the newest of them.
TARGET_POSE_TOPIC = 'target_pose'
TARGET_POSE_QOS = QoSProfile(history=HistoryPolicy.KEEP_LAST, depth=200,
                             reliability=ReliabilityPolicy.BEST_EFFORT)
WRENCH_TOPIC = 'wrench'
PAUSE_SERVICE = '~/pause'
STEP_SERVICE = '~/step'
CLOCK_QOS = QoSProfile(history=HistoryPolicy.KEEP_LAST, depth=1,
                       reliability=ReliabilityPolicy.RELIABLE)
WRENCH_QOS = TARGET_QOS
# Service events of ~/reset and ~/release (``<service>/_service_event``, service
# introspection with contents): what the node did, for ``ros2 service echo`` and mouse_record,
# which follows the node's target through them. RELIABLE, and deep enough for a burst of calls.
SERVICE_EVENT_QOS = QoSProfile(history=HistoryPolicy.KEEP_LAST, depth=100,
                               reliability=ReliabilityPolicy.RELIABLE)
# The body's URDF (std_msgs/String), when robot_description is set: as robot_state_publisher
# offers it (relative name, TRANSIENT_LOCAL so that a late reader such as RViz's RobotModel
# display still gets it, depth 1), for RViz to draw the link on the node's TF.
# A robot's joints (sensor_msgs/JointState), every published tick, as robot_state_publisher and
# controllers read them.
JOINT_STATES_TOPIC = 'joint_states'
JOINT_STATES_QOS = STATE_QOS
DESCRIPTION_TOPIC = 'robot_description'
DESCRIPTION_QOS = QoSProfile(history=HistoryPolicy.KEEP_LAST, depth=1,
                             reliability=ReliabilityPolicy.RELIABLE,
                             durability=DurabilityPolicy.TRANSIENT_LOCAL)
# The browser view of the node (``mouse_view``), in the node's namespace.
VIEW_NODE_NAME = 'mouse_view'
# The node as an RViz interactive marker (``mouse_marker``), in the node's namespace: the
# interactive marker server's topic namespace (one segment: RViz lists servers by the first),
# its three endpoints, and the QoS RViz's client uses for both topics.
MARKER_NODE_NAME = 'mouse_marker'
MARKER_NAMESPACE = 'mouse_marker'
MARKER_UPDATE_TOPIC = MARKER_NAMESPACE + '/update'
MARKER_FEEDBACK_TOPIC = MARKER_NAMESPACE + '/feedback'
MARKER_SERVICE = MARKER_NAMESPACE + '/get_interactive_markers'
MARKER_QOS = QoSProfile(history=HistoryPolicy.KEEP_LAST, depth=100,
                        reliability=ReliabilityPolicy.RELIABLE)


def node_name(namespace: str, name: str) -> str:
    """Return the fully qualified name of the node ``name`` in ``namespace`` (``/`` or ``/ns``)."""
    return f'{namespace.rstrip("/")}/{name}'
