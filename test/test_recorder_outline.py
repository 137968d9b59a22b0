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
``mouse_record``'s figure outlines a URDF body: the convex hull of its collision pieces, projected.

A recording in lockstep of a link of a sphere above the mug, turned and dragged: the recorder
reads the URDF from the node at the start, and the figure's outlines, from above and from the
side, where the body started and where it ended, are the 2-D convex hulls of the hull's vertices
placed by those poses (``BodyState.world_point``, the node's own placing) and projected. The box
body is outlined nowhere, as before.
"""

from pathlib import Path

import numpy as np
import pytest
from scipy.spatial import ConvexHull
from scipy.spatial.transform import Rotation

from mouse_constraint_ros.description.urdf_link import body_model
from mouse_constraint_ros.physics import BodyState
from mouse_constraint_ros.recording.body_outline import body_hull, outline
from mouse_constraint_ros.recording.capture import fetch_start, Recorder
from mouse_constraint_ros.recording.figure import draw_figure
from mouse_constraint_ros.recording.rows import tick_rows
from mouse_constraint_ros.timing.spin import StopRequest
from test_support.meshes import geometry, inertial, mug, urdf, write

LABELS = ('body at start (hull)', 'body at end (hull)')
START = tuple(Rotation.from_euler('xz', [0.4, 0.3]).as_quat())


def cup_urdf(folder: Path) -> str:
    """Return the URDF of a sphere above the mug, the mug's file in ``folder``."""
    path = write(mug(), Path(folder) / 'mug.stl')
    return urdf([inertial(0.4, (0.002, 0.0, 0.0, 0.002, 0.0, 0.001), xyz=(0.0, 0.0, 0.06)),
                 geometry('sphere', radius=0.05, xyz=(0.0, 0.0, 0.2)),
                 geometry('mesh', filename=str(path))])


def projected_hull(hull: np.ndarray, pose: BodyState, plane) -> np.ndarray:
    """Return the vertices of the 2-D convex hull of ``hull`` placed by ``pose``, projected."""
    flat = np.array([pose.world_point(tuple(point)) for point in hull])[:, list(plane)]
    return flat[ConvexHull(flat).vertices]


def outlines(figure) -> dict:
    """Return the body outlines of the two path plots: (plot, label) -> the line's points."""
    top, side = figure.axes[:2]
    return {(name, line.get_label()): line.get_xydata()
            for name, axes in (('top', top), ('side', side)) for line in axes.get_lines()
            if line.get_label() in LABELS}


def recorded(body, text: str):
    """Record the body turned, dragged 0.3 m along x and 0.1 m up; return (start, rows)."""
    recorder = body.add_node(Recorder(context=body.context))
    start = fetch_start(recorder, body.executor, StopRequest(), target_node='mouse_constraint',
                        timeout=5.0)
    for k in range(1, 31):
        body.target((0.01 * k, 0.0, 1.05 + k * 0.1 / 30))
        body.step(10)
    return start, tick_rows(recorder.received, start)


def test_the_figure_outlines_the_hull_of_a_urdf_body_where_it_started_and_ended(
        simulated_body_factory, tmp_path):
    """Each outline is closed, and its vertices are the projected hull's, to 1e-12 m."""
    text = cup_urdf(tmp_path)
    body = simulated_body_factory(robot_description=text, rate_hz=200.0,
                                  gravity=[0.0, 0.0, 0.0], initial_position=[0.0, 0.0, 1.0],
                                  initial_orientation=list(START), anchor=[0.0, 0.0, 0.05],
                                  marker_rate_hz=0.0, diagnostics_rate_hz=0.0)
    start, rows = recorded(body, text)
    assert start['robot_description'] == text and start['density'] == 0.0
    hull = body_hull(start)
    np.testing.assert_array_equal(hull, body_model(text).geometry.hull_points)
    first, last = (BodyState(row.position, row.orientation) for row in (rows[0], rows[-1]))
    assert np.linalg.norm(np.subtract(last.position, first.position)) > 0.2  # dragged
    drawn = outlines(draw_figure(rows, anchor=start['anchor'], frame_id='world', hull=hull))
    assert set(drawn) == {(name, label) for name in ('top', 'side') for label in LABELS}
    for (name, label), points in drawn.items():
        plane = (0, 1) if name == 'top' else (0, 2)
        pose = first if label == LABELS[0] else last
        expected = projected_hull(hull, pose, plane)
        np.testing.assert_array_equal(points[0], points[-1])  # closed
        ring = points[:-1]
        assert len(ring) == len(expected) >= 3
        # The same vertices, each matched to one of the other's (the start may differ).
        gaps = np.linalg.norm(ring[:, None, :] - expected[None, :, :], axis=2)
        assert np.all(gaps.min(axis=1) < 1e-12) and np.all(gaps.min(axis=0) < 1e-12)
        # Every hull vertex projected lies on the left of each edge, counter-clockwise: inside.
        every = np.array([pose.world_point(tuple(p)) for p in hull])[:, list(plane)]
        for a, b in zip(ring, points[1:]):
            edge, offsets = b - a, every - a
            assert np.all(edge[0] * offsets[:, 1] - edge[1] * offsets[:, 0] > -1e-12)


def test_the_box_body_is_outlined_nowhere_as_before(simulated_body_factory):
    """No robot_description: no hull read, no outline on the figure."""
    body = simulated_body_factory(rate_hz=200.0, gravity=[0.0, 0.0, 0.0], marker_rate_hz=0.0,
                                  diagnostics_rate_hz=0.0)
    start, rows = recorded(body, '')
    assert start['robot_description'] == '' and body_hull(start) is None
    assert body_hull({'anchor': (0.0, 0.0, 0.0)}) is None  # a node that did not say
    assert outlines(draw_figure(rows, anchor=start['anchor'], frame_id='world')) == {}


def test_a_urdf_unreadable_here_is_said_and_drawn_without_an_outline():
    """A package:// mesh of a workspace not sourced here: one warning, no hull."""
    warnings = []
    text = urdf([inertial(1.0, (0.01, 0.0, 0.0, 0.01, 0.0, 0.01)),
                 geometry('mesh', filename='package://no_such_package/meshes/a.stl')])
    assert body_hull({'robot_description': text, 'body_link': '', 'density': 0.0},
                     warnings.append) is None
    [warning] = warnings
    assert "source the workspace that installs 'no_such_package'" in warning
    assert warning.endswith('the figure draws no outline of the body')


def test_the_outline_of_a_cube_from_above_is_its_turned_square():
    """A 0.2 m cube turned 30 deg on z at (1, 2, 3): from above, its four corners, exactly."""
    corners = np.array([(x, y, z) for x in (-0.1, 0.1) for y in (-0.1, 0.1) for z in (-0.1, 0.1)])
    turn = Rotation.from_euler('z', np.pi / 6)
    ring = outline(corners, (1.0, 2.0, 3.0), tuple(turn.as_quat()), (0, 1))
    square = turn.apply([(-0.1, -0.1, 0.0), (0.1, -0.1, 0.0), (0.1, 0.1, 0.0),
                         (-0.1, 0.1, 0.0)])[:, :2] + (1.0, 2.0)
    assert len(ring) == 5 and np.array_equal(ring[0], ring[-1])
    assert sorted(map(tuple, np.round(ring[:-1], 12))) == sorted(map(tuple, np.round(square, 12)))
    # Counter-clockwise: a positive signed area, the square's 0.04 m^2.
    x, y = ring[:, 0], ring[:, 1]
    assert 0.5 * np.sum(x[:-1] * y[1:] - x[1:] * y[:-1]) == pytest.approx(0.04, abs=1e-15)
    # Points that span no area seen so (a square in the x-z plane, from above) have no outline.
    assert outline(corners * (1.0, 0.0, 1.0), (0.0, 0.0, 0.0), (0.0, 0.0, 0.0, 1.0),
                   (0, 1)) is None
