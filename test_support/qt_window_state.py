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
Qt 5's ``QMainWindow::saveState`` layout, read and written: the ``QMainWindow State`` of a .rviz.

rviz2 adds every panel of a configuration as a floating dock widget and docks it only when
``restoreState`` finds it, by its object name (the panel's ``Name``), in the state's dock areas.
The state is a ``QDataStream`` (big-endian) of:

- ``int 0xff`` (the version marker) and ``int 0`` (the version);
- ``uchar 0xfd`` and an ``int`` count of non-empty dock areas, each an ``int`` area (0 left,
  1 right, 2 top, 3 bottom), its ``QSize`` (two ints) and its item sequence: ``uchar 0xfc`` (a
  sequence) or ``uchar 0xfa`` and an ``int`` current index (tabs), ``uchar`` orientation (1
  horizontal, 2 vertical), an ``int`` count and the items; a dock widget is ``uchar 0xfb``, its
  object name (a ``QString``: ``uint32`` byte length and UTF-16BE), ``uchar`` flags (1 visible,
  2 floating) and four ints (position, size and two more along the area; x, y, width, height
  when floating); a nested sequence is ``uchar 0xfc``, four ints and a sequence;
- the central widget's ``QSize`` and four ``int`` corners (which area owns each corner);
- ``uchar 0xfc`` and the toolbar lines: an ``int`` count, each an ``int`` position and an ``int``
  count of toolbars, each its object name, ``uchar`` shown and orientation (1 shown, 2
  vertical), ``int`` position, ``int`` preferred size and two ``uint32`` of floating geometry.

This is the layout of qdockarealayout.cpp and qtoolbararealayout.cpp (Qt 5.15), read here so that
a test can check which panels a .rviz docks; ``encode`` writes the same layout.
"""

from dataclasses import dataclass, field
import struct
from typing import Collection, List, Tuple, Union

VERSION_MARKER = 0xff
DOCK_MARKER = 0xfd
SEQUENCE_MARKER = 0xfc
TAB_MARKER = 0xfa
WIDGET_MARKER = 0xfb
TOOLBAR_MARKER = 0xfc
VISIBLE = 1
FLOATING = 2
HORIZONTAL, VERTICAL = 1, 2
LEFT, RIGHT, TOP, BOTTOM = 0, 1, 2, 3


@dataclass
class DockWidget:
    """A dock widget by object name: flags (VISIBLE, FLOATING) and its four geometry ints."""

    name: str
    flags: int
    geometry: Tuple[int, int, int, int]


@dataclass
class Sequence:
    """Items along one orientation; ``tab`` is the current tab's index, or None (no tabs)."""

    orientation: int
    items: List[Union[DockWidget, 'Nested']]
    tab: Union[int, None] = None


@dataclass
class Nested:
    """A sequence inside a sequence, with its four geometry ints."""

    geometry: Tuple[int, int, int, int]
    sequence: Sequence


@dataclass
class Toolbar:
    """A toolbar by object name: shown and orientation flags, position, preferred size."""

    name: str
    flags: int
    position: int
    preferred_size: int
    geometry: Tuple[int, int] = (0, 0)


@dataclass
class WindowState:
    """A main window's dock areas ({area: (size, sequence)}), central size, corners, toolbars."""

    docks: dict
    central_size: Tuple[int, int]
    corners: Tuple[int, int, int, int]
    toolbars: List[Tuple[int, List[Toolbar]]] = field(default_factory=list)

    def dock_widgets(self) -> List[DockWidget]:
        """Return every dock widget of every area, in order."""
        found = []

        def walk(sequence: Sequence) -> None:
            for item in sequence.items:
                if isinstance(item, DockWidget):
                    found.append(item)
                else:
                    walk(item.sequence)
        for _size, sequence in self.docks.values():
            walk(sequence)
        return found


class _Reader:
    def __init__(self, data: bytes) -> None:
        self.data, self.offset = data, 0

    def take(self, form: str):
        values = struct.unpack_from('>' + form, self.data, self.offset)
        self.offset += struct.calcsize('>' + form)
        return values if len(values) > 1 else values[0]

    def string(self) -> str:
        length = self.take('I')
        text = self.data[self.offset:self.offset + length].decode('utf-16-be')
        self.offset += length
        return text

    def sequence(self) -> Sequence:
        marker = self.take('B')
        if marker not in (SEQUENCE_MARKER, TAB_MARKER):
            raise ValueError(f'expected a sequence at byte {self.offset - 1}, got {marker:#x}')
        tab = self.take('i') if marker == TAB_MARKER else None
        orientation, count = self.take('Bi')
        items = []
        for _ in range(count):
            marker = self.take('B')
            if marker == WIDGET_MARKER:
                name, flags = self.string(), self.take('B')
                items.append(DockWidget(name, flags, self.take('iiii')))
            elif marker == SEQUENCE_MARKER:
                geometry = self.take('iiii')
                items.append(Nested(geometry, self.sequence()))
            else:
                raise ValueError(f'unknown item marker {marker:#x} at byte {self.offset - 1}')
        return Sequence(orientation, items, tab)


def decode(data: bytes) -> WindowState:
    """
    Return the state ``QMainWindow::saveState`` wrote in ``data``.

    :raises ValueError: when a marker is not where the layout has it, or bytes are left over.
    :raises struct.error: when ``data`` ends early.
    """
    reader = _Reader(data)
    if reader.take('ii') != (VERSION_MARKER, 0):
        raise ValueError('not a QMainWindow state of version 0')
    if reader.take('B') != DOCK_MARKER:
        raise ValueError('no dock widget state')
    docks = {}
    for _ in range(reader.take('i')):
        area, width, height = reader.take('iii')
        docks[area] = ((width, height), reader.sequence())
    central_size, corners = reader.take('ii'), reader.take('iiii')
    toolbars = []
    if reader.offset < len(data):
        if reader.take('B') != TOOLBAR_MARKER:
            raise ValueError('no toolbar state')
        for _ in range(reader.take('i')):
            position, count = reader.take('ii')
            line = []
            for _ in range(count):
                name = reader.string()
                flags, position_in_line, preferred = reader.take('Bii')
                line.append(Toolbar(name, flags, position_in_line, preferred, reader.take('II')))
            toolbars.append((position, line))
    if reader.offset != len(data):
        raise ValueError(f'{len(data) - reader.offset} bytes left over')
    return WindowState(docks, central_size, corners, toolbars)


def _string(text: str) -> bytes:
    raw = text.encode('utf-16-be')
    return struct.pack('>I', len(raw)) + raw


def _sequence(sequence: Sequence) -> bytes:
    out = (struct.pack('>B', SEQUENCE_MARKER) if sequence.tab is None
           else struct.pack('>Bi', TAB_MARKER, sequence.tab))
    out += struct.pack('>Bi', sequence.orientation, len(sequence.items))
    for item in sequence.items:
        if isinstance(item, DockWidget):
            out += struct.pack('>B', WIDGET_MARKER) + _string(item.name)
            out += struct.pack('>Biiii', item.flags, *item.geometry)
        else:
            out += struct.pack('>Biiii', SEQUENCE_MARKER, *item.geometry)
            out += _sequence(item.sequence)
    return out


def encode(state: WindowState) -> bytes:
    """Return the bytes ``QMainWindow::saveState`` writes for ``state`` (``decode``'s inverse)."""
    out = struct.pack('>iiBi', VERSION_MARKER, 0, DOCK_MARKER, len(state.docks))
    for area, (size, sequence) in sorted(state.docks.items()):
        out += struct.pack('>iii', area, *size) + _sequence(sequence)
    out += struct.pack('>ii', *state.central_size) + struct.pack('>iiii', *state.corners)
    out += struct.pack('>Bi', TOOLBAR_MARKER, len(state.toolbars))
    for position, line in state.toolbars:
        out += struct.pack('>ii', position, len(line))
        for toolbar in line:
            out += _string(toolbar.name) + struct.pack(
                '>BiiII', toolbar.flags, toolbar.position, toolbar.preferred_size,
                *toolbar.geometry)
    return out


# QWIDGETSIZE_MAX: what Qt writes as a dock widget's maximum size along its area.
QWIDGETSIZE_MAX = (1 << 24) - 1
# Qt::DockWidgetArea of each corner, Qt's default: top corners to the top area, bottom ones to
# the bottom area.
DEFAULT_CORNERS = (4, 4, 8, 8)


def docked_layout(*, width: Tuple[int, int, int], height: int, top: int,
                  left: List[Tuple[str, int]], right: List[Tuple[str, int]],
                  hidden: Collection[str] = (),
                  toolbar: str) -> WindowState:
    """
    Return the state of a window with dock widgets stacked in its left and right areas.

    :param width: the left area's, the central widget's and the right area's widths (px).
    :param height: the dock areas' height (px).
    :param top: where the dock areas start: below the menu bar and the toolbar (px).
    :param left: (object name, height in px) of each widget of the left area, top down.
    :param right: the same for the right area.
    :param hidden: the names of widgets docked but hidden (shown from the window's menu).
    :param toolbar: the object name of the one toolbar, at the top.
    """
    def area(widgets: List[Tuple[str, int]]) -> Sequence:
        items, position = [], top
        for name, size in widgets:
            flags = 0 if name in hidden else VISIBLE
            items.append(DockWidget(name, flags, (position, size, 0, QWIDGETSIZE_MAX)))
            position += size
        return Sequence(VERTICAL, items)

    left_width, central_width, right_width = width
    return WindowState(
        docks={LEFT: ((left_width, height), area(left)),
               RIGHT: ((right_width, height), area(right))},
        central_size=(central_width, height), corners=DEFAULT_CORNERS,
        toolbars=[(TOP, [Toolbar(toolbar, VISIBLE, 0, -1)])])
