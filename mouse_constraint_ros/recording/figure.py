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
The figure of a recording: anchor and target paths, anchor error, speed and angular speed.

A recording with pushes (a wrench the node applied) gets a third row, the applied force over
time, and each push is marked where it acted: a shaded span and a line at its start on the time
plots, and its stretch of the anchor's path drawn over in magenta from a triangle where it began.
A URDF body is outlined on the path plots where it started and where it ended: its convex hull
seen from above and from the side (``body_outline``); the box body is not drawn. A robot's
recording (rows with ``joint_states``) gets a row of its own below, its joints' positions over
time.

matplotlib is imported when a figure is drawn, with its Agg canvas: no display is needed. Axes
show plain numbers (no offset such as ``1e-9+1``, which a body at rest would otherwise get), a
panel with nothing to draw says so, and text the font cannot draw (an emoji frame id) is shown
as its escapes rather than as missing glyphs.
"""

import math
from pathlib import Path
from typing import Optional, Sequence, Tuple

import numpy as np

from .applied_wrench import push_spans
from .body_outline import outline
from .rows import Row
from ..physics.algebra import Vector3

# A row without a wrench: zero force and torque.
_NO_WRENCH = ((0.0, 0.0, 0.0), (0.0, 0.0, 0.0))
# The figure: FIGURE_INCHES at FIGURE_DPI, i.e. 1500 x 1000 pixels.
FIGURE_INCHES = (15.0, 10.0)
FIGURE_DPI = 100
# Anchor errors below this are drawn at it on the logarithmic axis (m).
ERROR_FLOOR = 1e-9
# Headroom of the speed axes: a body at rest draws its zero speed inside the axes (m/s, rad/s).
SPEED_HEADROOM = 0.05
# How a push is marked: its colour, and the opacity of its span on the time plots.
PUSH_COLOR = 'magenta'
PUSH_ALPHA = 0.15
# The height of the applied wrench's row, relative to the other two rows.
WRENCH_ROW_HEIGHT = 0.6
# The height of a robot's joint positions' row, relative to the first two rows.
JOINTS_ROW_HEIGHT = 0.8
# The title of that row's panel.
JOINTS_TITLE = 'Joint positions (joint_states)'
# A URDF body's outline: its colour, and its line where the body started and where it ended.
BODY_OUTLINE_COLOR = 'tab:blue'
BODY_OUTLINES = ((0, ':', 'body at start (hull)'), (-1, '-', 'body at end (hull)'))


def drawable(text: str) -> str:
    """Return ``text`` with each character that matplotlib's font lacks as its escape."""
    from matplotlib.font_manager import FontProperties, findfont, get_font

    font = get_font(findfont(FontProperties()))
    return ''.join(c if c.isprintable() and font.get_char_index(ord(c)) else
                   c.encode('unicode_escape').decode('ascii') for c in text)


def draw_figure(rows: Sequence[Row], *, anchor: Vector3, frame_id: str,
                title: str = 'mouse_constraint', ticks: Optional[int] = None,
                hull: Optional[np.ndarray] = None):
    """
    Return the recording's figure (a matplotlib ``Figure`` on the Agg canvas, not shown).

    Top left the paths seen from above (x, y), top right from the side (x, z); bottom left the
    anchor error on a log scale, bottom right speed and angular speed. Each grab is marked: a
    cross at the grabbed point on the paths (black when the node took it, grey when it ignored
    it), a dotted vertical line at its time below. With pushes (``applied_wrench.push_spans``)
    a third row draws the applied force's components (and |torque|, when there was one) over
    time; each push is a shaded span on every time plot with a line at its start, labelled
    'push', and its stretch of the anchor path is drawn over in magenta, labelled 'anchor while
    pushed', from a triangle at the anchor where it began, labelled 'push start'. A robot's
    rows (``Row.joints``) add a last row, ``JOINTS_TITLE``: each joint's position over time, a
    line labelled by the joint's name, with the grabs and pushes marked as on the time plots.

    :param rows: the ticks, at least one.
    :param anchor: the anchor in the body frame (m) at the start, named in the title (with the
        last one when grabs changed it).
    :param frame_id: the frame of the positions, named on the axes.
    :param ticks: the ticks recorded, named in the title, when ``rows`` are fewer
        (``FigureRows``); by default ``len(rows)``.
    :param hull: a URDF body's hull vertices in the link frame (``body_outline.body_hull``):
        outlined on the path plots at the first row's pose, dotted, labelled 'body at start
        (hull)', and at the last row's, labelled 'body at end (hull)'; None draws no body.
    :raises ValueError: without rows.
    """
    from matplotlib.figure import Figure

    if not rows:
        raise ValueError('no ticks to draw')
    frame_id = drawable(frame_id)
    t = np.array([row.time for row in rows])
    anchors = np.array([row.anchor for row in rows])
    targets = np.array([row.target if row.target is not None else (np.nan,) * 3
                        for row in rows])
    errors = np.array([np.nan if row.anchor_error is None else row.anchor_error
                       for row in rows])
    grabbed = [row for row in rows if row.grab is not None]
    pushes = push_spans(rows)
    pushed = np.array([(row.wrench_force, row.wrench_torque) != _NO_WRENCH for row in rows])
    joint_names = next((row.joints.names for row in rows if row.joints is not None), ())
    figure = Figure(figsize=FIGURE_INCHES, dpi=FIGURE_DPI, layout='constrained')
    if pushes or joint_names:
        grid = figure.add_gridspec(2 + bool(pushes) + bool(joint_names), 2, height_ratios=(
            1.0, 1.0, *((WRENCH_ROW_HEIGHT,) if pushes else ()),
            *((JOINTS_ROW_HEIGHT,) if joint_names else ())))
        top, side = figure.add_subplot(grid[0, 0]), figure.add_subplot(grid[0, 1])
        error_axes, speed_axes = figure.add_subplot(grid[1, 0]), figure.add_subplot(grid[1, 1])
    else:
        (top, side), (error_axes, speed_axes) = figure.subplots(2, 2)
    for axes, (i, j), view in ((top, (0, 1), 'top view'), (side, (0, 2), 'side view')):
        axes.plot(anchors[:, i], anchors[:, j], color='tab:orange', linewidth=1.2,
                  label='anchor')
        axes.plot(targets[:, i], targets[:, j], color='tab:purple', linestyle='--',
                  linewidth=1.0, label='target')
        axes.plot(anchors[0, i], anchors[0, j], 'o', color='tab:orange', label='anchor start')
        axes.plot(anchors[-1, i], anchors[-1, j], 's', color='tab:orange', label='anchor end')
        if pushes:
            axes.plot(np.where(pushed, anchors[:, i], np.nan),
                      np.where(pushed, anchors[:, j], np.nan), color=PUSH_COLOR,
                      linewidth=2.0, label='anchor while pushed')
            starts = anchors[[index for index in range(len(rows)) if pushed[index] and (
                index == 0 or not pushed[index - 1])]]
            axes.plot(starts[:, i], starts[:, j], '^', color=PUSH_COLOR, markersize=8,
                      label='push start')
        if hull is not None:
            _draw_outlines(axes, hull, rows, (i, j))
        for taken, color, label in ((True, 'black', 'grab'), (False, 'grey', 'grab ignored')):
            points = np.array([row.grab for row in grabbed if row.grab_taken is taken])
            if len(points):
                axes.plot(points[:, i], points[:, j], 'x', color=color, markersize=9,
                          markeredgewidth=2, label=label)
        axes.set_aspect('equal', adjustable='datalim')
        axes.set_xlabel(f'{"xyz"[i]} (m, {frame_id})')
        axes.set_ylabel(f'{"xyz"[j]} (m, {frame_id})')
        axes.set_title(f'Anchor and target paths, {view}')
        axes.grid(True, alpha=0.3)
        axes.legend(loc='best', fontsize='small')
    _draw_error(error_axes, t, errors)
    spin_axes = _draw_speeds(speed_axes, t, rows)
    time_axes = [error_axes, speed_axes]
    if joint_names:
        time_axes.append(_draw_joints(figure.add_subplot(grid[-1, :]), t, rows, joint_names))
    for axes in time_axes:
        for index, row in enumerate(grabbed):
            axes.axvline(row.time, color='black' if row.grab_taken else 'grey', linestyle=':',
                         linewidth=1.0,
                         label='grab' if index == 0 and axes is speed_axes else None)
    if pushes:
        time_axes.append(_draw_wrench(figure.add_subplot(grid[2, :]), t, rows))
    for axes in time_axes:
        for index, push in enumerate(pushes):
            # The span, and a line at its start: a push of a few ticks is narrower than a pixel.
            axes.axvspan(push.start, push.end, color=PUSH_COLOR, alpha=PUSH_ALPHA, linewidth=0)
            axes.axvline(push.start, color=PUSH_COLOR, linewidth=1.0,
                         label='push' if index == 0 and axes is speed_axes else None)
    lines = [line for line in speed_axes.get_lines() + spin_axes.get_lines()
             if not line.get_label().startswith('_')]
    speed_axes.legend(lines, [line.get_label() for line in lines], loc='upper right',
                      fontsize='small')
    for axes in (top, side, speed_axes, spin_axes):
        axes.ticklabel_format(useOffset=False)
    error_axes.xaxis.get_major_formatter().set_useOffset(False)

    def point(vector) -> str:
        # To the nanometre: a grab where the anchor is gives it back up to rounding.
        return f'({", ".join(f"{round(c, 9) + 0.0:.3g}" for c in vector)})'

    last = point(rows[-1].body_anchor)
    changed = '' if last == point(anchor) else f', {last} at the end'
    grab_note = f', {len(grabbed)} grab{"s" if len(grabbed) != 1 else ""}' if grabbed else ''
    push_note = f', {len(pushes)} push{"es" if len(pushes) != 1 else ""}' if pushes else ''
    ticks = len(rows) if ticks is None else ticks
    figure.suptitle(f'{drawable(title)}: {t[-1]:.1f} s, {ticks} ticks, anchor '
                    f'{point(anchor)}{changed} m in the body frame{grab_note}{push_note}')
    return figure


def _draw_outlines(axes, hull: np.ndarray, rows: Sequence[Row], plane: Tuple[int, int]) -> None:
    """Outline the body's hull at the first and the last row's pose (``BODY_OUTLINES``)."""
    for index, style, label in BODY_OUTLINES:
        ring = outline(hull, rows[index].position, rows[index].orientation, plane)
        if ring is not None:
            axes.plot(ring[:, 0], ring[:, 1], color=BODY_OUTLINE_COLOR, linestyle=style,
                      linewidth=1.0, label=label)


def _draw_error(axes, t, errors) -> None:
    axes.set_xlim(0.0, max(t[-1], 1e-3))
    axes.set_xlabel('time (s)')
    axes.set_ylabel('anchor error |anchor - target| (m)')
    axes.set_title('Anchor error')
    if np.all(np.isnan(errors)):
        axes.text(0.5, 0.5, 'no target: the node held none while recorded', ha='center',
                  va='center', transform=axes.transAxes)
        axes.set_yticks([])
        return
    axes.semilogy(t, np.maximum(errors, ERROR_FLOOR), color='tab:red', linewidth=0.8)
    axes.grid(True, which='both', alpha=0.3)


def _draw_speeds(axes, t, rows):
    """Draw speed and angular speed on ``axes`` and a twin; return the twin."""
    speeds = np.array([row.speed for row in rows])
    spins = np.array([row.angular_speed for row in rows])
    axes.plot(t, speeds, color='tab:blue', linewidth=1.5, label='speed |v| (m/s)')
    axes.set_xlim(0.0, max(t[-1], 1e-3))
    axes.set_xlabel('time (s)')
    axes.set_ylabel('speed of the COM (m/s)', color='tab:blue')
    spin_axes = axes.twinx()
    # Dashed over the solid speed line: where both are zero (at rest), both show.
    spin_axes.plot(t, spins, color='tab:green', linewidth=1.0, linestyle='--',
                   label='angular speed |w| (rad/s)')
    spin_axes.set_ylabel('angular speed (rad/s)', color='tab:green')
    for twin, values in ((axes, speeds), (spin_axes, spins)):
        top = max(float(np.max(values)), SPEED_HEADROOM)
        twin.set_ylim(-0.05 * top, 1.05 * top)
    axes.set_title('Speed and angular speed')
    axes.grid(True, alpha=0.3)
    return spin_axes


def _draw_wrench(axes, t, rows):
    """Draw the applied force's components (and |torque|, when any) as steps; return ``axes``."""
    forces = np.array([row.wrench_force for row in rows])
    torques = np.array([math.hypot(*row.wrench_torque) for row in rows])
    for index, color in enumerate(('tab:blue', 'tab:orange', 'tab:green')):
        axes.plot(t, forces[:, index], color=color, linewidth=1.2, drawstyle='steps-post',
                  label=f'force {"xyz"[index]} (N)')
    axes.set_xlim(0.0, max(t[-1], 1e-3))
    axes.set_xlabel('time (s)')
    axes.set_ylabel('force (N, through the COM)')
    axes.set_title('Applied wrench (wrench topic, world frame)')
    axes.grid(True, alpha=0.3)
    handles = axes.get_lines()
    if np.any(torques):
        torque_axes = axes.twinx()
        torque_axes.plot(t, torques, color='tab:purple', linewidth=1.0, linestyle='--',
                         drawstyle='steps-post', label='|torque| (N m)')
        torque_axes.set_ylabel('|torque| (N m)', color='tab:purple')
        handles = handles + torque_axes.get_lines()
    axes.legend(handles, [line.get_label() for line in handles], loc='upper right',
                fontsize='small')
    return axes


def _draw_joints(axes, t, rows: Sequence[Row], names: Sequence[str]):
    """Draw each joint's position over time (a gap where a row has none); return ``axes``."""
    for name in names:
        positions = [None if row.joints is None else row.joints.value(name, 'position')
                     for row in rows]
        axes.plot(t, np.array([np.nan if p is None else p for p in positions]), linewidth=1.2,
                  label=drawable(name))
    axes.set_xlim(0.0, max(t[-1], 1e-3))
    axes.set_xlabel('time (s)')
    axes.set_ylabel('position (rad; m if prismatic)')
    axes.set_title(JOINTS_TITLE)
    axes.grid(True, alpha=0.3)
    axes.ticklabel_format(useOffset=False)
    axes.legend(loc='upper right', fontsize='small', ncol=max(1, len(names) // 8))
    return axes


def write_figure(path: Path, rows: Sequence[Row], *, anchor: Vector3, frame_id: str,
                 title: str = 'mouse_constraint', ticks: Optional[int] = None,
                 hull: Optional[np.ndarray] = None) -> None:
    """Draw the recording (``draw_figure``) into a PNG of ``FIGURE_INCHES`` at ``FIGURE_DPI``."""
    draw_figure(rows, anchor=anchor, frame_id=frame_id, title=title, ticks=ticks,
                hull=hull).savefig(path, dpi=FIGURE_DPI)
