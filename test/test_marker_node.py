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
``mouse_marker`` against the real node at 1 kHz, driven by a fake RViz as RViz drives it.

``FakeRviz`` is what RViz's InteractiveMarkers display with the Interact tool does on the
wire (rviz2 Jazzy, interactive_markers' client): it asks ``get_interactive_markers``, takes the
updates that follow the answer's number one after the other (a gap would reset it), and
publishes feedback with depth 100 and ``client_id`` ``/rviz``: at a press POSE_UPDATE then
MOUSE_DOWN with the picked point, one POSE_UPDATE per frame (30 a second) while the marker
moves on, at the release POSE_UPDATE then MOUSE_UP. Wall-clock timers run here (the marker's
rate is the path under test), the node at 1 kHz beside it in this process.
"""

import math
from pathlib import Path
import signal
import subprocess
import sys
import time
from typing import List, Optional

from geometry_msgs.msg import PointStamped, PoseStamped
import numpy as np
import pytest
from rclpy.node import Node
from rclpy.parameter import Parameter
from std_srvs.srv import SetBool
from visualization_msgs.msg import (InteractiveMarkerFeedback, InteractiveMarkerUpdate)
from visualization_msgs.srv import GetInteractiveMarkers

from mouse_constraint_ros.marker.node import (MAX_INPUT_RATE, MouseMarkerNode,
                                              PRESENCE_PERIOD)
from mouse_constraint_ros.marker.updates import MARKER_NAME, MAX_POSE_RATE, pose_message, pose_of
from mouse_constraint_ros.node.mouse_constraint_node import MouseConstraintNode
from mouse_constraint_ros.pointer.geometry import Pose, world_point
from mouse_constraint_ros.timing.spin import call_until_answered, StopRequest
from mouse_constraint_ros.wire.interface import (MARKER_FEEDBACK_TOPIC, MARKER_QOS,
                                                 MARKER_SERVICE, MARKER_UPDATE_TOPIC)
from test_support.robots import double_pendulum
from test_support.ros_harness import service_of, waits_at

BIN = Path(sys.executable).parent
FRAME_PERIOD = 1.0 / 30.0
LOCAL = (0.1, -0.1, 0.02)  # the pressed point: on the box's -y face, body frame
AT_REST = {'gravity': [0.0, 0.0, 0.0], 'hold_initial_anchor': False}


class FakeRviz:
    """RViz's interactive marker client on the wire, client id ``/rviz`` (see the module)."""

    def __init__(self, node: Node, client_id: str = '/rviz') -> None:
        """Subscribe to the updates, create the feedback publisher and the service client."""
        self.client_id = client_id
        self.updates: List[InteractiveMarkerUpdate] = []
        self.gaps = 0
        self.sequence: Optional[int] = None
        self.marker_pose: Optional[Pose] = None
        self.frame_id = ''
        self.feedback = node.create_publisher(InteractiveMarkerFeedback, MARKER_FEEDBACK_TOPIC,
                                              MARKER_QOS)
        node.create_subscription(InteractiveMarkerUpdate, MARKER_UPDATE_TOPIC, self._on_update,
                                 MARKER_QOS)
        self.client = node.create_client(GetInteractiveMarkers, MARKER_SERVICE)
        self.received_at: List[float] = []

    def initialize(self, ros, timeout: float = 20.0) -> None:
        """
        Ask for the marker as it is, as RViz does when the display starts, until it has one.

        As RViz's client, it asks again when no answer came within a second (its request
        timeout; ``call_until_answered``): a server in another process may not yet have matched
        the request's writer when the client sees the service.
        """
        deadline = time.monotonic() + timeout
        assert ros.spin_until(self.client.service_is_ready, timeout=timeout)
        while True:
            response = call_until_answered(self.client, GetInteractiveMarkers.Request(),
                                           ros.executor, StopRequest(), deadline=deadline)
            assert response is not None and time.monotonic() < deadline, 'no marker served'
            if response.markers:
                break
            ros.spin_for(0.2)
        self.sequence = response.sequence_number
        [marker] = response.markers
        self.marker_pose, self.frame_id = pose_of(marker.pose), marker.header.frame_id

    def _on_update(self, update: InteractiveMarkerUpdate) -> None:
        self.updates.append(update)
        self.received_at.append(time.monotonic())
        if self.sequence is None or update.seq_num <= self.sequence:
            return
        if update.seq_num != self.sequence + 1:
            self.gaps += 1
        self.sequence = update.seq_num
        for marker in update.markers:
            self.marker_pose = pose_of(marker.pose)
        for pose in update.poses:
            self.marker_pose = pose_of(pose.pose)

    def feedback_message(self, event: int, pose: Pose, point=None) -> InteractiveMarkerFeedback:
        """Return one feedback event of the body's marker, as this client signs it."""
        feedback = InteractiveMarkerFeedback(
            client_id=self.client_id, marker_name=MARKER_NAME, control_name='drag',
            event_type=event, pose=pose_message(pose), mouse_point_valid=point is not None)
        feedback.header.frame_id = self.frame_id
        if point is not None:
            feedback.mouse_point.x, feedback.mouse_point.y, feedback.mouse_point.z = point
        return feedback

    def send(self, event: int, pose: Pose, point=None) -> None:
        """Publish one feedback event of the body's marker."""
        self.feedback.publish(self.feedback_message(event, pose, point))

    def press(self, pose: Pose, point) -> None:
        """Press on the marker shown at ``pose``, the pick at ``point`` (None: it failed)."""
        self.send(InteractiveMarkerFeedback.POSE_UPDATE, pose, point)
        self.send(InteractiveMarkerFeedback.MOUSE_DOWN, pose, point)

    def release(self, pose: Pose) -> None:
        """Let go of the marker at ``pose``."""
        self.send(InteractiveMarkerFeedback.POSE_UPDATE, pose)
        self.send(InteractiveMarkerFeedback.MOUSE_UP, pose)


def _nodes(ros, *, marker_clock=time.monotonic, **parameters):
    node = ros.add(MouseConstraintNode(context=ros.context, parameter_overrides=[
        Parameter(name, value=value) for name, value in {**AT_REST, **parameters}.items()]))
    marker = ros.add(MouseMarkerNode(context=ros.context, clock=marker_clock))
    rviz = FakeRviz(ros.probe)
    assert ros.spin_until(lambda: marker.follower.parameters_known
                          and marker.updates.sequence > 0
                          and marker.release_client.service_is_ready()
                          and rviz.feedback.get_subscription_count() > 0, timeout=15.0)
    rviz.initialize(ros)
    return node, marker, rviz


def _drag(ros, rviz: FakeRviz, start: Pose, offsets) -> Pose:
    """Move the marker from ``start`` by each offset, one frame apart; return the last pose."""
    pose = start
    for offset in offsets:
        pose = Pose(tuple(np.add(start.position, offset)), start.orientation)
        rviz.send(InteractiveMarkerFeedback.POSE_UPDATE, pose)
        ros.spin_for(FRAME_PERIOD)
    return pose


def test_rviz_grabs_drags_and_releases_the_body(ros):
    """
    Press on the body: grabbed there; drag: the grabbed point follows the marker; let go: free.

    The body is at rest when pressed (the carrying of a pressed point from the pose RViz showed
    to a moving body's latest pose is ``test_marker.py``'s), so the anchor is the pressed point
    to 1e-9 m. The anchor is within 5 mm of the grabbed point moved with the marker after 0.5 s
    held still; with gravity on and released, the body falls. The server's updates reach RViz
    one after the other, at most 30 a second while the node publishes at 1 kHz, none during the
    drag, and the marker is back on the body after it.
    """
    node, marker, rviz = _nodes(ros)
    poses: List[PoseStamped] = ros.collect(PoseStamped, 'pose', depth=1000)
    shown = rviz.marker_pose
    rviz.press(shown, world_point(shown, LOCAL))
    assert ros.spin_until(lambda: np.allclose(node.get_parameter('anchor').value, LOCAL,
                                              rtol=0.0, atol=1e-9))
    pressed_updates = len(rviz.updates)
    path = [(0.01 * k, 0.0, 0.005 * k) for k in range(1, 31)]  # 0.3 m in x, 0.15 m up, 1 s
    end = _drag(ros, rviz, shown, path)
    ros.spin_for(0.5)
    grabbed = world_point(end, LOCAL)
    anchor = node.simulation.state.world_point(tuple(node.get_parameter('anchor').value))
    assert np.linalg.norm(np.subtract(anchor, grabbed)) < 0.005
    assert len(rviz.updates) == pressed_updates  # RViz would hold them until the release
    node.set_parameters([Parameter('gravity', value=[0.0, 0.0, -9.80665])])
    ros.spin_for(0.2)
    rviz.release(end)
    assert ros.spin_until(lambda: node.simulation.target is None)
    height = node.simulation.state.position[2]
    assert ros.spin_until(lambda: len(rviz.updates) > pressed_updates)
    ros.spin_for(0.5)
    # Falling: at least half of the 1.2 m a free body falls in 0.5 s.
    assert node.simulation.state.position[2] < height - 0.5 * (0.5 * 9.8 * 0.5 ** 2)
    assert rviz.gaps == 0
    # The marker back on the body, following it at 30 a second at most as it falls, and on its
    # latest pose, bit for bit, once it stops (paused).
    window = [t for t in rviz.received_at if t >= rviz.received_at[-1] - 0.4]
    assert 3 <= len(window) <= 0.4 * MAX_POSE_RATE + 1
    assert ros.call(SetBool, '/mouse_constraint/pause', SetBool.Request(data=True)).success

    def on_the_latest_pose() -> bool:
        last = poses[-1].pose
        return rviz.marker_pose == pose_of(last) and tuple(node.simulation.state.position) == (
            last.position.x, last.position.y, last.position.z)
    assert ros.spin_until(on_the_latest_pose)


def test_a_held_release_keeps_the_body_and_a_failed_pick_drags_the_anchor(ros):
    """hold_on_release: the body stays at the last target. A pick without a point: no grab."""
    node, marker, rviz = _nodes(ros)
    marker.set_parameters([Parameter('hold_on_release', value=True)])
    anchor = tuple(node.get_parameter('anchor').value)
    shown = rviz.marker_pose
    rviz.press(shown, None)
    end = _drag(ros, rviz, shown, [(0.0, 0.0, 0.01 * k) for k in range(1, 11)])
    rviz.release(end)
    ros.spin_for(1.0)
    assert tuple(node.get_parameter('anchor').value) == anchor
    assert node.simulation.target == pytest.approx(world_point(end, anchor), abs=1e-9)


def test_other_clients_floods_and_nan_are_passed_over(ros):
    """
    A second client mid-drag, a release without a press, a flood, a NaN pose: no harm.

    The flood (2000 pose updates at once) sends targets at most MAX_INPUT_RATE a second; the
    NaN pose sends none; the other client's feedback none; the drag goes on.
    """
    node, marker, rviz = _nodes(ros)
    other = FakeRviz(ros.probe, client_id='/rviz_other')
    other.frame_id = rviz.frame_id
    targets: List[PointStamped] = ros.collect(PointStamped, 'target', depth=10000)
    shown = rviz.marker_pose
    other.release(shown)  # a release without a press
    ros.spin_for(0.3)
    assert node.simulation.target is None and not marker.drag.dragging
    rviz.press(shown, world_point(shown, LOCAL))
    assert ros.spin_until(lambda: marker.drag.dragging)
    other.press(shown, world_point(shown, LOCAL))
    other.send(InteractiveMarkerFeedback.POSE_UPDATE,
               Pose((9.0, 9.0, 9.0), shown.orientation))
    nan = Pose((math.nan, 0.0, 1.0), shown.orientation)
    rviz.send(InteractiveMarkerFeedback.POSE_UPDATE, nan)
    ros.spin_for(0.3)
    assert marker.drag.client == '/rviz'
    assert all(math.isfinite(t.point.x) and t.point.x < 1.0 for t in targets)
    before, start = len(targets), time.monotonic()
    for k in range(2000):
        rviz.send(InteractiveMarkerFeedback.POSE_UPDATE,
                  Pose(tuple(np.add(shown.position, (1e-4 * k, 0.0, 0.0))), shown.orientation))
    # RViz's depth 100 keeps the newest feedback of a burst: the newest target goes out last.
    last = world_point(Pose(tuple(np.add(shown.position, (0.1999, 0.0, 0.0))),
                            shown.orientation), LOCAL)
    assert ros.spin_until(lambda: len(targets) > before and np.allclose(
        (targets[-1].point.x, targets[-1].point.y, targets[-1].point.z), last, atol=1e-9),
        timeout=20.0)
    flood = len(targets) - before
    assert flood <= (time.monotonic() - start) * MAX_INPUT_RATE + 2
    rviz.release(shown)
    assert ros.spin_until(lambda: node.simulation.target is None)


def test_scaled_quaternions_turn_as_unit_ones_and_a_refused_press_drags_the_anchor(ros):
    """
    Feedback whose quaternion is scaled drags as the unit one; one that holds no turn, nothing.

    The press is 1.9 m off the body, turned by a quaternion scaled by 3: the node would refuse
    it, so no grab goes and the drag moves the node's anchor, never the refused point; moves
    with the quaternion scaled by 10 send the anchor moved with the marker; zero, 1e300 and NaN
    quaternions send nothing.
    """
    node, marker, rviz = _nodes(ros)
    grabs: List[PointStamped] = ros.collect(PointStamped, 'grab')
    targets: List[PointStamped] = ros.collect(PointStamped, 'target')
    anchor = tuple(node.get_parameter('anchor').value)
    shown = rviz.marker_pose
    off = world_point(shown, (0.1, -2.0, 0.0))

    def scaled(pose: Pose, factor: float) -> Pose:
        return Pose(pose.position, tuple(factor * c for c in pose.orientation))
    rviz.press(scaled(shown, 3.0), off)
    assert ros.spin_until(lambda: marker.drag.dragging)
    moved = Pose(tuple(np.add(shown.position, (0.0, 0.0, 0.05))), shown.orientation)
    rviz.send(InteractiveMarkerFeedback.POSE_UPDATE, scaled(moved, 10.0))
    for orientation in ((0.0, 0.0, 0.0, 0.0), (1e300, 0.0, 0.0, 0.0), (math.nan, 0.0, 0.0, 1.0)):
        rviz.send(InteractiveMarkerFeedback.POSE_UPDATE, Pose(moved.position, orientation))
    ros.spin_for(0.5)
    assert grabs == [] and tuple(node.get_parameter('anchor').value) == anchor
    expected = world_point(moved, anchor)
    assert [(t.point.x, t.point.y, t.point.z) for t in targets] == [
        pytest.approx(expected, abs=1e-12)]
    assert node.simulation.target == pytest.approx(expected, abs=1e-12)
    rviz.release(moved)
    assert ros.spin_until(lambda: node.simulation.target is None)


class FakeClock:
    """A monotonic clock that stands still until told: ``now`` seconds."""

    def __init__(self) -> None:
        """Start at 0 s."""
        self.now = 0.0

    def __call__(self) -> float:
        """Return the time (s)."""
        return self.now


def _sends(marker: MouseMarkerNode, clock: FakeClock,
           answers: Optional[list] = None) -> List[tuple]:
    """Record each input the marker sends as (time, kind), and send it; the calls' futures too."""
    sent: List[tuple] = []

    def spy(kind: str, send):
        def record(*args, **kwargs):
            sent.append((clock.now, kind))
            result = send(*args, **kwargs)
            if answers is not None and kind == 'release':
                answers.append(result)  # the call's future
            return result
        return record
    marker.grab_publisher.publish = spy('grab', marker.grab_publisher.publish)
    marker.target_publisher.publish = spy('target', marker.target_publisher.publish)
    marker.release_client.call_async = spy('release', marker.release_client.call_async)
    return sent


def test_press_move_release_cycles_send_at_most_max_input_rate_inputs_a_second(ros):
    """
    2000 press, move and release cycles in 1 s: 100 inputs a second at most, grabs included.

    The marker's clock is a fake one that moves 0.5 ms per cycle; the feedback is handed to the
    marker's callback in order and its work runs after each cycle, as its timer would, each
    release answered at once (nothing spins meanwhile: the node's answers come later and are
    stale then). Grabs, targets and releases together go at least 1 / MAX_INPUT_RATE s apart,
    a slot nearly every time, the last a release; then, once the node answered every release,
    a press and a drag 5 ms after it grab and drag the body, each in its slot.
    """
    clock = FakeClock()
    node, marker, rviz = _nodes(ros, marker_clock=clock)
    answers: List = []
    sent = _sends(marker, clock, answers)
    shown = rviz.marker_pose
    hit = world_point(shown, LOCAL)
    moved = Pose(tuple(np.add(shown.position, (0.0, 0.0, 0.01))), shown.orientation)
    cycles, step = 2000, 0.0005
    for k in range(cycles):
        clock.now = 10.0 + k * step
        for event, pose, point in ((InteractiveMarkerFeedback.MOUSE_DOWN, shown, hit),
                                   (InteractiveMarkerFeedback.POSE_UPDATE, moved, None),
                                   (InteractiveMarkerFeedback.MOUSE_UP, moved, None)):
            marker._on_feedback(rviz.feedback_message(event, pose, point))
        marker._work()
        marker.release_gate.answered(marker.release_gate.sent)
    while marker._inputs.waiting:  # what still waits goes in the next slots
        clock.now += 1.0 / MAX_INPUT_RATE
        marker._work()
        marker.release_gate.answered(marker.release_gate.sent)
    flood = list(sent)
    times = [t for t, _ in flood]
    assert np.all(np.diff(times) >= 1.0 / MAX_INPUT_RATE - 1e-9)
    slots = cycles * step * MAX_INPUT_RATE
    assert 0.9 * slots <= len(flood) <= slots + 1 and flood[-1][1] == 'release'
    # The last release's answer: the node took every request it kept (a burst beyond the
    # service's queue loses its oldest requests, whose calls are never answered).
    assert ros.spin_until(answers[-1].done)
    clock.now += 0.005
    marker._on_feedback(rviz.feedback_message(InteractiveMarkerFeedback.MOUSE_DOWN, shown, hit))
    marker._on_feedback(rviz.feedback_message(InteractiveMarkerFeedback.POSE_UPDATE, moved))
    for _ in range(3):
        clock.now += 1.0 / MAX_INPUT_RATE
        marker._work()
    assert [kind for _, kind in sent[len(flood):]] == ['grab', 'target']
    assert ros.spin_until(lambda: node.simulation.target == pytest.approx(
        world_point(moved, LOCAL), abs=1e-9))


def test_a_press_right_after_a_release_grabs_once_the_node_answered_the_release(ros):
    """
    The release is a service call, the grab a message: the grab goes after the release's answer.

    The node takes a request and a message that wait at once in no set order (rclpy's
    SingleThreadedExecutor, this test's, takes the message first), so a grab sent one slot after
    the release would be undone by it. Here the release and the press come in consecutive slots
    while nothing spins; the node finds the release waiting, answers it, and only then gets the
    grab.
    """
    clock = FakeClock()
    node, marker, rviz = _nodes(ros, marker_clock=clock)
    sent = _sends(marker, clock)
    shown = rviz.marker_pose
    clock.now = 10.0
    marker._on_feedback(rviz.feedback_message(InteractiveMarkerFeedback.MOUSE_DOWN, shown,
                                              world_point(shown, LOCAL)))
    assert ros.spin_until(lambda: node.simulation.target is not None)
    for event, local in ((InteractiveMarkerFeedback.MOUSE_UP, None),
                         (InteractiveMarkerFeedback.MOUSE_DOWN, (-0.1, -0.1, 0.0))):
        clock.now += 1.0 / MAX_INPUT_RATE
        marker._on_feedback(rviz.feedback_message(
            event, shown, None if local is None else world_point(shown, local)))
        marker._work()
    assert [kind for _, kind in sent] == ['grab', 'release']
    # The release delivered before the node's next wait: it finds it waiting.
    assert waits_at(service_of(node, '/release'), ros.context)
    assert ros.spin_until(lambda: len(sent) == 3)
    assert [kind for _, kind in sent] == ['grab', 'release', 'grab']
    assert ros.spin_until(lambda: np.allclose(node.get_parameter('anchor').value,
                                              (-0.1, -0.1, 0.0), atol=1e-6))
    ros.spin_for(0.2)
    assert node.simulation.target is not None


def test_a_robot_is_drawn_as_its_tracked_link_and_a_press_on_it_grabs_that_link(ros):
    """A whole robot: the marker is the tracked link (the lower rod), pressed: that link held."""
    node, marker, rviz = _nodes(ros, robot_description=double_pendulum(), tracked_link='lower',
                                initial_joint_positions=[0.6, -0.9])
    assert marker.shape.error is None
    [rod] = marker.shape.geometry.collisions
    assert rod.kind == 'box' and rod.size == pytest.approx((0.04, 0.04, 0.5))
    shown = rviz.marker_pose  # the tracked link's frame
    local = (0.0, -0.02, -0.3)  # on the rod's -y face, in its frame
    rviz.press(shown, world_point(shown, local))
    assert ros.spin_until(lambda: node.simulation.target is not None)
    assert node.simulation.grabbed_link == 'lower'
    assert node.get_parameter('anchor').value == pytest.approx(local, abs=1e-9)


def test_a_drag_ends_when_its_rviz_leaves(ros):
    """
    Closed mid-drag (its feedback publisher gone), an RViz ends its drag as a release would.

    Held still, RViz sends nothing, so the body stays held while the publisher is there; once
    it leaves the graph the server releases the body within a few of its looks.
    """
    node, marker, rviz = _nodes(ros)
    shown = rviz.marker_pose
    rviz.press(shown, world_point(shown, LOCAL))
    _drag(ros, rviz, shown, [(0.0, 0.0, 0.01 * k) for k in range(1, 6)])
    ros.spin_for(1.0)  # held still: no feedback, still dragged
    assert marker.drag.dragging and node.simulation.target is not None
    ros.probe.destroy_publisher(rviz.feedback)
    start = time.monotonic()
    assert ros.spin_until(lambda: node.simulation.target is None, timeout=10.0)
    assert time.monotonic() - start < 4 * PRESENCE_PERIOD + 1.0
    assert not marker.drag.dragging


def test_a_drag_ends_when_its_rviz_leaves_while_another_stays(ros):
    """
    Two RViz by node name: the dragging one closes mid-drag and the drag ends; the other stays.

    Each RViz signs its feedback with its node's name, so the server knows which publisher the
    drag hangs on; the other leaving ends nothing.
    """
    node, marker, probe_rviz = _nodes(ros)
    rviz_nodes, clients = {}, {}
    for name in ('rviz_a', 'rviz_b'):
        rviz_nodes[name] = ros.add(Node(name, context=ros.context))
        clients[name] = FakeRviz(rviz_nodes[name], client_id=f'/{name}')
        assert ros.spin_until(lambda: clients[name].feedback.get_subscription_count() > 0,
                              timeout=15.0)
        clients[name].initialize(ros)
    dragging, other = clients['rviz_a'], clients['rviz_b']
    shown = dragging.marker_pose
    dragging.press(shown, world_point(shown, LOCAL))
    assert ros.spin_until(lambda: marker.drag.client == '/rviz_a')
    _drag(ros, dragging, shown, [(0.0, 0.0, 0.01 * k) for k in range(1, 6)])
    ros.spin_for(1.0)  # held still: no feedback, still dragged
    assert marker.drag.dragging and node.simulation.target is not None
    gone = rviz_nodes['rviz_a']  # closed: it leaves the graph
    ros.nodes.remove(gone)
    ros.executor.remove_node(gone)
    gone.destroy_node()
    start = time.monotonic()
    assert ros.spin_until(lambda: node.simulation.target is None, timeout=10.0)
    assert time.monotonic() - start < 4 * PRESENCE_PERIOD + 1.0
    assert not marker.drag.dragging
    # The other drags now; the probe's client (not a node of its name) is left alone.
    shown = other.marker_pose
    other.press(shown, world_point(shown, LOCAL))
    assert ros.spin_until(lambda: marker.drag.client == '/rviz_b')
    ros.probe.destroy_publisher(probe_rviz.feedback)
    ros.spin_for(4 * PRESENCE_PERIOD + 1.0)
    assert marker.drag.client == '/rviz_b' and node.simulation.target is not None


@pytest.mark.system
def test_the_command_serves_the_marker_until_ctrl_c(ros):
    """``mouse_marker`` as a process beside the node: RViz gets the marker; SIGINT: exit 0."""
    help_text = subprocess.run([str(BIN / 'mouse_marker'), '--help'], capture_output=True,
                               text=True, timeout=60)
    assert help_text.returncode == 0 and help_text.stdout.startswith('usage: mouse_marker')
    ros.add(MouseConstraintNode(context=ros.context, parameter_overrides=[
        Parameter(name, value=value) for name, value in AT_REST.items()]))
    process = subprocess.Popen([str(BIN / 'mouse_marker'), '--hold'], stdout=subprocess.PIPE,
                               stderr=subprocess.STDOUT, text=True)
    try:
        rviz = FakeRviz(ros.probe)
        rviz.initialize(ros)
        assert rviz.frame_id == 'world' and rviz.marker_pose is not None
    finally:
        process.send_signal(signal.SIGINT)
        output, _ = process.communicate(timeout=20)
    assert process.returncode == 0, output
    assert "as the interactive marker 'body' on /mouse_marker/update" in output
    assert 'Traceback' not in output
