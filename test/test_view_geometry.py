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

"""The web view's pure geometry and gestures: the ray on the box, the camera plane, the grab."""

import math

from hypothesis import given, settings, strategies as st
import numpy as np
import pytest
from scipy.spatial.transform import Rotation

from mouse_constraint_ros.description import BodyGeometry
from mouse_constraint_ros.inputs.grab import grab
from mouse_constraint_ros.physics import BodyState
from mouse_constraint_ros.pointer.geometry import (camera_plane_point, FRAME_FRACTION, framing,
                                                   material_point, Pose, ray_box_hit, world_point,
                                                   wxyz)
from mouse_constraint_ros.pointer.gestures import (Action, Camera, Gestures, GRAB, HOLD_MODIFIER,
                                                   RELEASE, SEGMENT_GAP, TARGET)

BOX = (0.4, 0.2, 0.1)
BOX_SHAPE = BodyGeometry.box(BOX)
TURNED = Pose((0.3, -0.2, 1.0), tuple(Rotation.from_euler('zyx', [0.7, -0.3, 0.4]).as_quat()))
finite = st.floats(-2.0, 2.0, allow_nan=False)


def _box_distance(pose: Pose, point) -> float:
    state = BodyState(pose.position, pose.orientation, (0.0,) * 3, (0.0,) * 3)
    return grab(state, BOX_SHAPE, point).distance


def test_a_ray_down_the_z_axis_meets_the_top_face():
    """From above the COM straight down: the top face, half the box's height above the COM."""
    pose = Pose((0.0, 0.0, 1.0), (0.0, 0.0, 0.0, 1.0))
    hit = ray_box_hit((0.05, 0.02, 3.0), (0.0, 0.0, -2.0), pose=pose, box_size=BOX)
    assert hit == pytest.approx((0.05, 0.02, 1.0 + BOX[2] / 2))


def test_misses_and_rays_pointing_away():
    """Beside the box, behind the origin, zero and NaN directions: no hit."""
    pose = Pose((0.0, 0.0, 1.0), (0.0, 0.0, 0.0, 1.0))
    assert ray_box_hit((0.3, 0.0, 3.0), (0.0, 0.0, -1.0), pose=pose, box_size=BOX) is None
    assert ray_box_hit((0.0, 0.0, 3.0), (0.0, 0.0, 1.0), pose=pose, box_size=BOX) is None
    assert ray_box_hit((0.0, 0.0, 3.0), (0.0, 0.0, 0.0), pose=pose, box_size=BOX) is None
    assert ray_box_hit((0.0, 0.0, 3.0), (math.nan, 0.0, -1.0), pose=pose,
                       box_size=BOX) is None


def test_from_inside_the_box_the_ray_meets_it_where_it_leaves():
    """An origin at the COM looking along +x: the face at x = +0.2."""
    pose = Pose((0.0, 0.0, 1.0), (0.0, 0.0, 0.0, 1.0))
    hit = ray_box_hit((0.0, 0.0, 1.0), (1.0, 0.0, 0.0), pose=pose, box_size=BOX)
    assert hit == pytest.approx((0.2, 0.0, 1.0))


@settings(max_examples=200, deadline=None)
@given(st.tuples(finite, finite, finite), st.tuples(finite, finite, finite))
def test_a_ray_through_a_point_inside_the_box_hits_its_surface_first(local, offset):
    """Aim from outside at a point inside the turned box: the hit is on the surface, before it."""
    inside = world_point(TURNED, np.multiply(np.array(local) / 2.0 * 0.99, BOX) / 2.0)
    origin = np.array(inside) + 3.0 * (np.array(offset) + (0.0, 0.0, 2.5))
    hit = ray_box_hit(origin, np.array(inside) - origin, pose=TURNED, box_size=BOX)
    assert hit is not None
    assert _box_distance(TURNED, hit) <= 1e-9
    # On the surface: just outside along the ray is off the box.
    direction = (np.array(inside) - origin) / np.linalg.norm(np.array(inside) - origin)
    assert _box_distance(TURNED, np.array(hit) - 1e-6 * direction) > 0.0
    assert np.linalg.norm(np.array(hit) - origin) <= np.linalg.norm(np.array(inside) - origin)


@settings(max_examples=200, deadline=None)
@given(st.tuples(finite, finite, finite), st.tuples(finite, finite, finite),
       st.tuples(finite, finite, finite))
def test_the_camera_plane_point_is_on_the_ray_and_the_plane(camera, through, pointer):
    """The point lies on the plane (n . (p - through) = 0) and on the ray from the camera."""
    camera, through = np.array(camera) + (0.0, 0.0, 5.0), np.array(through)
    normal = through - camera
    pointer = through + np.array(pointer)
    point = camera_plane_point(camera, pointer - camera, through=through, normal=normal)
    if point is None:
        assert np.dot(normal, pointer - camera) <= 1e-9 * np.linalg.norm(normal) * \
            np.linalg.norm(pointer - camera)
        return
    point = np.array(point)
    assert abs(np.dot(normal, point - through)) <= 1e-9 * np.linalg.norm(normal) * max(
        1.0, np.linalg.norm(point - through))
    assert np.linalg.norm(np.cross(point - camera, pointer - camera)) <= 1e-9 * max(
        1.0, np.linalg.norm(point - camera) * np.linalg.norm(pointer - camera))


def test_the_camera_plane_refuses_parallel_and_backward_rays():
    """A ray along the plane, or one pointing away from it: None."""
    assert camera_plane_point((0, 0, 5), (1, 0, 0), through=(0, 0, 1), normal=(0, 0, -1)) is None
    assert camera_plane_point((0, 0, 5), (0, 0, 1), through=(0, 0, 1), normal=(0, 0, -1)) is None
    assert camera_plane_point((0, 0, 5), (0.1, 0, -1), through=(0, 0, 1),
                              normal=(0, 0, -1)) == pytest.approx((0.4, 0.0, 1.0))


def test_a_material_point_follows_the_body():
    """A point of the body at one pose is at the same body-frame place at another."""
    shown = Pose((0.0, 0.0, 1.0), (0.0, 0.0, 0.0, 1.0))
    local = (0.2, 0.1, 0.05)
    moved = material_point(world_point(shown, local), shown=shown, now=TURNED)
    assert moved == pytest.approx(world_point(TURNED, local))
    expected = np.array(TURNED.position) + Rotation.from_quat(TURNED.orientation).apply(local)
    assert moved == pytest.approx(tuple(expected))


def test_wxyz_is_the_same_rotation():
    """REP 103's (x, y, z, w) becomes (w, x, y, z)."""
    assert wxyz((0.1, 0.2, 0.3, 0.9)) == (0.9, 0.1, 0.2, 0.3)


CAMERA = Camera((0.0, -3.0, 1.0), (0.0, 1.0, 0.0))
AT_REST = Pose((0.0, 0.0, 1.0), (0.0, 0.0, 0.0, 1.0))


@pytest.mark.parametrize('box', [BOX, (0.001, 0.001, 0.001), (4.0, 1.0, 0.5)])
def test_a_framed_box_spans_a_quarter_of_the_view_whatever_its_size(box):
    """The camera looks at the COM from where the longest edge spans FRAME_FRACTION."""
    fov, center = math.radians(75.0), np.array([0.3, -0.2, 1.0])
    view = framing(center, box, fov)
    assert view.look_at == pytest.approx(center)
    distance = np.linalg.norm(np.subtract(view.position, center))
    # An edge of the longest length, facing the camera at the COM, over the view's height.
    assert max(box) / (2.0 * distance * math.tan(fov / 2)) == pytest.approx(FRAME_FRACTION)
    assert view.position[2] > center[2]  # from above: the floor and the grid in sight
    assert view.near == pytest.approx(distance / 100)  # nothing of the box clipped
    assert distance - np.linalg.norm(box) / 2 > 10 * view.near


def test_a_drag_grabs_the_pressed_point_moves_on_the_camera_plane_and_releases():
    """Grab at the pressed point, targets at the grabbed point's depth, then a release."""
    gestures = Gestures()
    pressed = (0.1, -0.1, 1.02)
    assert gestures.start(7, pressed=pressed, camera=CAMERA, shown=AT_REST,
                          now=AT_REST, at=0.0) == [Action(GRAB, pytest.approx(pressed))]
    assert gestures.dragging(7)
    # The pointer's ray passes through (0.5, 2.0, 1.5): it meets y = -0.1 at a fifth of the way.
    far = (0.5, 2.0, 1.5)
    fraction = (-0.1 - CAMERA.position[1]) / (far[1] - CAMERA.position[1])
    expected = tuple(c + fraction * (f - c) for c, f in zip(CAMERA.position, far))
    assert gestures.move(7, far) == [Action(TARGET, pytest.approx(expected))]
    assert gestures.end(7, far, modifier=None, hold=False, at=1.0) == [
        Action(TARGET, pytest.approx(expected))]
    assert gestures.due(2.0) == [Action(RELEASE)]
    assert not gestures.dragging(7)
    assert gestures.move(7, far) == []


def test_a_body_that_moved_since_it_was_drawn_is_grabbed_at_the_pressed_material_point():
    """The grab carries the pressed point to the node's latest pose; the plane goes through it."""
    gestures = Gestures()
    now = Pose((0.0, 0.05, 0.98), AT_REST.orientation)
    actions = gestures.start(1, pressed=(0.1, -0.1, 1.02), camera=CAMERA, shown=AT_REST,
                             now=now, at=0.0)
    assert actions == [Action(GRAB, pytest.approx((0.1, -0.05, 1.0)))]
    (target,) = gestures.move(1, (0.1, 2.0, 1.0))
    assert target.point[1] == pytest.approx(-0.05)


@pytest.mark.parametrize('modifier, hold', [(HOLD_MODIFIER, False), (None, True)])
def test_a_hold_at_release_sends_no_release(modifier, hold):
    """Shift held at release, or the page's toggle: the last target stays, no release."""
    gestures = Gestures()
    gestures.start(2, pressed=(0.0, -0.1, 1.0), camera=CAMERA, shown=AT_REST, now=AT_REST,
                   at=0.0)
    actions = gestures.end(2, (0.0, 0.0, 1.0), modifier=modifier, hold=hold, at=1.0)
    assert [action.kind for action in actions] == [TARGET] and gestures.due(2.0) == []


def test_without_the_camera_the_targets_are_the_web_views_plane_points():
    """A browser that has not reported its camera: the pointer's own plane point is sent."""
    gestures = Gestures()
    gestures.start(3, pressed=(0.0, -0.1, 1.0), camera=None, shown=AT_REST, now=AT_REST,
                   at=0.0)
    assert gestures.move(3, (0.3, -0.1, 1.2)) == [Action(TARGET, (0.3, -0.1, 1.2))]


def test_a_click_grabs_where_the_ray_meets_the_box_then_releases_unless_held():
    """A click: a grab on the top face, then a release; with shift, the grab only."""
    down = ((0.1, 0.0, 3.0), (0.0, 0.0, -1.0))
    actions = Gestures.click(*down, now=AT_REST, geometry=BOX_SHAPE, modifier=None, hold=False)
    assert actions == [Action(GRAB, pytest.approx((0.1, 0.0, 1.05))), Action(RELEASE)]
    held = Gestures.click(*down, now=AT_REST, geometry=BOX_SHAPE, modifier=HOLD_MODIFIER,
                          hold=False)
    assert [action.kind for action in held] == [GRAB]
    assert Gestures.click((1.0, 0.0, 3.0), (0.0, 0.0, -1.0), now=AT_REST, geometry=BOX_SHAPE,
                          modifier=None, hold=False) == []


def test_shift_pressed_before_the_release_holds_the_body_and_the_drag_goes_on():
    """
    The browser ends a drag's segment when shift goes down and starts the next: one drag.

    The next segment's start within SEGMENT_GAP of the end continues the drag (no release, no
    new grab); its end with shift holds. A plain release goes once SEGMENT_GAP has passed.
    """
    gestures = Gestures()
    pressed = (0.1, -0.1, 1.02)
    assert [a.kind for a in gestures.start(5, pressed=pressed, camera=CAMERA, shown=AT_REST,
                                           now=AT_REST, at=1.0)] == [GRAB]
    far = (0.5, 2.0, 1.5)
    [target] = gestures.move(5, far)
    assert gestures.end(5, far, modifier=None, hold=False, at=1.2) == [target]
    assert gestures.due(1.2 + 0.5 * SEGMENT_GAP) == [] and gestures.ending(5)
    # shift down: the next segment starts, where the pointer is; the drag is the same one
    assert gestures.start(5, pressed=far, camera=None, shown=AT_REST, now=AT_REST,
                          at=1.2 + 0.5 * SEGMENT_GAP) == []
    assert gestures.dragging(5) and not gestures.ending(5) and gestures.move(5, far) == [target]
    assert gestures.end(5, far, modifier=HOLD_MODIFIER, hold=False, at=1.3) == [target]
    assert gestures.ending(5)
    assert gestures.due(10.0) == [] and not gestures.dragging(5) and not gestures.ending(5)


def test_a_plain_release_goes_once_no_next_segment_came():
    """No start within SEGMENT_GAP: the release; a start after it grabs anew, released first."""
    gestures = Gestures()
    gestures.start(6, pressed=(0.1, -0.1, 1.02), camera=CAMERA, shown=AT_REST, now=AT_REST,
                   at=0.0)
    assert gestures.end(6, (0.5, 2.0, 1.5), modifier=None, hold=False, at=1.0) != []
    assert gestures.due(1.0 + SEGMENT_GAP) == []
    assert gestures.due(1.0 + 1.01 * SEGMENT_GAP) == [Action(RELEASE)]
    assert gestures.due(5.0) == []
    gestures.start(6, pressed=(0.1, -0.1, 1.02), camera=CAMERA, shown=AT_REST, now=AT_REST,
                   at=6.0)
    gestures.end(6, (0.5, 2.0, 1.5), modifier=None, hold=False, at=7.0)
    actions = gestures.start(6, pressed=(0.1, -0.1, 1.02), camera=CAMERA, shown=AT_REST,
                             now=AT_REST, at=7.0 + 2.0 * SEGMENT_GAP)
    assert [a.kind for a in actions] == [RELEASE, GRAB]
