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
The URDF's text checked element by element before the parser reads it.

yourdfpy takes what it is given: a ``<box size="1 2"/>``, a ``scale="nan 1 1"``, an
``<inertia/>`` without its moments or an ``rgba`` of two values pass it and fail later, far from
their cause, or not at all. Here each element of the body's link is read with lxml as the URDF
specification writes it, and the first that is not is refused in one line naming the link, the
element, what is wrong and the fix: numbers where numbers belong (finite, as many as the
attribute takes), one shape per ``<geometry>``, a ``filename`` on each ``<mesh>``, the six
moments of an ``<inertia>``, four colour components in [0, 1]. A ``${...}`` or ``$(...)``
anywhere is xacro that was not expanded.
"""

import math
from typing import List, Optional, Sequence

from lxml import etree

from .text_size import oversized
from .xml_declaration import as_xml_1_0
from ..physics.limits import MAX_DISTANCE

# The shapes one <geometry> holds.
SHAPES = ('box', 'sphere', 'cylinder', 'mesh')
# The moments of an <inertia>, in URDF order.
MOMENTS = ('ixx', 'ixy', 'ixz', 'iyy', 'iyz', 'izz')


def checked_root(text: str) -> etree._Element:
    """
    Return the ``<robot>`` element of the URDF ``text``; raise ValueError saying what is wrong.

    The size is checked before the text is parsed; then xacro left unexpanded.
    """
    if not isinstance(text, str) or not text.strip():
        raise ValueError('robot_description is empty')
    too_long = oversized(text)
    if too_long is not None:
        raise ValueError(too_long)
    data = as_xml_1_0(text).encode('utf-8', 'replace')  # pybullet's URDFs declare 0.0
    try:
        root = etree.fromstring(data, etree.XMLParser(resolve_entities=False, no_network=True))
    except etree.XMLSyntaxError as error:
        raise ValueError(f'robot_description is not well-formed XML: {error}') from None
    if root.tag != 'robot':
        raise ValueError(f'robot_description must have a <robot> root, got <{root.tag}>')
    for element in root.iter(tag=etree.Element):
        for name, value in element.attrib.items():
            if '${' in value or '$(' in value:
                raise ValueError(
                    f'{_where(element)} {name}="{value}" is xacro: robot_description is read '
                    'as plain URDF; expand it with xacro first (xacro file.urdf.xacro > '
                    'file.urdf)')
    return root


def link_elements(root: etree._Element) -> List[etree._Element]:
    """Return the ``<link>`` elements of the robot, each with a name."""
    links = root.findall('link')
    for link in links:
        if not link.get('name'):
            raise ValueError('robot_description has a <link> without a name: give it one')
    return links


def check_link(link: etree._Element) -> None:
    """Check every element of ``link`` the body is read from; raise ValueError at the first."""
    for inertial in link.findall('inertial'):
        _origin(inertial)
        masses = inertial.findall('mass')
        if len(masses) != 1:
            raise ValueError(f'{_where(inertial)} needs one <mass value="kg"/>, has '
                             f'{len(masses)}')
        _numbers(masses[0], 'value', 1)
        for inertia in inertial.findall('inertia'):
            missing = [name for name in MOMENTS if inertia.get(name) is None]
            if missing:
                raise ValueError(
                    f'{_where(inertia)} lacks {", ".join(missing)}: give all six moments '
                    f'({" ".join(MOMENTS)}, kg m^2, about the COM); 0 for a product of '
                    'inertia that is zero')
            for name in MOMENTS:
                _numbers(inertia, name, 1)
    for kind in ('collision', 'visual'):
        for element in link.findall(kind):
            _piece(element)


def _piece(element: etree._Element) -> None:
    """Check one ``<collision>`` or ``<visual>``: its origin, one shape, its material."""
    _origin(element)
    geometries = element.findall('geometry')
    shapes = [child for geometry in geometries for child in geometry
              if isinstance(child.tag, str)]
    if len(geometries) != 1 or len(shapes) != 1 or shapes[0].tag not in SHAPES:
        found = ', '.join(f'<{s.tag}>' for s in shapes) or 'nothing'
        raise ValueError(f'{_where(element)} needs one <geometry> holding one box, sphere, '
                         f'cylinder or mesh; it has {len(geometries)} <geometry> holding '
                         f'{found}')
    shape = shapes[0]
    if shape.tag == 'box':
        _numbers(shape, 'size', 3, fix='three edge lengths x y z (m)')
    elif shape.tag == 'sphere':
        _numbers(shape, 'radius', 1)
    elif shape.tag == 'cylinder':
        _numbers(shape, 'radius', 1)
        _numbers(shape, 'length', 1)
    else:
        if not (shape.get('filename') or '').strip():
            raise ValueError(f'{_where(shape)} has no filename: name the mesh file '
                             '(package://, file:// or an absolute path)')
        if shape.get('scale') is not None:
            _numbers(shape, 'scale', (1, 3), fix='x y z factors, or one for all three')
    for color in element.iterfind('material/color'):
        values = _numbers(color, 'rgba', 4, fix='four components r g b a, each in [0, 1]')
        if not all(0.0 <= v <= 1.0 for v in values):
            raise ValueError(f'{_where(color)} rgba="{color.get("rgba")}": each of r g b a '
                             'must lie in [0, 1]')


def _origin(element: etree._Element) -> None:
    """Check the ``<origin>`` of ``element``, if any: xyz and rpy of three finite numbers."""
    for origin in element.findall('origin'):
        for name in ('xyz', 'rpy'):
            if origin.get(name) is not None:
                values = _numbers(origin, name, 3, fix='three numbers')
                if name == 'xyz' and not max(abs(v) for v in values) <= MAX_DISTANCE:
                    raise ValueError(f'{_where(origin)} xyz="{origin.get(name)}" lies beyond '
                                     f'{MAX_DISTANCE:g} m: give a point within it')


def _numbers(element: etree._Element, name: str, count, *,
             fix: Optional[str] = None) -> Sequence[float]:
    """Return the finite numbers of attribute ``name``; raise ValueError unless ``count``."""
    counts = (count,) if isinstance(count, int) else tuple(count)
    text = element.get(name)
    wanted = fix or ('one number' if counts == (1,) else f'{counts[0]} numbers')
    if text is None:
        raise ValueError(f'{_where(element)} has no {name}: give {wanted}')
    try:
        values = [float(word) for word in text.split()]
    except ValueError:
        raise ValueError(f'{_where(element)} {name}="{text}" is not numbers: give '
                         f'{wanted}') from None
    if len(values) not in counts:
        raise ValueError(f'{_where(element)} {name}="{text}" has {len(values)} values: give '
                         f'{wanted}')
    if not all(math.isfinite(v) for v in values):
        raise ValueError(f'{_where(element)} {name}="{text}" is not finite: give {wanted}, '
                         'finite')
    return values


def _where(element: etree._Element) -> str:
    """
    Return where ``element`` is: its link, and the path from it (``<collision> 2 <geometry>``).

    An element one of several of its kind under its parent is numbered from 1.
    """
    path, link = [], None
    node = element
    while node is not None and isinstance(node.tag, str) and node.tag != 'robot':
        if node.tag == 'link':
            link = node.get('name', '')
            break
        parent = node.getparent()
        siblings = [] if parent is None else parent.findall(node.tag)
        number = f' {siblings.index(node) + 1}' if len(siblings) > 1 else ''
        path.append(f'<{node.tag}>{number}')
        node = parent
    where = ' '.join(reversed(path))
    if link is not None:
        return f'link {link!r} {where}'.rstrip()
    return f'robot_description {where}'.rstrip()
