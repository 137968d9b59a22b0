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

matplotlib is imported when a figure is drawn, with its Agg canvas: no display is needed.
"""

from pathlib import Path
from typing import Sequence

import numpy as np

from .rows import Row
from ..physics.algebra import Vector3

# The figure: FIGURE_INCHES at FIGURE_DPI, i.e. 1500 x 1000 pixels.
FIGURE_INCHES = (15.0, 10.0)
FIGURE_DPI = 100
# Anchor errors below this are drawn at it on the logarithmic axis (m).
ERROR_FLOOR = 1e-9


def write_figure(path: Path, rows: Sequence[Row], *, anchor: Vector3, frame_id: str,
                 title: str = 'mouse_constraint') -> None:
    """
    Draw the recording into a PNG of ``FIGURE_INCHES`` at ``FIGURE_DPI`` (Agg, no display).

    Top left the paths seen from above (x, y), top right from the side (x, z); bottom left the
    anchor error on a log scale, bottom right speed and angular speed. Each grab is marked: a
    black cross at the grabbed point on the paths, a dotted vertical line at its time below.

    :param rows: the ticks, at least one.
    :param anchor: the anchor in the body frame (m) at the start, named in the title (with the
        last one when grabs changed it).
    :param frame_id: the frame of the positions, named on the axes.
    :raises ValueError: without rows.
    """
    from matplotlib.figure import Figure

    if not rows:
        raise ValueError('no ticks to draw')
    t = np.array([row.time for row in rows])
    anchors = np.array([row.anchor for row in rows])
    targets = np.array([row.target if row.target is not None else (np.nan,) * 3
                        for row in rows])
    errors = np.array([np.nan if row.anchor_error is None else row.anchor_error
                       for row in rows])
    grabbed = [row for row in rows if row.grab is not None]
    grabs = np.array([row.grab for row in grabbed]).reshape(-1, 3)
    figure = Figure(figsize=FIGURE_INCHES, dpi=FIGURE_DPI, layout='constrained')
    (top, side), (error_axes, speed_axes) = figure.subplots(2, 2)
    for axes, (i, j), view in ((top, (0, 1), 'top view'), (side, (0, 2), 'side view')):
        axes.plot(anchors[:, i], anchors[:, j], color='tab:orange', linewidth=1.2,
                  label='anchor')
        axes.plot(targets[:, i], targets[:, j], color='tab:purple', linestyle='--',
                  linewidth=1.0, label='target')
        axes.plot(anchors[0, i], anchors[0, j], 'o', color='tab:orange', label='anchor start')
        axes.plot(anchors[-1, i], anchors[-1, j], 's', color='tab:orange', label='anchor end')
        if grabbed:
            axes.plot(grabs[:, i], grabs[:, j], 'x', color='black', markersize=9,
                      markeredgewidth=2, label='grab')
        axes.set_aspect('equal', adjustable='datalim')
        axes.set_xlabel(f'{"xyz"[i]} (m, {frame_id})')
        axes.set_ylabel(f'{"xyz"[j]} (m, {frame_id})')
        axes.set_title(f'Anchor and target paths, {view}')
        axes.grid(True, alpha=0.3)
        axes.legend(loc='best', fontsize='small')
    error_axes.semilogy(t, np.maximum(errors, ERROR_FLOOR), color='tab:red', linewidth=0.8)
    error_axes.set_xlim(0.0, max(t[-1], 1e-3))
    error_axes.set_xlabel('time (s)')
    error_axes.set_ylabel('anchor error |anchor - target| (m)')
    error_axes.set_title('Anchor error')
    error_axes.grid(True, which='both', alpha=0.3)
    speed_axes.plot(t, [row.speed for row in rows], color='tab:blue', label='speed |v| (m/s)')
    speed_axes.set_xlim(0.0, max(t[-1], 1e-3))
    speed_axes.set_xlabel('time (s)')
    speed_axes.set_ylabel('speed of the COM (m/s)', color='tab:blue')
    spin_axes = speed_axes.twinx()
    spin_axes.plot(t, [row.angular_speed for row in rows], color='tab:green', linewidth=1.0,
                   label='angular speed |w| (rad/s)')
    spin_axes.set_ylabel('angular speed (rad/s)', color='tab:green')
    speed_axes.set_title('Speed and angular speed')
    for axes in (error_axes, speed_axes):
        for index, row in enumerate(grabbed):
            axes.axvline(row.time, color='black', linestyle=':', linewidth=1.0,
                         label='grab' if index == 0 and axes is speed_axes else None)
    speed_axes.grid(True, alpha=0.3)
    lines = [line for line in speed_axes.get_lines() + spin_axes.get_lines()
             if not line.get_label().startswith('_')]
    speed_axes.legend(lines, [line.get_label() for line in lines], loc='upper right',
                      fontsize='small')

    def point(vector) -> str:
        # To the nanometre: a grab where the anchor is gives it back up to rounding.
        return f'({", ".join(f"{round(c, 9) + 0.0:.3g}" for c in vector)})'

    last = point(rows[-1].body_anchor)
    changed = '' if last == point(anchor) else f', {last} at the end'
    grab_note = f', {len(grabbed)} grab{"s" if len(grabbed) != 1 else ""}' if grabbed else ''
    figure.suptitle(f'{title}: {t[-1]:.1f} s, {len(rows)} ticks, anchor {point(anchor)}'
                    f'{changed} m in the body frame{grab_note}')
    figure.savefig(path, dpi=FIGURE_DPI)
