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

"""The body's shape of the node's parameters, and a click's ray on a URDF body (the mug)."""

import math

from hypothesis import given, settings, strategies as st
import numpy as np
import pytest
from rcl_interfaces.msg import ParameterType, ParameterValue
from scipy.spatial.transform import Rotation
import trimesh

from mouse_constraint_ros.description import BodyGeometry
from mouse_constraint_ros.description.body_geometry import lone_box
from mouse_constraint_ros.description.urdf_link import body_model
from mouse_constraint_ros.node.body_parameters import GEOMETRY_PARAMETERS
from mouse_constraint_ros.pointer.body_shape import BodyShape, ray_body_hit
from mouse_constraint_ros.pointer.geometry import local_point, Pose, ray_box_hit, world_point
from mouse_constraint_ros.pointer.gestures import Gestures, GRAB, RELEASE
from mouse_constraint_ros.pointer.node_follower import PARAMETER_NAMES
from mouse_constraint_ros.pointer.node_readouts import ViewParameters
from test_support.meshes import geometry, MUG_BOTTOM, MUG_HEIGHT, MUG_RADIUS, urdf, write
from test_support.meshes import mug as mug_mesh
from test_support.robots import double_pendulum

# The mug's origin in its link frame: moved and turned, so that the link frame is not the mesh's.
MUG_XYZ, MUG_RPY = (0.01, -0.02, 0.03), (0.2, -0.1, 0.3)
TURNED = Pose((0.3, -0.2, 1.0), tuple(Rotation.from_euler('zyx', [0.7, -0.3, 0.4]).as_quat()))
unit = st.floats(-1.0, 1.0, allow_nan=False)


@pytest.fixture(scope='module')
def mug_urdf(tmp_path_factory) -> str:
    """Return the URDF of the mug, its mesh written to a file named by absolute path."""
    path = write(mug_mesh(), tmp_path_factory.mktemp('mug') / 'mug.stl')
    return urdf([geometry('mesh', filename=str(path), xyz=MUG_XYZ, rpy=MUG_RPY)])


@pytest.fixture(scope='module')
def mug(mug_urdf) -> BodyGeometry:
    """Return the mug's geometry, as the node makes it (inertia at a density)."""
    return body_model(mug_urdf, density=1000.0).geometry


def _in_link_frame(point) -> np.ndarray:
    """Return a point of the mesh's own frame in the link frame (the URDF origin)."""
    rotation = Rotation.from_euler('xyz', MUG_RPY).as_matrix()
    return rotation @ np.asarray(point, dtype=float) + MUG_XYZ


def _trimesh_hit(surface: trimesh.Trimesh, origin, direction):
    """Return trimesh's own nearest hit (t >= 0) of a link-frame ray on the surface, or None."""
    hits, _, _ = surface.ray.intersects_location([origin], [direction])
    if not len(hits):
        return None
    t = (hits - origin) @ direction
    ahead = t >= 0.0
    return hits[ahead][np.argmin(t[ahead])] if ahead.any() else None


@settings(max_examples=60, deadline=None)
@given(st.tuples(unit, unit, unit), st.tuples(unit, unit, unit))
def test_a_click_ray_meets_the_mesh_where_trimesh_does(mug, aim, side):
    """From outside the turned mug towards a point in its bounds: trimesh's own hit, to 1e-9."""
    surface = mug.surface(collision=True)
    low, high = surface.bounds
    target = low + (np.array(aim) + 1.0) / 2.0 * (high - low)
    offset = np.array(side) + (0.0, 0.0, 1.5)
    origin_local = target + 0.3 * offset / np.linalg.norm(offset)
    direction_local = target - origin_local
    origin = world_point(TURNED, origin_local)
    direction = world_point(TURNED, direction_local)
    direction = np.subtract(direction, TURNED.position)
    hit = ray_body_hit(origin, direction, pose=TURNED, geometry=mug)
    expected = _trimesh_hit(surface, origin_local, direction_local)
    if expected is None:
        assert hit is None
        return
    assert hit is not None
    local = np.array(local_point(hit, TURNED))
    assert np.linalg.norm(local - expected) <= 1e-9
    _, distance, _ = trimesh.proximity.closest_point(surface, [local])
    assert distance[0] <= 1e-9


def test_a_ray_down_the_axis_meets_the_bottom_inside_the_cup_not_its_rim(mug):
    """Straight down the mug's axis: the inside of its bottom, where no box or hull would be."""
    top = _in_link_frame((0.0, 0.0, MUG_HEIGHT + 0.2))
    down = _in_link_frame((0.0, 0.0, -1.0)) - _in_link_frame((0.0, 0.0, 0.0))
    origin = world_point(TURNED, top)
    direction = np.subtract(world_point(TURNED, down), TURNED.position)
    hit = ray_body_hit(origin, direction, pose=TURNED, geometry=mug)
    assert hit is not None
    bottom = world_point(TURNED, _in_link_frame((0.0, 0.0, MUG_BOTTOM)))
    assert np.linalg.norm(np.subtract(hit, bottom)) <= 1e-9
    assert mug.distance(local_point(hit, TURNED)) <= 1e-9


def test_a_ray_beside_the_mesh_misses_it(mug):
    """Down beside the mug's wall, 1 cm off; pointing away; no direction: no hit."""
    beside = world_point(TURNED, _in_link_frame((MUG_RADIUS + 0.01, 0.0, MUG_HEIGHT + 0.2)))
    down = np.subtract(world_point(TURNED, _in_link_frame((0.0, 0.0, -1.0))),
                       world_point(TURNED, _in_link_frame((0.0, 0.0, 0.0))))
    assert ray_body_hit(beside, down, pose=TURNED, geometry=mug) is None
    above = world_point(TURNED, _in_link_frame((0.0, 0.0, MUG_HEIGHT + 0.2)))
    assert ray_body_hit(above, -down, pose=TURNED, geometry=mug) is None
    assert ray_body_hit(above, (0.0, 0.0, 0.0), pose=TURNED, geometry=mug) is None
    assert ray_body_hit(above, (math.nan, 0.0, -1.0), pose=TURNED, geometry=mug) is None


def test_a_click_on_the_mug_grabs_where_its_ray_meets_the_mesh(mug):
    """Gestures.click on a mesh body: the grab at the mesh point, then the release."""
    at_rest = Pose((0.0, 0.0, 1.0), (0.0, 0.0, 0.0, 1.0))
    origin = np.add(_in_link_frame((0.0, 0.0, MUG_HEIGHT + 0.2)), at_rest.position)
    direction = _in_link_frame((0.0, 0.0, -1.0)) - _in_link_frame((0.0, 0.0, 0.0))
    actions = Gestures.click(origin, direction, now=at_rest, geometry=mug, modifier=None,
                             hold=False)
    bottom = np.add(_in_link_frame((0.0, 0.0, MUG_BOTTOM)), at_rest.position)
    assert [a.kind for a in actions] == [GRAB, RELEASE]
    assert np.linalg.norm(np.subtract(actions[0].point, bottom)) <= 1e-9
    beside = np.add(_in_link_frame((MUG_RADIUS + 0.01, 0.0, MUG_HEIGHT + 0.2)),
                    at_rest.position)
    assert Gestures.click(beside, direction, now=at_rest, geometry=mug, modifier=None,
                          hold=False) == []


def test_the_box_body_is_met_by_the_ray_on_the_box_as_before():
    """The box of box_size: ray_box_hit's point, bit for bit; from inside, where it leaves."""
    box = (0.4, 0.2, 0.1)
    shape = BodyGeometry.box(box)
    assert lone_box(shape.collisions) == box
    for origin, direction in (((0.05, 0.02, 3.0), (0.1, -0.2, -2.0)),
                              ((0.3, -0.2, 1.0), (1.0, 0.0, 0.0))):
        assert ray_body_hit(origin, direction, pose=TURNED, geometry=shape) == ray_box_hit(
            origin, direction, pose=TURNED, box_size=box)
    inside = ray_body_hit(TURNED.position, (1.0, 0.0, 0.0), pose=TURNED, geometry=shape)
    assert inside is not None and np.linalg.norm(np.subtract(inside, TURNED.position)) > 0.04


def test_a_box_piece_moved_off_the_link_origin_is_met_where_it_is():
    """A URDF box 0.1 m up the link's z: a ray down meets its top at z = 0.1 + 0.05."""
    shape = body_model(urdf([geometry('box', size=(0.2, 0.2, 0.1), xyz=(0.0, 0.0, 0.1))]),
                       density=1000.0).geometry
    assert lone_box(shape.collisions) is None
    at_rest = Pose((0.0, 0.0, 1.0), (0.0, 0.0, 0.0, 1.0))
    hit = ray_body_hit((0.05, 0.0, 3.0), (0.0, 0.0, -1.0), pose=at_rest, geometry=shape)
    assert hit == pytest.approx((0.05, 0.0, 1.15), abs=1e-12)


def _string(text: str) -> ParameterValue:
    return ParameterValue(type=ParameterType.PARAMETER_STRING, string_value=text)


def test_the_view_asks_for_every_parameter_the_shape_is_made_of():
    """The follower's get_parameters names GEOMETRY_PARAMETERS; their values are read."""
    assert set(GEOMETRY_PARAMETERS) <= set(PARAMETER_NAMES)
    read = ViewParameters().with_values([
        ('robot_description', _string('<robot/>')), ('body_link', _string('cup')),
        ('density', ParameterValue(type=ParameterType.PARAMETER_DOUBLE, double_value=500.0))])
    assert (read.robot_description, read.body_link, read.density) == ('<robot/>', 'cup', 500.0)
    negative = ParameterValue(type=ParameterType.PARAMETER_DOUBLE, double_value=-1.0)
    assert ViewParameters().with_values([('density', negative)]).density == 0.0


def test_the_shape_is_made_again_only_when_its_parameters_change(mug_urdf):
    """A URDF: its link; an anchor change keeps the same geometry; no URDF: the box again."""
    shape = BodyShape()
    assert lone_box(shape.geometry.collisions) == ViewParameters().box_size
    parameters = ViewParameters(robot_description=mug_urdf, density=1000.0)
    assert shape.update(parameters) and shape.error is None
    made = shape.geometry
    assert [piece.kind for piece in made.collisions] == ['mesh']
    assert not shape.update(parameters._replace(anchor=(0.0, 0.0, 0.05)))
    assert shape.geometry is made
    assert shape.update(parameters._replace(robot_description='', box_size=(0.3, 0.2, 0.1)))
    assert lone_box(shape.geometry.collisions) == (0.3, 0.2, 0.1)


def test_a_robot_is_its_tracked_links_shape_for_a_client_that_draws_one_body():
    """Several links, no body_link: the tracked link's pieces; the tool's by default, remade."""
    shape = BodyShape()
    parameters = ViewParameters(robot_description=double_pendulum(), tracked_link='lower')
    assert shape.update(parameters) and shape.error is None
    [rod] = shape.geometry.collisions
    assert rod.kind == 'box' and rod.size == pytest.approx((0.04, 0.04, 0.5))
    assert rod.transform[:3, 3] == pytest.approx((0.0, 0.0, -0.25))
    # The tool, 'tip', has no pieces: a 5 cm cube at its frame.
    assert shape.update(parameters._replace(tracked_link=''))
    assert shape.error is None and lone_box(shape.geometry.collisions) == (0.05, 0.05, 0.05)
    assert not shape.update(parameters._replace(tracked_link='', anchor=(0.0, 0.0, 0.0)))
    assert shape.update(parameters._replace(tracked_link='hand'))
    assert "'hand'" in shape.error and lone_box(shape.geometry.collisions) == (0.4, 0.2, 0.1)


def test_a_description_this_process_cannot_read_leaves_the_box_and_says_why(tmp_path):
    """A mesh file this machine does not have: the box of box_size, the reason in error."""
    missing = urdf([geometry('mesh', filename=str(tmp_path / 'absent.stl'))])
    shape = BodyShape()
    assert shape.update(ViewParameters(robot_description=missing, density=1000.0,
                                       box_size=(0.1, 0.2, 0.3)))
    assert lone_box(shape.geometry.collisions) == (0.1, 0.2, 0.3)
    assert 'no such file' in shape.error and 'drawn as the box of box_size' in shape.error
