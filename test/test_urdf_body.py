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
A URDF link through ROS: ``SimulatedBody(robot_description=..., body_link=...)`` in lockstep.

The shipped tool (config/tool.urdf) and one whose ``<inertial>`` frame is turned have their COM
off the link frame and a full inertia tensor (products of inertia). Hung by an anchor in the link
frame, each swings with the period of the exact physical pendulum of its inertia, which the test
derives on its own (scipy); pose, TF and the anchor are of the link frame. A box URDF reproduces
the box parameters' run bit for bit.
"""

import math
from pathlib import Path
from typing import NamedTuple, Tuple
from xml.etree import ElementTree

from geometry_msgs.msg import PoseStamped, TwistStamped
import numpy as np
import pytest
from rclpy.node import Node
from scipy.linalg import eigh
from scipy.spatial.transform import Rotation
from std_msgs.msg import String

from mouse_constraint_ros.physics import RigidBody
from mouse_constraint_ros.wire.interface import DESCRIPTION_QOS
from test_support.meshes import box as box_mesh, box_urdf, geometry, inertial, urdf, write
from test_support.ros_harness import RecordingBroadcaster, stamp_of

G = 9.80665
RATE_HZ = 1000.0
PIVOT = np.array([0.0, 0.0, 1.0])
AMPLITUDE = 0.02
SHIPPED_TOOL = Path(__file__).resolve().parent.parent / 'config' / 'tool.urdf'


class Link(NamedTuple):
    """A link as the test reads it: mass, COM and inertia (<inertial> frame), its rpy, URDF."""

    mass: float
    com: Tuple[float, float, float]
    rpy: Tuple[float, float, float]
    inertia: Tuple[float, ...]
    text: str

    @classmethod
    def read(cls, text: str) -> 'Link':
        """Return the link of a one-link URDF, read with the standard library's XML parser."""
        inertial_element = ElementTree.fromstring(text).find('link/inertial')
        origin = inertial_element.find('origin')

        def numbers(name: str) -> Tuple[float, ...]:
            return tuple(float(c) for c in origin.get(name, '0 0 0').split())
        moments = inertial_element.find('inertia')
        return cls(float(inertial_element.find('mass').get('value')), numbers('xyz'),
                   numbers('rpy'), tuple(float(moments.get(n)) for n in (
                       'ixx', 'ixy', 'ixz', 'iyy', 'iyz', 'izz')), text)

    def link_inertia(self) -> np.ndarray:
        """Return the inertia about the COM in the link's axes: R I R^T, R of the URDF rpy."""
        ixx, ixy, ixz, iyy, iyz, izz = self.inertia
        local = np.array([[ixx, ixy, ixz], [ixy, iyy, iyz], [ixz, iyz, izz]])
        turn = Rotation.from_euler('xyz', self.rpy).as_matrix()
        return turn @ local @ turn.T


def turned_tool() -> str:
    """Return a tool whose <inertial> frame is turned and has products of inertia of its own."""
    return urdf([inertial(1.3, (0.012, 0.001, -0.0008, 0.010, 0.0005, 0.004),
                          xyz=(0.03, -0.01, -0.22), rpy=(0.3, -0.2, 0.5)),
                 geometry('cylinder', radius=0.015, length=0.3, xyz=(0.0, 0.0, -0.15)),
                 geometry('box', size=(0.08, 0.03, 0.03), xyz=(0.0, 0.0, -0.3))],
                link='tool')


TOOLS = {'config/tool.urdf': lambda: SHIPPED_TOOL.read_text(), 'turned inertial': turned_tool}
# The turned tool's anchor is off the link origin, to place it through the link frame.
ANCHORS = {'config/tool.urdf': (0.0, 0.0, 0.0), 'turned inertial': (0.005, 0.0, 0.01)}


def pendulum(link: Link, anchor):
    """
    Return the slow mode of ``link`` hung by ``anchor`` at PIVOT: (period, start, direction).

    About the pivot, the inertia is I_p = I_w + m (L^2 E - d d^T), d the COM from the pivot
    (straight down, length L), and gravity stiffens the two tilts by m g L. The spin about the
    vertical is free (no stiffness), so the tilts' inertia is I_p's Schur complement over it;
    the generalized eigenproblem (m g L E2) u = w^2 M u gives the two modes. ``start`` is the
    link frame's pose (position, quaternion x y z w) tilted AMPLITUDE rad along the slower one,
    ``direction`` the horizontal unit vector the COM swings along.
    """
    arm = np.subtract(link.com, anchor)
    length = float(np.linalg.norm(arm))
    hang, _ = Rotation.align_vectors([[0.0, 0.0, -1.0]], [arm / length])
    world = hang.as_matrix() @ link.link_inertia() @ hang.as_matrix().T
    d = np.array([0.0, 0.0, -length])
    about_pivot = world + link.mass * (length ** 2 * np.eye(3) - np.outer(d, d))
    schur = about_pivot[:2, :2] - np.outer(about_pivot[:2, 2], about_pivot[2, :2]) / (
        about_pivot[2, 2])
    squares, modes = eigh(link.mass * G * length * np.eye(2), schur)
    slow = modes[:, 0] / np.linalg.norm(modes[:, 0])
    tilt = Rotation.from_rotvec(AMPLITUDE * np.array([slow[0], slow[1], 0.0])) * hang
    position = PIVOT - tilt.apply(anchor)
    swing = np.cross([slow[0], slow[1], 0.0], d)
    return (2.0 * math.pi / math.sqrt(squares[0]), (position, tilt.as_quat()),
            swing / np.linalg.norm(swing))


def crossings(times: np.ndarray, values: np.ndarray) -> np.ndarray:
    """Return the times ``values`` crosses zero, linearly interpolated between ticks."""
    sign = np.signbit(values)
    at = np.nonzero(sign[1:] != sign[:-1])[0]
    return times[at] - values[at] * (times[at + 1] - times[at]) / (values[at + 1] - values[at])


@pytest.mark.parametrize('tool', list(TOOLS))
def test_an_offset_com_full_inertia_link_swings_as_its_exact_physical_pendulum(
        simulated_body_factory, tool):
    """Through ROS, the period is the exact pendulum's within 0.5 %; pose and TF: the link."""
    link, anchor = Link.read(TOOLS[tool]()), ANCHORS[tool]
    assert all(link.inertia[i] for i in (1, 2, 4)), 'a full tensor: products of inertia'
    period, (position, orientation), swing = pendulum(link, anchor)
    broadcaster = RecordingBroadcaster()
    body = simulated_body_factory(
        robot_description=link.text, body_link='tool', rate_hz=RATE_HZ, anchor=anchor,
        initial_position=position, initial_orientation=orientation, angular_friction=0.0,
        marker_rate_hz=0.0, transform_broadcaster=broadcaster.factory)
    ticks = round(4.5 * period * RATE_HZ)
    times, along, pivot_error = np.empty(ticks), np.empty(ticks), 0.0
    for i in range(ticks):
        body.step()
        pose = body.pose
        com = pose.position + Rotation.from_quat(pose.orientation).apply(link.com)
        times[i], along[i] = pose.time, float(np.dot(com - PIVOT, swing))
        pivot_error = max(pivot_error, float(np.linalg.norm(body.anchor - PIVOT)))
    measured = 2.0 * float(np.mean(np.diff(crossings(times, along))))
    assert abs(measured / period - 1.0) < 0.005, (measured, period)
    assert pivot_error < 1e-4
    transform = broadcaster.sent[-1]
    assert (transform.header.frame_id, transform.child_frame_id) == ('world', 'tool')
    t = transform.transform.translation
    assert (t.x, t.y, t.z) == tuple(body.pose.position)


def test_pose_and_twist_are_of_the_link_frame_origin(simulated_body_factory):
    """Falling and spun by a torque: the twist's linear part is the pose's derivative."""
    body = simulated_body_factory(
        robot_description=turned_tool(), rate_hz=RATE_HZ, hold_initial_anchor=False,
        initial_position=PIVOT, marker_rate_hz=0.0, wrench_timeout=0.0)
    reader = Node('reader', context=body.context)
    poses, twists = [], []
    reader.create_subscription(PoseStamped, 'pose', poses.append, 400)
    reader.create_subscription(TwistStamped, 'twist', twists.append, 400)
    body.add_node(reader)
    body.wrench((0.0, 0.0, 0.0), (0.02, -0.01, 0.03))
    body.step(300)
    assert [stamp_of(p) for p in poses] == [stamp_of(t) for t in twists]
    assert len(poses) == 300 and twists[-1].header.frame_id == 'world'
    x = np.array([[p.pose.position.x, p.pose.position.y, p.pose.position.z] for p in poses])
    v = np.array([[t.twist.linear.x, t.twist.linear.y, t.twist.linear.z] for t in twists])
    w = np.array([[t.twist.angular.x, t.twist.angular.y, t.twist.angular.z] for t in twists])
    q = np.array([[p.pose.orientation.x, p.pose.orientation.y, p.pose.orientation.z,
                   p.pose.orientation.w] for p in poses])
    # The step's position update is a substep's velocity behind the central difference: at
    # most a tick of gravity. The COM's velocity, v + w x R c, is far from it.
    central = (x[2:] - x[:-2]) * (RATE_HZ / 2.0)
    assert float(np.max(np.linalg.norm(central - v[1:-1], axis=1))) < G / RATE_HZ
    com_offset = np.cross(w, Rotation.from_quat(q).apply(Link.read(turned_tool()).com))
    assert float(np.max(np.linalg.norm(com_offset, axis=1))) > 0.1
    first = poses[0].pose.position
    assert np.linalg.norm(np.array([first.x, first.y, first.z]) - PIVOT) < 1e-4


def run(body, ticks: int) -> list:
    """Step ``body`` with a drag onto the floor; return every pose and twist as floats."""
    out = []
    body.step()
    body.grab(body.anchor)
    for i in range(ticks):
        if i % 10 == 0:
            body.target((0.3 * math.sin(i / 200.0), 0.1 * i / ticks, 0.3 - 0.3 * i / ticks))
        body.step()
        out.append((*body.pose.position, *body.pose.orientation, *body.twist.linear,
                    *body.twist.angular))
    return out


# The box parameters' runs, by their parameters: a run is the same floats whichever test ran it.
BOX_RUNS = {}


@pytest.mark.parametrize('kind', ['solid', 'typed', 'mesh'])
def test_a_box_urdf_reproduces_the_box_parameters_bit_for_bit(
        simulated_body_factory, kind, tmp_path):
    """
    The same body as box parameters, a URDF box or a URDF mesh cuboid: the same floats each tick.

    The drag takes it onto the floor, where the box's corners and the mesh's hull vertices are
    the same contacts in the same order. The edges are binary fractions: an STL file stores
    float32 vertices, and these are exact in it.
    """
    size, mass = (0.5, 0.25, 0.125), 2.0
    common = {'floor': True, 'initial_position': (0.0, 0.0, 0.3), 'marker_rate_hz': 0.0,
              'anchor': (0.25, 0.125, 0.0625)}
    box = {'box_size': size, 'mass': mass}
    if kind == 'solid':
        text = box_urdf(mass, size)
    elif kind == 'mesh':
        path = write(box_mesh(size), tmp_path / 'cuboid.stl')
        solid = RigidBody.solid_box(mass, size)
        text = urdf([inertial(mass, solid.inertia), geometry('mesh', filename=str(path))])
    else:
        box['inertia'] = (0.011, 0.001, 0.0, 0.03, 0.0, 0.035)
        text = urdf([inertial(mass, box['inertia']), geometry('box', size=size)])
    key = repr(box)
    if key not in BOX_RUNS:  # 'solid' and 'mesh' are the same box parameters: one run for both
        BOX_RUNS[key] = run(simulated_body_factory(**box, **common), 1500)
    as_box = BOX_RUNS[key]
    as_urdf = run(simulated_body_factory(robot_description=text, **common), 1500)
    assert as_urdf == as_box
    assert min(row[2] for row in as_box) < 0.07  # it reached the floor (half height 0.0625)


def test_the_urdf_is_offered_latched_on_robot_description(simulated_body_factory):
    """A reader that comes late (as RViz does) gets the URDF; a new URDF follows; a box: none."""
    text = turned_tool()
    body = simulated_body_factory(robot_description=text, marker_rate_hz=0.0)
    box = simulated_body_factory(namespace='/box', marker_rate_hz=0.0)
    body.step(5)
    box.step(5)
    reader = Node('description_reader', context=body.context)
    texts = []
    reader.create_subscription(String, 'robot_description', lambda m: texts.append(m.data),
                               DESCRIPTION_QOS)
    body.add_node(reader)
    box_reader = Node('box_description_reader', namespace='/box', context=box.context)
    box_texts = []
    box_reader.create_subscription(String, 'robot_description',
                                   lambda m: box_texts.append(m.data), DESCRIPTION_QOS)
    box.add_node(box_reader)
    # Matching takes a drain or a few on a busy machine; the latched sample comes with it.
    body.step_until(lambda: bool(texts), max_ticks=100)
    box.step(100)
    assert texts == [text] and box_texts == []
    sphere = urdf([inertial(1.0, (0.004, 0.0, 0.0, 0.004, 0.0, 0.004)),
                   geometry('sphere', radius=0.1)], link='ball')
    body.set_parameters(robot_description=sphere, anchor=(0.0, 0.0, 0.1))
    body.step_until(lambda: len(texts) > 1, max_ticks=100)
    assert texts == [text, sphere]
