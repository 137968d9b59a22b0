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
``mouse_view`` in-process against a node whose body is a URDF link: the mug, and primitives.

As in test_view_node, the view runs with its real scene on a viser server (no browser) and its
own click and drag callbacks are called as viser calls them. The page draws the link's pieces
in the link frame that the node's pose is of; a click's ray grabs the mesh where it meets it,
inside the cup as well; a drag grabs the pressed point; the box comes back with the box.
"""

import asyncio
from types import SimpleNamespace

import numpy as np
import pytest
from rclpy.parameter import Parameter
import trimesh

# mouse_view serves its page with viser (requirements/view.txt; no rosdep key: package.xml).
viser = pytest.importorskip('viser',
                            reason='mouse_view needs viser: pip install -r requirements/view.txt')
from mouse_constraint_ros.node.mouse_constraint_node import MouseConstraintNode
from mouse_constraint_ros.pointer.geometry import framing, world_point
from mouse_constraint_ros.pointer.gestures import HOLD_MODIFIER
from mouse_constraint_ros.view.node import MouseViewNode
from mouse_constraint_ros.view.scene import ViewScene
from mouse_constraint_ros.view.server import start
from test_support import viser_client
from test_support.meshes import geometry, MUG_BOTTOM, MUG_HEIGHT, MUG_RADIUS, urdf, write
from test_support.meshes import mug as mug_mesh

# The mug at rest, its COM's place given by its link frame; inertia from its mesh at a density.
AT_REST = {'gravity': [0.0, 0.0, 0.0], 'hold_initial_anchor': False, 'density': 1000.0,
           'anchor': [MUG_RADIUS, 0.0, 0.05], 'initial_position': [0.1, 0.2, 0.5]}
CAMERA = SimpleNamespace(position=np.array([0.1, -3.0, 0.55]),
                         look_at=np.array([0.1, 0.2, 0.55]))


@pytest.fixture
def server():
    """Yield a viser server on a free port, stopped afterwards."""
    server = start('127.0.0.1', 0)
    yield server
    server.stop()


@pytest.fixture
def mug_path(tmp_path):
    """Return the mug's mesh file, written to the test's folder."""
    return write(mug_mesh(), tmp_path / 'mug.stl')


def _started(ros, server, description: str, **parameters):
    node = ros.add(MouseConstraintNode(context=ros.context, parameter_overrides=[
        Parameter(name, value=value) for name, value in
        {**AT_REST, 'robot_description': description, **parameters}.items()]))
    view = ros.add(MouseViewNode(scene_factory=lambda p: ViewScene(server, p),
                                 context=ros.context))
    clients = view.node_services.clients.values()
    assert ros.spin_until(lambda: view.scene.shown is not None and view.follower.parameters_known
                          and view.grab_publisher.get_subscription_count() > 0
                          and all(c.service_is_ready() for c in clients))
    ros.spin_for(0.2)
    return node, view


def test_the_page_draws_the_links_mesh_in_the_link_frame(ros, server, mug_path):
    """The mug: one mesh node of the file's vertices under the /body frame, at the link pose."""
    node, view = _started(ros, server, urdf([geometry('mesh', filename=str(mug_path))]))
    scene = view.scene
    assert isinstance(scene.body, viser.FrameHandle)
    [piece] = scene.drawing.pieces
    assert isinstance(piece, viser.MeshHandle) and piece.name.startswith('/body/')
    from_file = trimesh.load(mug_path, force='mesh')
    assert len(piece.vertices) == len(from_file.vertices)
    assert np.array_equal(piece.faces, from_file.faces)
    # The link frame is the pose the node publishes, not the COM (which lies up the mug's axis).
    assert tuple(scene.body.position) == pytest.approx(view.latest_pose().position, abs=1e-3)
    assert view.latest_pose().position == pytest.approx((0.1, 0.2, 0.5), abs=1e-3)
    assert tuple(scene.anchor.position) == pytest.approx(AT_REST['anchor'])
    longest = max(2 * MUG_RADIUS, MUG_HEIGHT)
    assert scene.anchor.radius == pytest.approx(0.05 * longest, rel=1e-6)
    assert scene.drawing.center == pytest.approx((0.0, 0.0, 0.5 * MUG_HEIGHT), abs=1e-9)


def test_a_click_down_the_cup_grabs_its_bottom_inside(ros, server, mug_path):
    """A click's ray down the mug's axis: the anchor on the inner bottom, not the rim or a box."""
    node, view = _started(ros, server, urdf([geometry('mesh', filename=str(mug_path))]))
    pose = view.latest_pose()
    top = world_point(pose, (0.0, 0.0, MUG_HEIGHT + 0.5))
    down = np.subtract(world_point(pose, (0.0, 0.0, 0.0)), top)
    asyncio.run(view._on_click(SimpleNamespace(ray_origin=top, ray_direction=tuple(down),
                                               modifier=HOLD_MODIFIER)))
    assert ros.spin_until(lambda: node.simulation.target is not None)
    anchor = node.get_parameter('anchor').value
    assert np.linalg.norm(np.subtract(anchor, (0.0, 0.0, MUG_BOTTOM))) <= 1e-9


def test_a_drag_grabs_the_pressed_point_of_the_mesh(ros, server, mug_path):
    """A press on the mug's outer wall (drawn at the link pose): that point is the anchor."""
    node, view = _started(ros, server, urdf([geometry('mesh', filename=str(mug_path))]))
    local = (0.0, -MUG_RADIUS, 0.06)  # on the outer wall, facing the camera (-y)
    event = SimpleNamespace(phase='start', client_id=1, client=SimpleNamespace(camera=CAMERA),
                            start_position=world_point(view.scene.shown, local),
                            end_position=(0.0, 0.0, 0.0), modifier=None)
    asyncio.run(view._on_drag(event))
    assert ros.spin_until(lambda: np.allclose(node.get_parameter('anchor').value, local,
                                              atol=1e-6))


def test_primitives_are_drawn_as_their_shapes_and_the_box_comes_back(ros, server):
    """Visual sphere and cylinder (collision box): viser's own; without a URDF, the box again."""
    description = urdf([
        geometry('box', size=(0.1, 0.1, 0.1)),
        geometry('sphere', radius=0.03, xyz=(0.0, 0.0, 0.08), element='visual'),
        geometry('cylinder', radius=0.02, length=0.1, rpy=(np.pi / 2, 0.0, 0.0),
                 element='visual')])
    node, view = _started(ros, server, description, anchor=[0.0, 0.0, 0.05])
    sphere, cylinder = view.scene.drawing.pieces
    assert isinstance(sphere, viser.IcosphereHandle) and sphere.radius == 0.03
    assert tuple(sphere.position) == pytest.approx((0.0, 0.0, 0.08))
    assert isinstance(cylinder, viser.CylinderHandle)
    assert (cylinder.radius, cylinder.height) == (0.02, 0.1)
    # Turned a quarter about x: its axis (z) along -y.
    turned = trimesh.transformations.quaternion_matrix(cylinder.wxyz)[:3, :3] @ (0.0, 0.0, 1.0)
    assert turned == pytest.approx((0.0, -1.0, 0.0), abs=1e-12)
    assert node.set_parameters([Parameter('robot_description', value='')])[0].successful
    assert ros.spin_until(lambda: isinstance(view.scene.body, viser.BoxHandle))
    assert view.scene.drawing.pieces == []
    assert tuple(view.scene.body.dimensions) == tuple(view.parameters.box_size)


def test_a_page_that_loads_is_turned_to_the_middle_of_the_mug(ros, server, mug_path):
    """The camera looks at the mug's middle (half its height up the link's z), framed by it."""
    node, view = _started(ros, server, urdf([geometry('mesh', filename=str(mug_path))]))
    client = viser_client.RawClient(server.get_port())
    try:
        client.send(viser_client.camera((3.0, 3.0, 3.0), (0.0, 0.0, 0.0)))
        assert viser_client.spin_reading(ros, client, lambda: len(server.get_clients()) == 1)
        handle = next(iter(server.get_clients().values()))
        middle = world_point(view.scene.shown, (0.0, 0.0, 0.5 * MUG_HEIGHT))
        assert viser_client.spin_reading(ros, client, lambda: np.allclose(
            handle.camera.look_at, middle, atol=1e-6))
        expected = framing(middle, view.scene.drawing.extents, handle.camera.fov)
        assert tuple(handle.camera.position) == pytest.approx(expected.position, abs=1e-6)
    finally:
        client.close()


def test_a_visuals_material_colour_is_drawn(ros, server):
    """One box visual in red, half opaque: a box under the /body frame in that colour."""
    red = ('<visual><geometry><box size="0.1 0.1 0.1"/></geometry><material name="red">'
           '<color rgba="1 0 0 0.5"/></material></visual>')
    node, view = _started(ros, server, urdf([geometry('box', size=(0.1, 0.1, 0.1)), red]),
                          anchor=[0.0, 0.0, 0.05])
    assert isinstance(view.scene.body, viser.FrameHandle)
    [box] = view.scene.drawing.pieces
    assert isinstance(box, viser.BoxHandle) and tuple(box.dimensions) == (0.1, 0.1, 0.1)
    assert tuple(box.color) == (255, 0, 0) and box.opacity == 0.5
