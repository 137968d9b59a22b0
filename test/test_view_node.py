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
``mouse_view`` in-process against the real node: gestures reach it, the page follows it.

The view runs with its real scene on a viser server (port 0, no browser attached); a gesture
is fed to the view's own drag and click callbacks, as viser would call them, so that everything
from the callback on (queue, guard condition, geometry, messages, services) is the real path.
The browser tier (test_view_browser) drives the same callbacks through a real browser.
"""

import asyncio
import time
from types import SimpleNamespace

import numpy as np
import pytest
from rcl_interfaces.msg import Parameter as RclParameter, ParameterEvent, ParameterType, \
    ParameterValue
from rclpy.parameter import Parameter

# mouse_view serves its page with viser (requirements/view.txt; no rosdep key: package.xml).
pytest.importorskip('viser', reason='mouse_view needs viser: pip install -r requirements/view.txt')
from mouse_constraint_ros.node.mouse_constraint_node import MouseConstraintNode
from mouse_constraint_ros.pointer.geometry import framing, world_point
from mouse_constraint_ros.pointer.gestures import Action, GRAB, HOLD_MODIFIER, RELEASE
from mouse_constraint_ros.pointer.push_throttle import MAX_PUSH_RATE
from mouse_constraint_ros.view.node import MouseViewNode
from mouse_constraint_ros.view.scene import FLOOR_GAP, FLOOR_THICKNESS, ViewScene
from mouse_constraint_ros.view.server import start
from test_support import viser_client
from test_support.ros_harness import service_of, waits_at

AT_REST = {'gravity': [0.0, 0.0, 0.0], 'hold_initial_anchor': False}
CAMERA = SimpleNamespace(position=np.array([0.0, -3.0, 1.0]), look_at=np.array([0.0, 0.0, 1.0]))


@pytest.fixture
def server():
    """Yield a viser server on a free port, stopped afterwards."""
    server = start('127.0.0.1', 0)
    yield server
    server.stop()


def _view(ros, server, **options) -> MouseViewNode:
    return ros.add(MouseViewNode(scene_factory=lambda p: ViewScene(server, p),
                                 context=ros.context, **options))


def _node(ros, **parameters) -> MouseConstraintNode:
    return ros.add(MouseConstraintNode(context=ros.context, parameter_overrides=[
        Parameter(name, value=value) for name, value in {**AT_REST, **parameters}.items()]))


def _drag(view: MouseViewNode, phase: str, *, start=(0.0, 0.0, 0.0), end=(0.0, 0.0, 0.0),
          modifier=None) -> None:
    event = SimpleNamespace(phase=phase, client_id=1, client=SimpleNamespace(camera=CAMERA),
                            start_position=tuple(start), end_position=tuple(end),
                            modifier=modifier)
    asyncio.run(view._on_drag(event))


def _ready(ros, view: MouseViewNode, node: MouseConstraintNode) -> None:
    clients = view.node_services.clients.values()
    assert ros.spin_until(lambda: view.scene.shown is not None and view.follower.parameters_known
                          and view.grab_publisher.get_subscription_count() > 0
                          and all(c.service_is_ready() for c in clients))
    ros.spin_for(0.2)


def test_press_drag_release_reach_the_node(ros, server):
    """The grab becomes the anchor, the drag its target on the camera plane, the release frees."""
    node = _node(ros)
    view = _view(ros, server)
    _ready(ros, view, node)
    shown = view.scene.shown
    local = (0.1, -0.1, 0.02)  # on the face that looks at the camera (y = -0.1)
    _drag(view, 'start', start=world_point(shown, local))
    assert ros.spin_until(lambda: np.allclose(node.get_parameter('anchor').value, local,
                                              atol=1e-6))
    # The pointer's ray through (0.3, 0, 1.2) from the camera, met with the plane y = -0.1.
    grabbed_y = world_point(view.latest_pose(), local)[1]
    pointer = np.array([0.3, 0.0, 1.2])
    fraction = (grabbed_y - CAMERA.position[1]) / (pointer[1] - CAMERA.position[1])
    expected = CAMERA.position + fraction * (pointer - CAMERA.position)
    _drag(view, 'update', end=pointer)
    assert ros.spin_until(lambda: node.simulation.target is not None
                          and np.allclose(node.simulation.target, expected, atol=1e-9))
    ros.spin_for(2.0)
    anchor = world_point(view.latest_pose(), local)
    assert np.linalg.norm(np.array(anchor) - expected) < 0.01
    _drag(view, 'end', end=pointer)
    assert ros.spin_until(lambda: node.simulation.target is None)
    assert ros.spin_until(
        lambda: view.scene.reply.content == '/mouse_constraint/release: released')
    _drag(view, 'start', start=world_point(view.latest_pose(), local))
    assert ros.spin_until(lambda: node.simulation.target is not None)
    assert view.scene.reply.content == ''  # the next drag: "released" no longer holds


def test_a_held_release_keeps_the_target(ros, server):
    """Shift at release: the last target stays, no release."""
    node = _node(ros)
    view = _view(ros, server)
    _ready(ros, view, node)
    local = (-0.1, -0.1, 0.0)
    _drag(view, 'start', start=world_point(view.scene.shown, local), modifier=HOLD_MODIFIER)
    _drag(view, 'end', end=(0.0, 0.0, 1.3), modifier=HOLD_MODIFIER)
    assert ros.spin_until(lambda: node.simulation.target is not None
                          and abs(node.simulation.target[2] - 1.3) < 0.05)
    ros.spin_for(0.3)
    assert node.simulation.target is not None


def test_a_grab_right_after_a_release_goes_once_the_node_answered_it(ros, server):
    """
    A release and a grab sent together reach the node in the order sent.

    The release is a service call, the grab a message: the node takes the two in no set order
    when both wait at once (rclpy's SingleThreadedExecutor, this test's, takes the message
    first), so the grab waits for the release's answer. They are sent while nothing spins: the
    grab, sent with the release, would be waiting beside it.
    """
    node = _node(ros)
    view = _view(ros, server)
    _ready(ros, view, node)
    local = (0.1, -0.1, 0.02)
    _drag(view, 'start', start=world_point(view.scene.shown, local))
    assert ros.spin_until(lambda: node.simulation.target is not None)
    grab = world_point(view.latest_pose(), (-0.1, -0.1, 0.0))
    view.send([Action(RELEASE), Action(GRAB, grab)], view._now_ns())
    assert view.outbox.waiting == 1  # the grab, behind the release
    # The release delivered before the node's next wait: it finds it waiting.
    assert waits_at(service_of(node, '/release'), ros.context)
    assert ros.spin_until(
        lambda: view.scene.reply.content == '/mouse_constraint/release: released')
    assert ros.spin_until(lambda: node.simulation.target is not None)
    assert np.allclose(node.get_parameter('anchor').value, (-0.1, -0.1, 0.0), atol=1e-6)
    # The panel's Release, then a press: the same order.
    view.release()
    _drag(view, 'start', start=world_point(view.latest_pose(), local))
    view._run_work()  # the press, queued by viser's thread, handled at once
    assert view.outbox.waiting == 1
    assert waits_at(service_of(node, '/release'), ros.context)
    assert ros.spin_until(lambda: np.allclose(node.get_parameter('anchor').value, local,
                                              atol=1e-6))
    ros.spin_for(0.2)
    assert node.simulation.target is not None


def test_an_unanswered_release_is_given_up_and_said_so(ros, server):
    """
    Releases to a node that never answers: each given up after its timeout, the page says so.

    The node here publishes pose and offers ``~/release``, and is never spun; the view's work
    timer gives its calls up, and leaves none pending in the release's client.
    """
    from mouse_constraint_ros.pointer.service_calls import GIVE_UP_SECONDS
    from mouse_constraint_ros.wire.interface import RELEASE_SERVICE
    from test_support.silent_node import FakeClock, silent_node

    clock = FakeClock()
    view = _view(ros, server, clock=clock)
    client = view.node_services.clients[RELEASE_SERVICE]
    with silent_node():
        assert ros.spin_until(client.service_is_ready)
        for _ in range(3):
            view.release()
            view._run_work()
            clock.now += 1.0  # the release's wait for its answer runs out
        assert len(client._pending_requests) == 3
        clock.now += GIVE_UP_SECONDS
        view._run_work()
        assert client._pending_requests == {}
        assert view.scene.reply.content == (
            f'/mouse_constraint/release: no answer in {GIVE_UP_SECONDS:g} s')


def test_the_hint_says_how_to_drag_until_the_first_grab(ros, server):
    """One line in the panel says to press on the body; the first grab takes it away."""
    node = _node(ros)
    view = _view(ros, server)
    _ready(ros, view, node)
    assert view.scene.hint.visible and 'Press on the body' in view.scene.hint.content
    _drag(view, 'start', start=world_point(view.scene.shown, (0.1, -0.1, 0.02)))
    assert ros.spin_until(lambda: not view.scene.hint.visible)
    _drag(view, 'end', end=(0.0, 0.0, 1.0))
    assert ros.spin_until(lambda: node.simulation.target is None)
    assert not view.scene.hint.visible


def test_a_click_grabs_where_its_ray_meets_the_box_and_releases(ros, server):
    """A click on the body at rest: the anchor on its top face, then the body free."""
    node = _node(ros)
    view = _view(ros, server)
    _ready(ros, view, node)
    pose = view.latest_pose()
    top = world_point(pose, (0.05, 0.0, 0.05))
    ray = np.array(top) - (0.0, 0.0, 3.0)
    asyncio.run(view._on_click(SimpleNamespace(ray_origin=(top[0], top[1], 3.0),
                                               ray_direction=tuple(ray), modifier=None)))
    assert ros.spin_until(lambda: node.simulation.target is None)
    anchor = node.get_parameter('anchor').value
    # The top face (z = +0.05 in the body frame) at the clicked place, as the body turned.
    assert abs(np.max(np.abs(np.array(anchor) / (0.2, 0.1, 0.05))) - 1.0) < 1e-6


def test_the_page_follows_the_nodes_parameters_and_buttons(ros, server):
    """At most 60 pushes a second; a box_size change redraws it; pause, step, reset answer."""
    node = _node(ros)
    view = _view(ros, server)
    _ready(ros, view, node)
    pushes, start = view.pushes, time.monotonic()
    ros.spin_for(2.0)
    rate = (view.pushes - pushes) / (time.monotonic() - start)
    assert 5.0 < rate <= MAX_PUSH_RATE + 1.0  # the node publishes at 1 kHz
    node.set_parameters([Parameter('box_size', value=[0.5, 0.3, 0.2])])
    assert ros.spin_until(lambda: tuple(view.scene.body.dimensions) == (0.5, 0.3, 0.2))
    view.toggle_pause()
    assert ros.spin_until(lambda: node.ticker.paused)
    view.call('~/step')
    assert ros.spin_until(lambda: view.scene.reply.content.startswith(
        '/mouse_constraint/step: one tick of 0.001 s'))
    view.toggle_pause()
    assert ros.spin_until(lambda: not node.ticker.paused)
    view.call('~/reset')
    assert ros.spin_until(
        lambda: view.scene.reply.content == '/mouse_constraint/reset: back to the initial state, '
                                            'no target')


def test_it_looks_for_the_node_before_it_says_there_is_none(ros, server):
    """While discovery may run the page says it is looking; then, still no node, none."""
    view = _view(ros, server, discovery_seconds=1.0)
    ros.spin_for(0.6)
    assert view.scene.status.content == 'looking for **/mouse_constraint** on `/pose`'
    assert ros.spin_until(lambda: 'no node on /pose' in view.scene.status.content, timeout=2.0)


def test_no_node_then_the_node_comes_and_goes(ros, server):
    """Without the node the page says so; it recovers when the node comes and again after."""
    view = _view(ros, server, discovery_seconds=0.0)
    ros.spin_for(0.5)
    assert 'no node on /pose' in view.scene.status.content
    view._on_pose(b'not a pose')  # malformed input is passed over
    assert view.latest_pose() is None
    node = _node(ros, box_size=[0.6, 0.2, 0.1])
    assert ros.spin_until(lambda: 'no node' not in view.scene.status.content
                          and tuple(view.scene.body.dimensions) == (0.6, 0.2, 0.1))
    ros.executor.remove_node(node)
    ros.nodes.remove(node)
    node.destroy_node()
    assert ros.spin_until(lambda: 'no node on /pose' in view.scene.status.content)
    _node(ros, box_size=[0.3, 0.2, 0.1])
    assert ros.spin_until(lambda: 'no node' not in view.scene.status.content
                          and tuple(view.scene.body.dimensions) == (0.3, 0.2, 0.1))


def test_the_view_follows_a_namespace(ros, server):
    """In /robot the view watches /robot/mouse_constraint and says /robot/pose without it."""
    view = _view(ros, server, namespace='/robot', discovery_seconds=0.0)
    ros.spin_for(0.5)
    assert view.target_node == '/robot/mouse_constraint'
    assert 'no node on /robot/pose' in view.scene.status.content
    ros.add(MouseConstraintNode(context=ros.context, namespace='/robot'))
    assert ros.spin_until(lambda: view.scene.shown is not None
                          and '/robot/mouse_constraint' in view.scene.status.content)


def test_the_page_stays_live_on_a_clock_that_stands_still(ros, server):
    """With use_sim_time and no /clock the view's timers still run: the page says no node."""
    view = _view(ros, server, discovery_seconds=0.0,
                 parameter_overrides=[Parameter('use_sim_time', value=True)])
    assert ros.spin_until(lambda: 'no node on /pose' in view.scene.status.content)


def test_a_floor_parameter_draws_the_floor_and_unknown_ones_change_nothing(ros, server):
    """``floor`` true at ``floor_height`` in /parameter_events shows the slab; others pass by."""
    view = _view(ros, server)
    publisher = ros.probe.create_publisher(ParameterEvent, '/parameter_events', 10)
    assert ros.spin_until(lambda: publisher.get_subscription_count() > 0)
    assert not view.scene.floor.visible

    def event(node: str, *parameters) -> ParameterEvent:
        return ParameterEvent(node=node, changed_parameters=list(parameters))
    floor = RclParameter(name='floor', value=ParameterValue(
        type=ParameterType.PARAMETER_BOOL, bool_value=True))
    height = RclParameter(name='floor_height', value=ParameterValue(
        type=ParameterType.PARAMETER_DOUBLE, double_value=-0.25))
    unknown = RclParameter(name='no_such_parameter', value=ParameterValue(
        type=ParameterType.PARAMETER_STRING, string_value='x'))
    publisher.publish(event('/elsewhere/mouse_constraint', floor))
    ros.spin_for(0.3)
    assert not view.scene.floor.visible
    publisher.publish(event('/mouse_constraint', floor, height, unknown))
    assert ros.spin_until(lambda: view.scene.floor.visible)
    top = -0.25 - FLOOR_GAP * max(view.parameters.box_size)
    assert view.scene.floor.position[2] == pytest.approx(top - 0.5 * FLOOR_THICKNESS)
    height.value.double_value = 0.0  # the grid's plane: the slab's top is drawn under it
    publisher.publish(event('/mouse_constraint', height))
    assert ros.spin_until(lambda: view.parameters.floor_height == 0.0)
    assert view.scene.floor.position[2] + 0.5 * FLOOR_THICKNESS == pytest.approx(-0.002)


@pytest.mark.parametrize('box', [[0.001, 0.001, 0.001], [4.0, 2.0, 1.0]])
def test_the_spheres_and_lines_are_drawn_to_the_boxs_scale(ros, server, box):
    """A 1 mm or a 4 m box: the spheres a tenth of its longest edge across, as RViz's."""
    node = _node(ros, box_size=box)
    view = _view(ros, server)
    _ready(ros, view, node)
    scene = view.scene
    assert tuple(scene.body.dimensions) == tuple(box)
    assert scene.anchor.radius == scene.target.radius == pytest.approx(0.05 * max(box))
    assert scene.line.thickness == pytest.approx(max(box) / 30)


def test_a_page_that_loads_is_turned_to_the_body(ros, server):
    """A page connecting: its camera looks at the body from where the box reads well."""
    node = _node(ros, initial_position=[0.5, 0.5, 0.3])
    view = _view(ros, server)
    _ready(ros, view, node)
    client = viser_client.RawClient(server.get_port())
    try:
        client.send(viser_client.camera((3.0, 3.0, 3.0), (0.0, 0.0, 0.0)))
        assert viser_client.spin_reading(ros, client, lambda: len(server.get_clients()) == 1)
        handle = next(iter(server.get_clients().values()))
        assert viser_client.spin_reading(ros, client, lambda: np.allclose(
            handle.camera.look_at, view.scene.shown.position, atol=1e-6))
        expected = framing(view.scene.shown.position, (0.4, 0.2, 0.1), handle.camera.fov)
        assert tuple(handle.camera.position) == pytest.approx(expected.position, abs=1e-6)
        assert tuple(server.initial_camera.look_at) == pytest.approx(expected.look_at)
    finally:
        client.close()


def test_the_panel_shows_the_force_the_pointer_feels(ros, server):
    """With publish_force the panel reads the felt force: the weight held at rest; else n/a."""
    node = _node(ros, gravity=[0.0, 0.0, -9.80665], publish_force=True, mass=2.0,
                 anchor=[0.0, 0.0, 0.0], hold_initial_anchor=True)
    view = _view(ros, server)
    _ready(ros, view, node)
    # Held at its COM at rest, the pointer feels the weight: (0, 0, -m |g|).
    assert ros.spin_until(lambda: 'force felt: 19.61 N (0.00, 0.00, -19.61)'
                          in view.scene.numbers.content)
    assert node.set_parameters([Parameter('publish_force', value=False)])[0].successful
    assert ros.spin_until(lambda: 'force felt: n/a (publish_force off)'
                          in view.scene.numbers.content)
