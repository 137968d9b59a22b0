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

"""The RViz marker's pure parts: what a drag sends, and the updates that keep RViz's copy."""

import math

import pytest
from scipy.spatial.transform import Rotation
from visualization_msgs.msg import InteractiveMarkerControl

from mouse_constraint_ros.description import BodyGeometry
from mouse_constraint_ros.marker.drag import MarkerDrag
from mouse_constraint_ros.marker.input_pacer import InputPacer
from mouse_constraint_ros.marker.presence import departed, watched
from mouse_constraint_ros.marker.updates import (MARKER_NAME, MarkerUpdates, MAX_POSE_RATE,
                                                 pose_of)
from mouse_constraint_ros.pointer.geometry import Pose, world_point
from mouse_constraint_ros.pointer.gestures import Action, GRAB, RELEASE, TARGET
from mouse_constraint_ros.wire.interface import node_name

BOX = (0.4, 0.2, 0.1)
ANCHOR = (0.2, 0.1, 0.05)
SHOWN = Pose((0.0, 0.0, 1.0), tuple(Rotation.from_euler('z', 0.3).as_quat()))
NOW = Pose((0.05, 0.0, 0.98), tuple(Rotation.from_euler('zy', [0.35, 0.1]).as_quat()))
LOCAL = (0.1, -0.1, 0.02)  # a point of the -y face, body frame
# The node's box and grab_margin, which a press is checked against.
NODE = {'geometry': BodyGeometry.box(BOX), 'margin': 0.01}


def test_a_press_on_the_body_grabs_the_pressed_point_carried_to_the_latest_pose():
    """The hit point of the shown pose, at the node's pose now; moves carry it with the marker."""
    drag = MarkerDrag()
    hit = world_point(SHOWN, LOCAL)
    [grab] = drag.press('/rviz', shown=SHOWN, hit=hit, now=NOW, anchor=ANCHOR, **NODE)
    assert grab.kind == GRAB and grab.point == pytest.approx(world_point(NOW, LOCAL), abs=1e-12)
    moved = Pose((0.3, 0.2, 1.1), SHOWN.orientation)
    [target] = drag.move('/rviz', moved)
    assert target.kind == TARGET
    assert target.point == pytest.approx(world_point(moved, LOCAL), abs=1e-12)
    assert drag.release('/rviz', hold=False) == [Action(RELEASE)]
    assert not drag.dragging


def test_a_held_release_keeps_the_target_and_a_failed_pick_drags_the_anchor():
    """Hold: no release. No hit point (RViz's pick failed): no grab, the anchor is dragged."""
    drag = MarkerDrag()
    assert drag.press('/rviz', shown=SHOWN, hit=None, now=NOW, anchor=ANCHOR, **NODE) == []
    moved = Pose((0.3, 0.2, 1.1), SHOWN.orientation)
    assert drag.move('/rviz', moved) == [Action(TARGET, world_point(moved, ANCHOR))]
    assert drag.release('/rviz', hold=True) == []
    # A point that is not finite is no hit either.
    assert drag.press('/rviz', shown=SHOWN, hit=(math.nan, 0.0, 1.0), now=NOW, anchor=ANCHOR,
                      **NODE) == []
    assert drag.dragging


def test_one_drag_at_a_time_and_nothing_without_a_press_or_from_nan():
    """Another client's feedback mid-drag, a move or release without a press, NaN: nothing."""
    drag = MarkerDrag()
    moved = Pose((0.3, 0.2, 1.1), SHOWN.orientation)
    assert drag.move('/rviz', moved) == [] and drag.release('/rviz', hold=False) == []
    nan_pose = Pose((math.nan, 0.0, 1.0), SHOWN.orientation)
    assert drag.press('/rviz', shown=nan_pose, hit=None, now=NOW, anchor=ANCHOR, **NODE) == []
    assert not drag.dragging
    drag.press('/rviz', shown=SHOWN, hit=world_point(SHOWN, LOCAL), now=NOW, anchor=ANCHOR,
               **NODE)
    assert drag.press('/other', shown=SHOWN, hit=None, now=NOW, anchor=ANCHOR, **NODE) == []
    assert drag.move('/other', moved) == [] and drag.release('/other', hold=False) == []
    assert drag.move('/rviz', nan_pose) == []
    assert drag.client == '/rviz'


def _updates_at(updates: MarkerUpdates, poses, times):
    sent = []
    for pose, now in zip(poses, times):
        sent += updates.pose(pose, now) + updates.flush(now)
    return sent


def test_updates_are_numbered_one_after_the_other_and_poses_go_at_most_30_a_second():
    """The whole marker first; then a pose per 1/30 s at most, only when it moved."""
    updates = MarkerUpdates('/mouse_marker')
    assert updates.current() == [] and updates.pose(SHOWN, 0.0) == []
    [first] = updates.marker(frame_id='world', geometry=BodyGeometry.box(BOX), pose=SHOWN)
    [marker] = first.markers
    assert (first.seq_num, marker.name, marker.header.frame_id) == (1, MARKER_NAME, 'world')
    [control] = marker.controls
    assert control.interaction_mode == InteractiveMarkerControl.MOVE_3D
    assert (control.markers[0].scale.x, control.markers[0].scale.y) == BOX[:2]
    # A body moving at 1 kHz for 1 s: at most one pose per 1/30 s.
    times = [k * 0.001 for k in range(1, 1001)]
    poses = [Pose((t, 0.0, 1.0), SHOWN.orientation) for t in times]
    sent = _updates_at(updates, poses, times)
    assert 29 <= len(sent) <= MAX_POSE_RATE
    assert [u.seq_num for u in sent] == list(range(2, 2 + len(sent)))
    assert all(len(u.poses) == 1 and not u.markers for u in sent)
    # At rest: the newest pose held back goes when its slot comes, then nothing more.
    rest = [1.0 + k * 0.01 for k in range(100)]
    [last] = _updates_at(updates, [poses[-1]] * 100, rest)
    assert last.seq_num == sent[-1].seq_num + 1 and pose_of(last.poses[0].pose) == poses[-1]
    assert _updates_at(updates, [poses[-1]] * 100, [2.0 + t for t in rest]) == []
    assert pose_of(updates.current()[0].pose) == poses[-1]


def test_during_a_drag_no_pose_goes_and_at_its_end_the_marker_snaps_back():
    """Mid-drag: no poses, the whole marker deferred; the end: one update, next in number."""
    updates = MarkerUpdates('/mouse_marker')
    updates.marker(frame_id='world', geometry=BodyGeometry.box(BOX), pose=SHOWN)
    updates.dragging = True
    moved = [Pose((k * 0.01, 0.0, 1.0), SHOWN.orientation) for k in range(1, 50)]
    assert _updates_at(updates, moved, [k * 0.05 for k in range(1, 50)]) == []
    assert updates.marker(frame_id='world', geometry=BodyGeometry.box((0.5, 0.2, 0.1)),
                          pose=NOW) == []
    [end] = updates.drag_ended(moved[-1])
    assert end.seq_num == 2 and end.markers[0].controls[0].markers[0].scale.x == 0.5
    assert pose_of(end.markers[0].pose) == moved[-1]
    updates.dragging = True
    [back] = updates.drag_ended(NOW)
    assert back.seq_num == 3 and pose_of(back.poses[0].pose) == NOW


def test_a_drag_hangs_on_its_own_rviz_or_on_every_client_when_none_is_named_so():
    """The dragging RViz's publishers by node name; unnamed, all; one of them gone ends it."""
    assert node_name('/', 'rviz') == '/rviz' and node_name('/lab', 'rviz') == '/lab/rviz'
    a, b, c = ('/rviz', (1,)), ('/rviz_b', (2,)), ('/rviz', (3,))
    assert watched('/rviz', [a, b]) == {(1,)}
    # Two clients of one name are not told apart: the drag hangs on both.
    assert watched('/rviz', [a, b, c]) == {(1,), (3,)}
    # A client that signs with another id: every publisher on the graph.
    assert watched('someone', [a, b]) == {(1,), (2,)}
    hung_on = watched('/rviz', [a, b])
    assert not departed(hung_on, [a, b]) and not departed(hung_on, [a])
    assert not departed(hung_on, [a, ('/rviz_new', (4,))])
    assert departed(hung_on, [b]) and departed(hung_on, [])
    assert departed(watched('/rviz', [a, b, c]), [a, b])
    # None known at the press: the drag ends when no feedback publisher is left.
    assert watched('/rviz', []) == frozenset()
    assert not departed(frozenset(), [b]) and departed(frozenset(), [])


def _scaled(pose: Pose, factor: float) -> Pose:
    return Pose(pose.position, tuple(factor * c for c in pose.orientation))


def test_a_non_unit_quaternion_is_normalised_and_one_that_cannot_be_is_passed_over():
    """A quaternion scaled by 3 or 10 turns as the unit one; zero, NaN, 1e300 drag nothing."""
    unit, scaled = MarkerDrag(), MarkerDrag()
    hit = world_point(SHOWN, LOCAL)
    [grab] = unit.press('/rviz', shown=SHOWN, hit=hit, now=NOW, anchor=ANCHOR, **NODE)
    assert scaled.press('/rviz', shown=_scaled(SHOWN, 3.0), hit=hit, now=_scaled(NOW, 0.1),
                        anchor=ANCHOR, **NODE) == [
        Action(GRAB, pytest.approx(grab.point, abs=1e-12))]
    moved = Pose((0.3, 0.2, 1.1), SHOWN.orientation)
    [target] = unit.move('/rviz', moved)
    [scaled_target] = scaled.move('/rviz', _scaled(moved, 10.0))
    assert scaled_target.point == pytest.approx(target.point, abs=1e-12)
    for orientation in ((0.0, 0.0, 0.0, 0.0), (math.nan, 0.0, 0.0, 1.0),
                        (1e300, 0.0, 0.0, 0.0), (0.0, math.inf, 0.0, 0.0)):
        bad = Pose(moved.position, orientation)
        assert scaled.move('/rviz', bad) == []
        fresh = MarkerDrag()
        assert fresh.press('/rviz', shown=bad, hit=hit, now=NOW, anchor=ANCHOR, **NODE) == []
        assert fresh.press('/rviz', shown=SHOWN, hit=hit, now=bad, anchor=ANCHOR,
                           **NODE) == []
        assert not fresh.dragging


def test_a_press_the_node_would_refuse_grabs_nothing_and_drags_the_anchor():
    """A hit farther than the margin from the box at the latest pose: no grab, the anchor."""
    drag = MarkerDrag()
    off = world_point(SHOWN, (0.2 + 0.011, 0.0, 0.0))  # 11 mm off the +x face
    assert drag.press('/rviz', shown=SHOWN, hit=off, now=NOW, anchor=ANCHOR, **NODE) == []
    moved = Pose((0.3, 0.2, 1.1), SHOWN.orientation)
    assert drag.move('/rviz', moved) == [Action(TARGET, world_point(moved, ANCHOR))]
    drag.release('/rviz', hold=False)
    within = world_point(SHOWN, (0.2 + 0.009, 0.0, 0.0))  # 9 mm off: taken, as by the node
    [grab] = drag.press('/rviz', shown=SHOWN, hit=within, now=NOW, anchor=ANCHOR, **NODE)
    assert grab.point == pytest.approx(world_point(NOW, (0.209, 0.0, 0.0)), abs=1e-12)


def test_the_pacer_lets_one_input_go_per_slot_in_order_and_drops_what_is_moot():
    """100 a second, any kind; the newest target; a grab or a release drops what waits after."""
    pacer = InputPacer(100.0)

    def offer(kind: str, item: str, now: float):
        """Add an input and return what goes at ``now``, as the marker node does."""
        pacer.add(kind, item)
        return pacer.flush(now)
    assert offer(GRAB, 'grab 1', 0.0) == (GRAB, 'grab 1')
    assert offer(TARGET, 'target 1', 0.001) is None
    assert offer(TARGET, 'target 2', 0.002) is None and pacer.waiting == [TARGET]
    assert offer(RELEASE, 'release 1', 0.003) is None and pacer.waiting == [RELEASE]
    assert offer(GRAB, 'grab 2', 0.004) is None
    assert offer(TARGET, 'target 3', 0.005) is None
    assert pacer.waiting == [RELEASE, GRAB, TARGET]
    assert offer(RELEASE, 'release 2', 0.006) is None and pacer.waiting == [RELEASE]
    assert offer(GRAB, 'grab 3', 0.007) is None and pacer.waiting == [RELEASE, GRAB]
    assert offer(GRAB, 'grab 4', 0.008) is None and pacer.waiting == [RELEASE, GRAB]
    assert pacer.flush(0.0099) is None
    assert pacer.flush(0.01) == (RELEASE, 'release 1') and pacer.flush(0.015) is None
    assert offer(TARGET, 'target 4', 0.02) == (GRAB, 'grab 4')
    assert pacer.flush(0.03) == (TARGET, 'target 4') and pacer.waiting == []
    assert offer(TARGET, 'target 5', 0.04) == (TARGET, 'target 5')
    with pytest.raises(ValueError):
        offer('push', 'x', 1.0)
    with pytest.raises(ValueError):
        InputPacer(0.0)


def test_added_inputs_wait_for_a_flush_and_what_they_make_moot_is_dropped():
    """``add`` queues without letting anything go; what a later input makes moot is dropped."""
    pacer = InputPacer(100.0)
    pacer.add(RELEASE, 'release')
    pacer.add(TARGET, 'target 1')
    pacer.add(GRAB, 'grab')
    pacer.add(TARGET, 'target 2')
    assert pacer.waiting == [RELEASE, GRAB, TARGET]
    assert [pacer.flush(t) for t in (0.0, 0.005, 0.01, 0.02, 0.03)] == [
        (RELEASE, 'release'), None, (GRAB, 'grab'), (TARGET, 'target 2'), None]
    with pytest.raises(ValueError):
        pacer.add('push', 'x')
