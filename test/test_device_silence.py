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

"""Tell the device: refused poses counted with their reason, a silent device's force zero."""

from geometry_msgs.msg import PoseStamped
import numpy as np
import pytest
from rclpy.node import Node

from mouse_constraint_ros.cli import ctl
from mouse_constraint_ros.monitoring.input_diagnostics import input_status, InputReport
from mouse_constraint_ros.node.parameters import DEFAULTS, node_config
from mouse_constraint_ros.node.startup import hold_here
from mouse_constraint_ros.testing import SimulatedBody
from mouse_constraint_ros.wire.interface import TARGET_POSE_TOPIC, TARGET_QOS
from mouse_constraint_ros.wire.messages import set_stamp
from test_support.haptic_listener import StateListener

COM = (0.0, 0.0, 1.0)  # the default body's COM at the start
WEIGHT = 2.0 * 9.80665


class Device(Node):
    """Publishes the handle at the COM, where the anchor starts, in a frame of its choice."""

    def __init__(self, *, context, frame_id: str = '') -> None:
        """Create the pose publisher."""
        super().__init__('device', context=context, start_parameter_services=False)
        self.publisher = self.create_publisher(PoseStamped, TARGET_POSE_TOPIC, TARGET_QOS)
        self.frame_id = frame_id

    def send(self, nanoseconds: int, point=COM) -> None:
        """Publish the handle at ``point``."""
        message = PoseStamped()
        message.header.frame_id = self.frame_id
        set_stamp(message.header.stamp, nanoseconds)
        p = message.pose.position
        p.x, p.y, p.z = point
        message.pose.orientation.w = 1.0
        self.publisher.publish(message)


def device_loop(sends, ticks: int, frame_id: str = '', **parameters):
    """
    Step ``ticks`` ticks, the device sending before the ticks in ``sends``; return the forces.

    The body is held at its COM (anchor at the origin), so the held force is the weight.
    """
    body = SimulatedBody(publish_force=True, anchor=[0.0, 0.0, 0.0], **parameters)
    with body:
        listener = body.add_node(StateListener(context=body.context))
        device = body.add_node(Device(context=body.context, frame_id=frame_id))
        for tick in range(ticks):
            if tick in sends:
                device.send(round(body.time * 1e9))
            body.step()
        refusals = body.node.refusals
    return np.array([force for _, force in listener.forces]), refusals


@pytest.mark.ros
def test_a_device_that_stops_feels_zero_after_the_timeout_and_the_force_again_when_it_returns():
    """
    Poses for 50 ticks, none for 200, then again: held force, zero after device_timeout, held.

    The last pose of the first run is taken before tick 49 at 0.049 s; the ticks whose stamp is
    more than 0.1 s later (from 0.150 s, tick 149 on) send zero, until a pose comes again.
    """
    sends = set(range(50)) | set(range(250, 300))
    forces, refusals = device_loop(sends, 300)
    assert refusals == (0, None)
    norms = np.linalg.norm(forces, axis=1)
    assert np.all(norms[:149] > 0.5 * WEIGHT)
    assert np.all(norms[149:250] == 0.0)
    assert np.all(norms[250:] > 0.5 * WEIGHT)


@pytest.mark.ros
def test_before_any_pose_the_force_is_the_held_weight_and_timeout_zero_never_mutes():
    forces, _ = device_loop(set(), 300)
    assert np.all(np.linalg.norm(forces, axis=1) > 0.5 * WEIGHT)
    forces, _ = device_loop({0}, 300, device_timeout=0.0)
    assert np.all(np.linalg.norm(forces, axis=1) > 0.5 * WEIGHT)


@pytest.mark.ros
def test_a_device_in_the_wrong_frame_is_refused_by_reason_and_feels_nothing_after_the_timeout():
    """Every pose refused ('frame'): the held weight only until device_timeout, then zero."""
    forces, (count, refusal) = device_loop(set(range(300)), 300, frame_id='geotouch')
    assert count == 300 and refusal.key == 'frame'
    norms = np.linalg.norm(forces, axis=1)
    assert np.all(norms[100:] == 0.0) and norms[0] > 0.5 * WEIGHT


def test_the_inputs_status_counts_by_reason_and_warns_while_refusals_come_or_the_device_is_mute():
    report = InputReport(refused=3, by_key={'workspace': 1, 'frame': 2},
                         last_line="ignoring target pose in frame 'geotouch': ...",
                         new_refusals=2, device_age=0.25, device_silent=True, device_timeout=0.1)
    status = input_status('/n: inputs', '/n', report)
    assert status.level == b'\x01'
    assert status.message == ('2 inputs refused since the last report, the last ignoring target '
                              "pose in frame 'geotouch': ...; device silent: force zero (no "
                              'valid pose for 0.250 s)')
    values = {value.key: value.value for value in status.values}
    assert values['refused inputs'] == '3'
    assert values['refused by reason'] == 'frame 2, workspace 1'
    quiet = input_status('/n: inputs', '/n', report._replace(new_refusals=0, device_age=0.01,
                                                             device_silent=False))
    assert quiet.level == b'\x00'
    assert quiet.message == 'no input refused since the last report'
    assert {v.key: v.value for v in quiet.values}['device'] == 'valid pose 0.010 s ago'
    assert values['device ticks (early, late)'] == 'off: tick_source clock'
    clocked = input_status('/n: inputs', '/n', report._replace(device_ticks=(1000, 3, 2)))
    assert {v.key: v.value for v in clocked.values}['device ticks (early, late)'] == '1000 (3, 2)'
    assert values['device poses lost'] == 'off: tick_source clock'
    lost = input_status('/n: inputs', '/n', report._replace(
        new_refusals=0, device_silent=False, device_lost=7, new_lost=3))
    assert lost.level == b'\x01'
    assert lost.message == '3 device poses lost since the last report (gaps in their stamps)'
    assert {v.key: v.value for v in lost.values}['device poses lost'] == '7'


def test_the_start_says_where_to_hold_the_device_in_both_frames():
    config = node_config({**DEFAULTS, 'device_frame_id': 'touch_base', 'device_scale': 10.0,
                          'device_pose': [0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0]})
    assert hold_here(config) == (
        "the anchor starts at (0.2, 0.1, 1.05) m in 'world': hold the device there, at "
        "(0.02, 0.01, 0.005) in 'touch_base', before its poses come on target_pose")


@pytest.mark.ros
def test_echo_inputs_prints_the_refusals_and_the_device_state_from_diagnostics():
    """Wrong-frame poses, then silence: /diagnostics and mouse_ctl echo inputs say both."""
    with SimulatedBody(publish_force=True, diagnostics_rate_hz=100.0) as body:
        node = Node('mouse_ctl', context=body.context)
        lines = []
        ctl.create_echo(node, 'inputs', lines.append, print_rate=0.0)
        body.add_node(node)
        device = body.add_node(Device(context=body.context, frame_id='geotouch'))
        for _ in range(20):
            device.send(round(body.time * 1e9))
            body.step()
        body.step(150)
        lines.clear()
        body.step_until(lambda: len(lines) >= 2, max_ticks=100_000)
    line = lines[-1]
    assert ' WARN  device silent: force zero (no valid pose for ' in line
    assert '  refused inputs: 20  refused by reason: frame 20  last refusal: ignoring target ' \
           "pose in frame 'geotouch': this node works in 'world' (no tf lookup is made)  " in line
