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
``TargetGate``: the node's target policy as plain data, and the same verdicts as the node.

The node is asked through its ``target`` topic, stepped in lockstep: the test sees whether the
simulation took each target and, for a refused one, the node's refusal and its key.
"""

import dataclasses
import itertools
import math

from geometry_msgs.msg import PoseStamped
import numpy as np
import pytest
from rclpy.node import Node

from mouse_constraint_ros.cli.target import circle_point
from mouse_constraint_ros.inputs.target_gate import REASONS
from mouse_constraint_ros.inputs.target_gate import TargetGate
from mouse_constraint_ros.testing import InputRefused
from mouse_constraint_ros.wire.interface import TARGET_POSE_QOS, TARGET_POSE_TOPIC

FRAME = 'odom'
RADIUS = 5.0
BEYOND = math.nextafter(RADIUS, math.inf)
FRAMES = ['', FRAME, 'world', 'Odom', ' odom']
POINTS = [(0.0, 0.0, 1.0), (3.0, 4.0, 0.0), (0.0, 0.0, -RADIUS), (BEYOND, 0.0, 0.0),
          (3.0, 4.0, 1e-6), (1e9, 0.0, 0.0), (math.nan, 0.0, 0.0), (0.0, math.inf, 0.0),
          (0.0, 0.0, -math.inf)]
SENTINEL = (0.125, -0.25, 0.5)


def node_verdict(body, frame: str, point) -> tuple:
    """Return (taken, refusal keys) of the node for one target, by the tick after it."""
    body.node.simulation.target = SENTINEL
    try:
        body.target(point, frame_id=frame)
    except InputRefused as refused:
        body.step()
        return body.node.simulation.target != SENTINEL, [refused.key]
    body.step()
    return body.node.simulation.target != SENTINEL, []


def test_gate_gives_the_node_s_verdict_for_every_frame_and_point(simulated_body_factory):
    """Taken by the node exactly when the gate returns None; else refused under the gate's key."""
    body = simulated_body_factory(frame_id=FRAME, workspace_radius=RADIUS, marker_rate_hz=0.0,
                                  diagnostics_rate_hz=0.0)
    gate = TargetGate(FRAME, RADIUS)
    verdicts = set()
    for frame, point in itertools.product(FRAMES, POINTS):
        refusal = gate.refusal(frame, point)
        taken, keys = node_verdict(body, frame, point)
        assert taken == (refusal is None), (frame, point)
        assert keys == ([] if refusal is None else [refusal.key]), (frame, point)
        verdicts.add(None if refusal is None else refusal.key)
    # The cases reach every verdict.
    assert verdicts == {None, *REASONS}


def test_refusal_reasons_say_why():
    """Frame before finiteness before the workspace, each reason naming what failed."""
    gate = TargetGate('world', 10000.0)
    assert gate.refusal('map', (math.nan, 0.0, 0.0)) == (
        'frame', "in frame 'map': this node works in 'world' (no tf lookup is made)")
    finite = gate.refusal('', (math.inf, 0.0, 1e9))
    assert finite.key == 'finite' and str((math.inf, 0.0, 1e9)) in finite.reason
    far = gate.refusal('world', (1e9, 0.0, 0.0))
    assert far.key == 'workspace' and str((1e9, 0.0, 0.0)) in far.reason
    assert f'workspace_radius {gate.workspace_radius:g} m' in far.reason
    assert gate.refusal('', [1, 2, 3]) is None


def test_a_device_pose_in_another_frame_names_the_node_s_frame_and_the_device_s():
    """A device pose's gate says both frames: the node's frame_id, the device_frame_id."""
    gate = TargetGate('fd_base', math.inf, 'world')
    assert gate.refusal('geotouch', (0.0, 0.0, 0.0)) == (
        'frame', "in frame 'geotouch': this node works in 'world' and takes device poses in "
                 "'fd_base' (device_frame_id); no tf lookup is made")
    assert gate.refusal('fd_base', (0.0, 0.0, 0.0)) is None
    assert TargetGate('world', 1.0, 'world').refusal('map', (0.0, 0.0, 0.0)) == (
        'frame', "in frame 'map': this node works in 'world' (no tf lookup is made)")


def test_the_node_refuses_a_device_pose_in_another_frame_naming_both(simulated_body_factory):
    """device_frame_id fd_base, a pose in geotouch: the refusal says world and fd_base."""
    body = simulated_body_factory(device_frame_id='fd_base', marker_rate_hz=0.0,
                                  diagnostics_rate_hz=0.0)
    device = body.add_node(Node('device', context=body.context))
    publisher = device.create_publisher(PoseStamped, TARGET_POSE_TOPIC, TARGET_POSE_QOS)
    body.step()
    pose = PoseStamped()
    pose.header.frame_id = 'geotouch'
    pose.pose.orientation.w = 1.0
    publisher.publish(pose)
    body.step_until(lambda: body.node.refusals[0] > 0, max_ticks=100)
    assert body.node.refusals[1].reason == (
        "in frame 'geotouch': this node works in 'world' and takes device poses in 'fd_base' "
        '(device_frame_id); no tf lookup is made')


def test_gate_is_a_frozen_value():
    """Equal settings give equal gates; a gate cannot be changed after the node made it."""
    gate = TargetGate('world', 1.0)
    assert gate == TargetGate('world', 1.0) and hash(gate) == hash(TargetGate('world', 1.0))
    with pytest.raises(dataclasses.FrozenInstanceError):
        gate.workspace_radius = 2.0


@pytest.mark.parametrize('center', [(3.0, -4.0, 2.0), (0.0, 0.0, 1.0), (-0.5, 0.0, -7.0)])
def test_circle_is_taken_exactly_when_its_farthest_point_is_inside(center):
    """The workspace test of a circle holds at its extent, |(|c_xy| + r, c_z)|, either way."""
    radius = 0.75
    extent = math.hypot(math.hypot(center[0], center[1]) + radius, center[2])
    inside = TargetGate('world', extent * (1.0 + 1e-12))
    outside = TargetGate('world', extent * (1.0 - 1e-12))
    assert inside.circle_refusal('world', center, radius) is None
    refusal = outside.circle_refusal('', center, radius)
    assert refusal.key == 'workspace' and f'radius {radius:g} m' in refusal.reason
    # Every point the circle mode publishes passes the gate that took the circle.
    samples = [circle_point(list(center), radius, 1.0, t) for t in np.linspace(0.0, 1.0, 721)]
    assert all(inside.refusal('', point) is None for point in samples)
    assert max(math.hypot(*point) for point in samples) == pytest.approx(extent, rel=1e-5)


def test_circle_in_a_foreign_frame_is_refused_for_its_frame():
    """The frame is checked before the extent, with the same reason as for one target."""
    gate = TargetGate('world', 1.0)
    assert gate.circle_refusal('map', (0.0, 0.0, 0.5), 0.1) == gate.refusal('map', (0, 0, 0))
