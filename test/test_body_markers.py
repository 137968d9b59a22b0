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
The body's RViz markers of a URDF link: a marker per piece, each at the link pose and its origin.

The link below has four visual pieces, each turned and moved by its own origin: a red box, a
sphere, a cylinder and the mug mesh at twice its size, and a collision sphere. At a link pose
turned a quarter about z, each marker's pose is the composition worked out by hand: x + R t and
q q_piece; a 4 x 4 product of the two transforms checks them all once more.
"""

import math
from pathlib import Path

import numpy as np
import pytest
from scipy.spatial.transform import Rotation
from visualization_msgs.msg import Marker, MarkerArray

from mouse_constraint_ros.description import BodyGeometry
from mouse_constraint_ros.description.body_geometry import Piece
from mouse_constraint_ros.description.urdf_link import body_model
from mouse_constraint_ros.monitoring.body_markers import (compose, drawn_pieces, mesh_resource,
                                                          placed)
from mouse_constraint_ros.monitoring.markers import BODY_COLOR, marker_array, SPHERE_FRACTION
from mouse_constraint_ros.physics import BodyState
from mouse_constraint_ros.wire.messages import stamp_nanoseconds
from test_support.marker_viewer import marker_viewer
from test_support.meshes import cube, geometry, inertial, mug, urdf, write

HALF = math.sqrt(0.5)
# The link's pose: at (1, 2, 3), turned a quarter about z.
LINK = BodyState((1.0, 2.0, 3.0), (0.0, 0.0, HALF, HALF))
RED = (1.0, 0.0, 0.0, 1.0)
WEIGHT = inertial(0.5, (0.001, 0.0, 0.0, 0.001, 0.0, 0.001), xyz=(0.0, 0.0, 0.02))


def visual(kind: str, **keywords) -> str:
    """Return a ``<visual>`` element (``meshes.geometry``'s)."""
    return geometry(kind, element='visual', **keywords)


def red_box() -> str:
    """Return a visual box with a red material, its origin at (0.1, 0, 0) turned 90 deg on z."""
    element = visual('box', size=(0.04, 0.02, 0.01), xyz=(0.1, 0.0, 0.0),
                     rpy=(0.0, 0.0, math.pi / 2))
    return element.replace('</visual>', '<material name="red"><color rgba="1 0 0 1"/>'
                                        '</material></visual>')


def tool(folder: Path) -> BodyGeometry:
    """Return the link of four visuals and one collision sphere, its mug in ``folder``."""
    path = write(mug(), folder / 'mug.stl')
    return body_model(urdf([
        WEIGHT, red_box(),
        visual('sphere', radius=0.03, xyz=(0.0, 0.0, 0.05)),
        visual('cylinder', radius=0.01, length=0.2, xyz=(0.0, 0.2, 0.0),
               rpy=(math.pi / 2, 0.0, 0.0)),
        visual('mesh', filename=str(path), scale=(2.0, 2.0, 2.0), xyz=(0.0, 0.0, -0.1)),
        geometry('sphere', radius=0.05)])).geometry


def matrix(position, orientation) -> np.ndarray:
    """Return the 4 x 4 transform of a position and a quaternion (x, y, z, w)."""
    transform = np.eye(4)
    transform[:3, :3] = Rotation.from_quat(orientation).as_matrix()
    transform[:3, 3] = position
    return transform


def xyz(vector) -> tuple:
    """Return the x, y, z of a Point or Vector3 message."""
    return (vector.x, vector.y, vector.z)


def quaternion(message) -> tuple:
    """Return the x, y, z, w of a Quaternion message."""
    return (message.x, message.y, message.z, message.w)


def body_of(array: MarkerArray) -> list:
    """Return the markers of the body namespace, by id."""
    return sorted((m for m in array.markers if m.ns == 'body'), key=lambda m: m.id)


def test_each_visual_piece_is_a_marker_at_the_link_pose_composed_with_its_origin(tmp_path):
    """
    Box, sphere, cylinder and mesh: CUBE, SPHERE, CYLINDER, MESH_RESOURCE at x + R t, q q_p.

    The box's origin (0.1, 0, 0) turned a quarter on z lands at (1, 2.1, 3), turned a half; the
    cylinder's (0, 0.2, 0) turned a quarter on x at (0.8, 2, 3), turned (1/2, 1/2, 1/2, 1/2).
    The mesh is its file's URI at the URDF's scale; the red box keeps its colour.
    """
    geometry_ = tool(tmp_path)
    array = marker_array(frame_id='map', stamp_ns=7, box_size=geometry_.extents,
                         state=LINK.moved(geometry_.com), anchor=(1.0, 2.0, 3.0), target=None,
                         force=(0.0, 0.0, 0.0), reference=1.0,
                         pieces=drawn_pieces(geometry_, BODY_COLOR), link_pose=LINK)
    box, sphere, cylinder, mesh = body_of(array)
    assert [m.id for m in (box, sphere, cylinder, mesh)] == [0, 1, 2, 3]
    assert [m.type for m in (box, sphere, cylinder, mesh)] == [
        Marker.CUBE, Marker.SPHERE, Marker.CYLINDER, Marker.MESH_RESOURCE]
    for marker in (box, sphere, cylinder, mesh):
        assert marker.header.frame_id == 'map' and stamp_nanoseconds(marker.header.stamp) == 7
        assert marker.action == Marker.ADD
    assert xyz(box.pose.position) == pytest.approx((1.0, 2.1, 3.0), abs=1e-15)
    assert quaternion(box.pose.orientation) == pytest.approx((0.0, 0.0, 1.0, 0.0), abs=1e-15)
    assert xyz(box.scale) == (0.04, 0.02, 0.01)
    assert (box.color.r, box.color.g, box.color.b, box.color.a) == RED
    assert xyz(sphere.pose.position) == pytest.approx((1.0, 2.0, 3.05), abs=1e-15)
    assert quaternion(sphere.pose.orientation) == pytest.approx(LINK.orientation, abs=1e-15)
    assert xyz(sphere.scale) == (0.06, 0.06, 0.06)
    assert sphere.color.a == pytest.approx(BODY_COLOR[3])
    assert xyz(cylinder.pose.position) == pytest.approx((0.8, 2.0, 3.0), abs=1e-15)
    assert quaternion(cylinder.pose.orientation) == pytest.approx((0.5,) * 4, abs=1e-15)
    assert xyz(cylinder.scale) == (0.02, 0.02, 0.2)
    assert xyz(mesh.pose.position) == pytest.approx((1.0, 2.0, 2.9), abs=1e-15)
    assert mesh.mesh_resource == (tmp_path / 'mug.stl').as_uri()
    assert mesh.mesh_resource.startswith('file:///')
    assert xyz(mesh.scale) == (2.0, 2.0, 2.0)
    # Every piece once more: the marker's pose is the product of the two transforms.
    link = matrix(LINK.position, LINK.orientation)
    for marker, piece in zip((box, sphere, cylinder, mesh), geometry_.visuals):
        expected = link @ piece.transform
        drawn = matrix(xyz(marker.pose.position), quaternion(marker.pose.orientation))
        np.testing.assert_allclose(drawn, expected, rtol=0.0, atol=1e-15)
    # The other markers scale with the box about the collision sphere: 0.1 m.
    [anchor] = [m for m in array.markers if m.ns == 'anchor']
    assert geometry_.extents == pytest.approx((0.1, 0.1, 0.1), abs=1e-12)
    assert anchor.scale.x == SPHERE_FRACTION * max(geometry_.extents)


def test_a_link_without_visuals_is_drawn_by_its_collision_pieces(tmp_path):
    """No ``<visual>``: the collision sphere and the mug, as they are grabbed and land."""
    path = write(mug(), tmp_path / 'mug.stl')
    geometry_ = body_model(urdf([WEIGHT, geometry('sphere', radius=0.05, xyz=(0.0, 0.0, 0.2)),
                                 geometry('mesh', filename=str(path))])).geometry
    sphere, mesh = placed(drawn_pieces(geometry_, BODY_COLOR), LINK)
    assert (sphere.kind, mesh.kind) == (Marker.SPHERE, Marker.MESH_RESOURCE)
    assert sphere.position == pytest.approx((1.0, 2.0, 3.2), abs=1e-15)
    assert sphere.scale == (0.1, 0.1, 0.1) and mesh.scale == (1.0, 1.0, 1.0)
    assert mesh.position == LINK.position and mesh.orientation == LINK.orientation
    assert sphere.color == mesh.color == BODY_COLOR


def test_mesh_resources_are_the_uris_rviz_loads():
    """package:// and file:// as named; an absolute path its file:// URI; otherwise none."""
    assert mesh_resource('package://tools/meshes/mug.stl') == 'package://tools/meshes/mug.stl'
    assert mesh_resource('file:///srv/mug.dae') == 'file:///srv/mug.dae'
    assert mesh_resource('/srv/my meshes/mug.stl') == 'file:///srv/my%20meshes/mug.stl'
    assert mesh_resource('meshes/mug.stl') == mesh_resource('') == ''
    assert mesh_resource('http://example.org/mug.stl') == ''


def test_a_mesh_rviz_cannot_load_is_drawn_as_its_triangles():
    """A mesh piece without a loadable URI: a TRIANGLE_LIST of its triangles, its own frame."""
    turn = np.eye(4)
    turn[:3, :3] = Rotation.from_euler('x', 0.4).as_matrix()
    turn[:3, 3] = (0.0, 0.1, 0.0)
    mesh = cube(0.1)
    geometry_ = BodyGeometry('block', (0.0, 0.0, 0.0), (Piece('mesh', turn, mesh=mesh),))
    array = marker_array(frame_id='map', stamp_ns=0, box_size=(0.1, 0.1, 0.1), state=LINK,
                         anchor=(0.0, 0.0, 0.0), target=None, force=(0.0, 0.0, 0.0),
                         reference=1.0, pieces=drawn_pieces(geometry_, BODY_COLOR))
    [drawn] = body_of(array)
    assert drawn.type == Marker.TRIANGLE_LIST and drawn.mesh_resource == ''
    assert xyz(drawn.scale) == (1.0, 1.0, 1.0)
    assert [xyz(p) for p in drawn.points] == [
        tuple(v) for v in mesh.vertices[mesh.faces].reshape(-1, 3)]
    assert len(drawn.points) == 36
    np.testing.assert_allclose(
        matrix(xyz(drawn.pose.position), quaternion(drawn.pose.orientation)),
        matrix(LINK.position, LINK.orientation) @ turn, rtol=0.0, atol=1e-15)


def test_the_box_through_the_pieces_is_todays_box_marker():
    """The box body's one piece, at a frame at the COM, is the CUBE marker_array always drew."""
    box = (0.3, 0.2, 0.1)
    state = BodyState((0.1, -0.2, 0.9), tuple(Rotation.from_euler('zx', [0.3, 0.2]).as_quat()))
    common = {'frame_id': 'map', 'stamp_ns': 5, 'box_size': box, 'state': state,
              'anchor': (0.0, 0.0, 1.0), 'target': (0.0, 0.1, 1.0), 'force': (0.0, 0.0, 1.0),
              'reference': 2.0}
    today = marker_array(**common)
    pieces = marker_array(pieces=drawn_pieces(BodyGeometry.box(box), BODY_COLOR), **common)
    assert pieces == today
    assert xyz(today.markers[0].pose.position) == state.position


def test_body_markers_past_the_new_pieces_are_deleted():
    """Four pieces drawn before, two now: ids 0 and 1 drawn, 2 and 3 deleted, nothing more."""
    pieces = drawn_pieces(BodyGeometry('two', (0.0, 0.0, 0.0), (
        Piece('sphere', np.eye(4), (0.1,)), Piece('box', np.eye(4), (0.1, 0.2, 0.3)))),
        BODY_COLOR)
    common = {'frame_id': 'map', 'stamp_ns': 0, 'box_size': (0.3, 0.3, 0.3), 'state': LINK,
              'anchor': (0.0, 0.0, 0.0), 'target': None, 'force': (0.0, 0.0, 0.0),
              'reference': 1.0, 'pieces': pieces}
    drawn = body_of(marker_array(previous_pieces=4, **common))
    assert [(m.id, m.action) for m in drawn] == [
        (0, Marker.ADD), (1, Marker.ADD), (2, Marker.DELETE), (3, Marker.DELETE)]
    assert [m.id for m in body_of(marker_array(previous_pieces=2, **common))] == [0, 1]


def test_quaternions_compose_as_turns_do():
    """compose(a, b) is the turn b then a: its matrix is the product of theirs."""
    a, b = Rotation.from_euler('xyz', [0.3, -0.2, 1.1]), Rotation.from_euler('zyx', [0.7, 0.1, 2])
    product = compose(tuple(a.as_quat()), tuple(b.as_quat()))
    np.testing.assert_allclose(Rotation.from_quat(product).as_matrix(),
                               a.as_matrix() @ b.as_matrix(), rtol=0.0, atol=1e-15)
    assert math.fsum(c * c for c in product) == pytest.approx(1.0, abs=1e-15)


def test_the_node_draws_its_urdf_link_at_the_published_link_pose(simulated_body_factory):
    """
    ~/markers of a URDF body: the link's pieces at the link pose the node publishes on ``pose``.

    The link frame is not the COM (0.02 m up): the pieces go by the published pose, each at
    its composition with the piece's origin.
    """
    text = urdf([WEIGHT, red_box(), visual('sphere', radius=0.03, xyz=(0.0, 0.0, 0.05)),
                 geometry('sphere', radius=0.05)])
    geometry_ = body_model(text).geometry
    body = simulated_body_factory(robot_description=text, rate_hz=200.0, marker_rate_hz=20.0,
                                  initial_orientation=list(LINK.orientation),
                                  angular_damping=0.0, gravity=[0.0, 0.0, 0.0],
                                  hold_initial_anchor=False)
    arrays, poses = marker_viewer(body)
    body.step(10)
    body.step_until(lambda: len(arrays) > 1, max_ticks=100_000)
    box, sphere = body_of(arrays[-1])
    pose = poses[stamp_nanoseconds(box.header.stamp)].pose
    link = matrix(xyz(pose.position), quaternion(pose.orientation))
    assert xyz(pose.position) != tuple(body.node.simulation.state.position)
    for marker, piece in zip((box, sphere), geometry_.visuals):
        drawn = matrix(xyz(marker.pose.position), quaternion(marker.pose.orientation))
        np.testing.assert_allclose(drawn, link @ piece.transform, rtol=0.0, atol=1e-15)
    assert (box.type, sphere.type) == (Marker.CUBE, Marker.SPHERE)
    assert (box.color.r, box.color.g, box.color.b, box.color.a) == RED
