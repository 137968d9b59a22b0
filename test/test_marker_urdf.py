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
``mouse_marker`` with a URDF body: a sphere and the mug, drawn as they are and pressed on them.

The link has two collision pieces and no visual: a sphere of 5 cm above the mug (a closed cup, 8
cm wide and 10 cm high, open at the top). The marker draws both, in the link frame, at the link
pose the node publishes. A press is a grab where it lies on a piece (within ``grab_margin``), the
point RViz picks being where a ray from the camera first meets the surface (``BodyGeometry.ray``);
a press in the mug's cavity, or beside the sphere in the corner of its bounding box, is inside
the box about the pieces but on no piece: no grab, the drag moves the anchor.
"""

import math
from pathlib import Path

import numpy as np
import pytest
from rcl_interfaces.msg import ParameterType, ParameterValue
from scipy.spatial.transform import Rotation
from visualization_msgs.msg import InteractiveMarkerFeedback, Marker

from mouse_constraint_ros.description import BodyGeometry
from mouse_constraint_ros.description.urdf_link import body_model
from mouse_constraint_ros.marker.drag import MarkerDrag
from mouse_constraint_ros.marker.node import MouseMarkerNode
from mouse_constraint_ros.marker.updates import (body_marker, MARKER_NAME, pose_message,
                                                 pose_of, SCALE_FRACTION)
from mouse_constraint_ros.pointer.geometry import local_point, Pose, world_point
from mouse_constraint_ros.pointer.gestures import Action, GRAB, TARGET
from mouse_constraint_ros.pointer.node_readouts import ViewParameters
from test_support.meshes import geometry, inertial, mug, MUG_BOTTOM, MUG_RADIUS, urdf, write

SPHERE_CENTER, SPHERE_RADIUS = (0.0, 0.0, 0.2), 0.05
ANCHOR = (0.0, 0.0, 0.05)
SHOWN = Pose((0.0, 0.0, 1.0), tuple(Rotation.from_euler('z', 0.3).as_quat()))
NOW = Pose((0.05, 0.0, 0.98), tuple(Rotation.from_euler('zy', [0.35, 0.1]).as_quat()))
MARGIN = 0.01


def cup_urdf(folder: Path) -> str:
    """Return the URDF of the sphere above the mug, the mug's file in ``folder``."""
    path = write(mug(), Path(folder) / 'mug.stl')
    return urdf([inertial(0.4, (0.002, 0.0, 0.0, 0.002, 0.0, 0.001), xyz=(0.0, 0.0, 0.06)),
                 geometry('sphere', radius=SPHERE_RADIUS, xyz=SPHERE_CENTER),
                 geometry('mesh', filename=str(path))])


@pytest.fixture
def cup(tmp_path) -> BodyGeometry:
    """Return the sphere and the mug's geometry."""
    return body_model(cup_urdf(tmp_path)).geometry


def picked(geometry_: BodyGeometry, pose: Pose, camera, toward) -> tuple:
    """Return the world point RViz picks: where the ray from ``camera`` meets the body first."""
    local_camera = local_point(camera, pose)
    direction = np.subtract(local_point(toward, pose), local_camera)
    t = geometry_.ray(local_camera, direction)
    assert t is not None
    return world_point(pose, tuple(np.add(local_camera, t * direction)))


def test_a_press_on_the_sphere_or_the_mug_grabs_where_the_ray_met_it(cup):
    """The picked points of the sphere's top and the mug's wall are grabs, at the latest pose."""
    above = world_point(SHOWN, (0.0, 0.0, 2.0))
    top = picked(cup, SHOWN, above, world_point(SHOWN, SPHERE_CENTER))
    assert local_point(top, SHOWN) == pytest.approx((0.0, 0.0, 0.25), abs=1e-12)
    side = picked(cup, SHOWN, world_point(SHOWN, (1.0, 0.0, 0.05)),
                  world_point(SHOWN, (0.0, 0.0, 0.05)))
    # The mug's side is a polygon of 48 sections: its vertex on +x is at the full radius, to
    # the float32 the STL file stores.
    assert local_point(side, SHOWN) == pytest.approx((MUG_RADIUS, 0.0, 0.05), abs=1e-8)
    for point in (top, side):
        drag = MarkerDrag()
        [grab] = drag.press('/rviz', shown=SHOWN, hit=point, now=NOW, anchor=ANCHOR,
                            geometry=cup, margin=MARGIN)
        assert grab.kind == GRAB
        assert grab.point == pytest.approx(world_point(NOW, local_point(point, SHOWN)),
                                           abs=1e-12)


@pytest.mark.parametrize('local', [
    (0.0, 0.0, 0.06),  # in the mug's cavity: 3.5 cm from its wall, 5.2 cm above its bottom
    (0.035, 0.035, 0.235),  # beside the sphere, in its bounding box's corner: 1.1 cm off it
], ids=['in the cavity', 'beside the sphere'])
def test_a_press_inside_the_box_about_the_pieces_but_off_them_drags_the_anchor(cup, local):
    """No grab: the point is farther than grab_margin from both pieces; the anchor is dragged."""
    low, high = np.array([-0.05, -0.05, 0.0]), np.array([0.05, 0.05, 0.25])
    assert np.all(low <= local) and np.all(local <= high)  # inside the box about the pieces
    assert cup.distance(local) > MARGIN
    drag = MarkerDrag()
    assert drag.press('/rviz', shown=SHOWN, hit=world_point(SHOWN, local), now=NOW,
                      anchor=ANCHOR, geometry=cup, margin=MARGIN) == []
    moved = Pose((0.3, 0.2, 1.1), SHOWN.orientation)
    assert drag.move('/rviz', moved) == [Action(TARGET, world_point(moved, ANCHOR))]
    # On a box about the pieces the same point is a grab.
    assert MarkerDrag().press('/rviz', shown=SHOWN, hit=world_point(SHOWN, local), now=NOW,
                              anchor=ANCHOR, geometry=BodyGeometry.box((0.1, 0.1, 0.5)),
                              margin=MARGIN)


def test_the_marker_draws_the_pieces_in_the_link_frame_at_the_link_pose(cup, tmp_path):
    """A SPHERE at its origin and the mug's MESH_RESOURCE, in the marker's frame, both scaled."""
    marker = body_marker(frame_id='world', geometry=cup, pose=NOW)
    assert pose_of(marker.pose) == NOW and marker.header.frame_id == 'world'
    [control] = marker.controls
    sphere, mesh = control.markers
    assert (sphere.type, mesh.type) == (Marker.SPHERE, Marker.MESH_RESOURCE)
    assert sphere.header.frame_id == mesh.header.frame_id == ''  # relative to the marker
    position = sphere.pose.position
    assert (position.x, position.y, position.z) == SPHERE_CENTER
    assert (sphere.scale.x, sphere.scale.y, sphere.scale.z) == (0.1, 0.1, 0.1)
    assert mesh.mesh_resource == (tmp_path / 'mug.stl').as_uri()
    assert (mesh.pose.position.x, mesh.pose.position.y, mesh.pose.position.z) == (0.0,) * 3
    assert mesh.pose.orientation.w == 1.0
    assert marker.scale == pytest.approx(SCALE_FRACTION * 0.25, abs=1e-12)


def test_the_followed_parameters_take_the_urdf_body():
    """robot_description, body_link and density are read; a negative density is passed over."""
    def value(kind: int, **fields) -> ParameterValue:
        return ParameterValue(type=kind, **fields)
    parameters = ViewParameters().with_values([
        ('robot_description', value(ParameterType.PARAMETER_STRING, string_value='<robot/>')),
        ('body_link', value(ParameterType.PARAMETER_STRING, string_value='cup')),
        ('density', value(ParameterType.PARAMETER_DOUBLE, double_value=800.0))])
    assert (parameters.robot_description, parameters.body_link, parameters.density) == (
        '<robot/>', 'cup', 800.0)
    assert parameters.with_values([
        ('density', value(ParameterType.PARAMETER_DOUBLE, double_value=-1.0)),
        ('body_link', value(ParameterType.PARAMETER_INTEGER, integer_value=3)),
        ('density', value(ParameterType.PARAMETER_DOUBLE, double_value=math.nan))]) == parameters


class FakeClock:
    """A monotonic clock that stands still until told: ``now`` seconds."""

    def __init__(self) -> None:
        """Start at 10 s."""
        self.now = 10.0

    def __call__(self) -> float:
        """Return the time (s)."""
        return self.now


def press(marker: MouseMarkerNode, clock: FakeClock, shown: Pose, point) -> None:
    """Hand the marker a press at ``point`` on the body shown at ``shown``, a slot later."""
    clock.now += 1.0
    feedback = InteractiveMarkerFeedback(
        client_id='/rviz', marker_name=MARKER_NAME, control_name='drag',
        event_type=InteractiveMarkerFeedback.MOUSE_DOWN, pose=pose_message(shown),
        mouse_point_valid=True)
    feedback.mouse_point.x, feedback.mouse_point.y, feedback.mouse_point.z = point
    marker._on_feedback(feedback)


def release(marker: MouseMarkerNode, clock: FakeClock, shown: Pose) -> None:
    """Hand the marker the release, a slot later, and let it go."""
    clock.now += 1.0
    marker._on_feedback(InteractiveMarkerFeedback(
        client_id='/rviz', marker_name=MARKER_NAME, control_name='drag',
        event_type=InteractiveMarkerFeedback.MOUSE_UP, pose=pose_message(shown)))


def test_the_marker_node_draws_and_grabs_the_urdf_body_in_lockstep(
        simulated_body_factory, tmp_path):
    """
    Beside the node stepped in lockstep: the marker learns the link, draws it, grabs on it.

    The marker's pose is the link pose the node publishes (not the COM); its control draws the
    sphere and the mug. A press on the mug's wall becomes the node's anchor (the link-frame
    point); one in the mug's cavity sends no grab, and the anchor stays.
    """
    text = cup_urdf(tmp_path)
    body = simulated_body_factory(robot_description=text, rate_hz=100.0,
                                  gravity=[0.0, 0.0, 0.0], hold_initial_anchor=False,
                                  anchor=list(ANCHOR), marker_rate_hz=0.0)
    clock = FakeClock()
    marker = body.add_node(MouseMarkerNode(context=body.context, clock=clock))
    grabs = []
    send = marker.grab_publisher.publish
    marker.grab_publisher.publish = lambda message: (grabs.append(message), send(message))
    marker.follower.look()
    body.step_until(lambda: marker.follower.parameters_known, max_ticks=100)
    assert marker.parameters.robot_description == text
    body.step(1)
    marker._work()
    [drawn] = marker.updates.current()
    shown = pose_of(drawn.pose)
    assert shown == Pose(tuple(body.pose.position), tuple(body.pose.orientation))
    assert shown.position != tuple(body.node.simulation.state.position)  # the COM is 6 cm up
    sphere, mesh = drawn.controls[0].markers
    assert (sphere.type, mesh.type) == (Marker.SPHERE, Marker.MESH_RESOURCE)
    wall = (0.0, -MUG_RADIUS, 0.05)  # the mug's wall, where its section's vertex is
    press(marker, clock, shown, world_point(shown, wall))
    body.step(1)
    assert len(grabs) == 1
    assert tuple(body.node.get_parameter('anchor').value) == pytest.approx(wall, abs=1e-9)
    release(marker, clock, shown)
    marker._work()
    body.step(1)
    assert body.node.simulation.target is None
    cavity = (0.0, 0.0, MUG_BOTTOM + 0.03)
    press(marker, clock, shown, world_point(shown, cavity))
    marker._work()
    body.step(1)
    assert len(grabs) == 1 and marker.drag.dragging
    assert tuple(body.node.get_parameter('anchor').value) == pytest.approx(wall, abs=1e-9)
