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
Bodies to test and measure: URDF text for a link, and the meshes its pieces name.

``urdf`` writes one link from its parts; the meshes are made here from closed forms (no file is
written by hand): ``mug`` (a surface of revolution, closed, that ``config/mug.stl`` is made of:
``python -m test_support.meshes config/mug.stl``), ``cube``, ``ellipsoid_hull`` (a convex mesh of
exactly ``count`` hull vertices, the benchmark's) and ``open_box`` (a box with a face missing).
"""

import math
import os
from pathlib import Path
import sys
from typing import Dict, Iterable, Optional, Sequence, Tuple

import numpy as np
import trimesh

# The mug: outer radius, wall, height and bottom (m), and the sections of its revolution.
MUG_RADIUS = 0.04
MUG_WALL = 0.005
MUG_HEIGHT = 0.1
MUG_BOTTOM = 0.008
MUG_SECTIONS = 48


def mug() -> trimesh.Trimesh:
    """Return a closed mug-like cup, its base on z = 0 and its axis along z."""
    r, w, h, b = MUG_RADIUS, MUG_WALL, MUG_HEIGHT, MUG_BOTTOM
    # The profile in (radius, z), closed: out along the base, up the outside, down the inside.
    profile = np.array([(0.0, 0.0), (r, 0.0), (r, h), (r - w, h), (r - w, b), (0.0, b)])
    mesh = trimesh.creation.revolve(profile, sections=MUG_SECTIONS)
    mesh.merge_vertices()
    return mesh


def cube(edge: float) -> trimesh.Trimesh:
    """Return a cube of ``edge`` (m) about the origin: eight vertices, twelve triangles."""
    return trimesh.creation.box((edge, edge, edge))


def box(size: Sequence[float]) -> trimesh.Trimesh:
    """Return a box mesh of full edges ``size`` (m) about the origin."""
    return trimesh.creation.box(tuple(size))


def ellipsoid_hull(count: int, axes: Sequence[float]) -> trimesh.Trimesh:
    """Return the convex hull of ``count`` Fibonacci points on an ellipsoid: all are vertices."""
    k = np.arange(count) + 0.5
    polar = np.arccos(1.0 - 2.0 * k / count)
    azimuth = math.pi * (1.0 + math.sqrt(5.0)) * k
    points = np.column_stack((np.cos(azimuth) * np.sin(polar),
                              np.sin(azimuth) * np.sin(polar), np.cos(polar)))
    return trimesh.convex.convex_hull(points * np.asarray(axes, dtype=float))


def open_box(size: Sequence[float]) -> trimesh.Trimesh:
    """Return a box mesh missing two triangles (a face): not a closed surface."""
    mesh = box(size)
    return trimesh.Trimesh(mesh.vertices, mesh.faces[2:], process=False)


def write(mesh: trimesh.Trimesh, path: Path) -> Path:
    """Write ``mesh`` as binary STL to ``path``; return the path."""
    path = Path(path)
    path.write_bytes(mesh.export(file_type='stl'))
    return path


def _origin(xyz: Sequence[float], rpy: Sequence[float]) -> str:
    return (f'<origin xyz="{" ".join(repr(float(c)) for c in xyz)}" '
            f'rpy="{" ".join(repr(float(c)) for c in rpy)}"/>')


def inertial(mass: float, inertia: Sequence[float], *, xyz=(0.0, 0.0, 0.0),
             rpy=(0.0, 0.0, 0.0)) -> str:
    """Return an ``<inertial>`` element: mass (kg), inertia in URDF order, its origin."""
    names = ('ixx', 'ixy', 'ixz', 'iyy', 'iyz', 'izz')
    values = ' '.join(f'{n}="{float(v)!r}"' for n, v in zip(names, inertia))
    return (f'<inertial>{_origin(xyz, rpy)}<mass value="{float(mass)!r}"/>'
            f'<inertia {values}/></inertial>')


def geometry(kind: str, *, size: Sequence[float] = (), radius: float = 0.0,
             length: float = 0.0, filename: str = '', scale: Optional[Sequence[float]] = None,
             xyz=(0.0, 0.0, 0.0), rpy=(0.0, 0.0, 0.0), element: str = 'collision') -> str:
    """Return a ``<collision>`` (or ``<visual>``) element of one box, sphere, cylinder or mesh."""
    if kind == 'box':
        shape = f'<box size="{" ".join(repr(float(e)) for e in size)}"/>'
    elif kind == 'sphere':
        shape = f'<sphere radius="{float(radius)!r}"/>'
    elif kind == 'cylinder':
        shape = f'<cylinder radius="{float(radius)!r}" length="{float(length)!r}"/>'
    else:
        scaled = '' if scale is None else f' scale="{" ".join(repr(float(s)) for s in scale)}"'
        shape = f'<mesh filename="{filename}"{scaled}/>'
    return f'<{element}>{_origin(xyz, rpy)}<geometry>{shape}</geometry></{element}>'


def urdf(parts: Iterable[str], *, link: str = 'body', extra_links: Sequence[str] = ()) -> str:
    """Return a URDF of one link ``link`` made of ``parts`` (and empty ``extra_links``)."""
    links = ''.join(f'<link name="{name}"/>' for name in extra_links)
    return (f'<?xml version="1.0"?><robot name="test"><link name="{link}">{"".join(parts)}'
            f'</link>{links}</robot>')


def box_urdf(mass: float, size: Sequence[float], *, link: str = 'body') -> str:
    """Return the URDF of a uniform solid box: the inertia as ``RigidBody.solid_box`` has it."""
    from mouse_constraint_ros.physics import RigidBody
    body = RigidBody.solid_box(mass, size)
    return urdf([inertial(body.mass, body.inertia), geometry('box', size=size)], link=link)


# The cases of ``bad_bodies``, for a test's parametrization.
BAD_BODY_NAMES = ('malformed XML', 'missing link', 'several links, none named',
                  'missing mesh file', 'mesh not closed', 'non-physical inertia', 'zero mass',
                  'unresolvable package://', 'huge mesh', 'no inertial and no density',
                  'empty collision geometry', 'empty visual geometry', 'mesh without filename',
                  'closed flat mesh', 'scale 0 0 0', 'scale 1 1 0', 'four coplanar points',
                  'nan scale', 'scale of two values', 'box of two values', 'oversized URDF',
                  'unexpanded xacro', 'FIFO as mesh', '/dev/zero as mesh',
                  '<inertia/> without moments', 'rgba of two values')
# Those the executable is started with (each start takes seconds): the first ones, and those whose
# failure once came with a traceback or numpy's warnings.
STARTED_BAD_BODY_NAMES = BAD_BODY_NAMES[:10] + (
    'empty collision geometry', 'empty visual geometry', 'mesh without filename',
    'closed flat mesh', 'nan scale')


def bad_bodies(folder: Path) -> Dict[str, Tuple[str, str, str]]:
    """
    Return the bad inputs a URDF body is refused for, each as (URDF, body_link, words said).

    The meshes they name are written into ``folder``: a cube with a face missing, a 100 MB
    file (sparse: it takes no room on the disk), a closed triangle (both sides), a closed
    surface of four points in a plane, a cube, and a FIFO.
    """
    folder = Path(folder)
    write(open_box((0.1, 0.1, 0.1)), folder / 'open.stl')
    with open(folder / 'huge.stl', 'wb') as huge:
        huge.truncate(100 * 10 ** 6)
    write(trimesh.Trimesh([(0.0, 0.0, 0.0), (0.1, 0.0, 0.0), (0.0, 0.1, 0.0)],
                          [(0, 1, 2), (0, 2, 1)], process=False), folder / 'flat.stl')
    # A tetrahedron's four faces with its apex pressed into its base's plane.
    write(trimesh.Trimesh([(0.0, 0.0, 0.0), (0.1, 0.0, 0.0), (0.0, 0.1, 0.0), (0.03, 0.03, 0.0)],
                          [(0, 2, 1), (0, 1, 3), (1, 2, 3), (0, 3, 2)], process=False),
          folder / 'coplanar.stl')
    write(cube(0.1), folder / 'cube.stl')
    fifo = folder / 'fifo.stl'
    if not fifo.exists():
        os.mkfifo(fifo)
    cube_mesh = str(folder / 'cube.stl')
    weight = inertial(1.0, (0.01, 0.0, 0.0, 0.01, 0.0, 0.01))
    cube_piece = geometry('box', size=(0.1, 0.1, 0.1))

    def mesh(filename: str) -> str:
        return urdf([weight, geometry('mesh', filename=filename)])

    def shaped(filename: str, attributes: str) -> str:
        return urdf([weight, f'<collision><geometry><mesh filename="{filename}" {attributes}/>'
                             '</geometry></collision>'])
    cases = {
        'malformed XML': ('<robot name="r"><link name="a">', '',
                          'robot_description is not well-formed XML'),
        'missing link': (urdf([weight, cube_piece], extra_links=['base']), 'gripper',
                         "body_link 'gripper' is not a link of robot_description; its links: "
                         'body, base'),
        'several links, none named': (
            urdf([weight, cube_piece], extra_links=['base']), '',
            'set body_link to the one to simulate'),
        'missing mesh file': (mesh(str(folder / 'absent.stl')), '', 'no such file'),
        'mesh not closed': (mesh(str(folder / 'open.stl')), '', 'is not a closed surface'),
        'non-physical inertia': (urdf([inertial(1.0, (1.0, 0.0, 0.0, 1.0, 0.0, 3.0)),
                                       cube_piece]), '', 'inertia is not physically realizable'),
        'zero mass': (urdf([inertial(0.0, (0.01, 0.0, 0.0, 0.01, 0.0, 0.01)), cube_piece]), '',
                      'mass must be finite and > 0, got 0.0'),
        'unresolvable package://': (mesh('package://no_such_package/meshes/a.stl'), '',
                                    "source the workspace that installs 'no_such_package'"),
        'huge mesh': (mesh(str(folder / 'huge.stl')), '',
                      'is 95.4 MiB, over the limit of 16 MiB'),
        'no inertial and no density': (urdf([cube_piece]), '', 'or set density (kg/m^3)'),
        'empty collision geometry': (
            '<robot name="r"><link name="b"><collision><geometry/></collision></link></robot>',
            '', "link 'b' <collision> needs one <geometry> holding one box, sphere, cylinder or "
            'mesh'),
        'empty visual geometry': (urdf([weight, cube_piece, '<visual><geometry/></visual>']), '',
                                  "link 'body' <visual> needs one <geometry> holding one box"),
        'mesh without filename': (urdf([weight, '<collision><geometry><mesh/></geometry>'
                                                '</collision>']), '',
                                  "link 'body' <collision> <geometry> <mesh> has no filename"),
        'closed flat mesh': (mesh(str(folder / 'flat.stl')), '',
                             "link 'body' <collision>: mesh '" + str(folder / 'flat.stl')
                             + "' has no volume: its points lie in a plane"),
        'scale 0 0 0': (shaped(cube_mesh, 'scale="0 0 0"'), '',
                        'at scale 0 0 0 has no volume: its points lie at one point'),
        'scale 1 1 0': (shaped(cube_mesh, 'scale="1 1 0"'), '',
                        'at scale 1 1 0 has no volume: its points lie in a plane'),
        'four coplanar points': (mesh(str(folder / 'coplanar.stl')), '',
                                 "coplanar.stl' has no volume: its points lie in a plane"),
        'nan scale': (shaped(cube_mesh, 'scale="nan 1 1"'), '',
                      '<mesh> scale="nan 1 1" is not finite'),
        'scale of two values': (shaped(cube_mesh, 'scale="1 2"'), '',
                                '<mesh> scale="1 2" has 2 values: give x y z factors'),
        'box of two values': (urdf([weight, '<collision><geometry><box size="1 2"/></geometry>'
                                            '</collision>']), '',
                              "link 'body' <collision> <geometry> <box> size=\"1 2\" has 2 "
                              'values: give three edge lengths'),
        'oversized URDF': (urdf([weight, cube_piece, '<!--' + 'x' * 5 * 2 ** 20 + '-->']), '',
                           'robot_description is 5.0 MiB, over the limit of 4 MiB'),
        'unexpanded xacro': (urdf([weight, '<collision><geometry><box size="${s} 1 1"/>'
                                           '</geometry></collision>']), '',
                             'size="${s} 1 1" is xacro: robot_description is read as plain '
                             'URDF; expand it with xacro first'),
        'FIFO as mesh': (mesh(str(fifo)), '', 'is not a regular file (a FIFO, a device'),
        '/dev/zero as mesh': (mesh('/dev/zero'), '', "'/dev/zero' is not a regular file"),
        '<inertia/> without moments': (
            urdf(['<inertial><mass value="1"/><inertia/></inertial>', cube_piece]), '',
            "link 'body' <inertial> <inertia> lacks ixx, ixy, ixz, iyy, iyz, izz"),
        'rgba of two values': (
            urdf([weight, cube_piece, '<visual><geometry><box size="0.1 0.1 0.1"/></geometry>'
                                      '<material name="m"><color rgba="1 0"/></material>'
                                      '</visual>']), '',
            "link 'body' <visual> <material> <color> rgba=\"1 0\" has 2 values"),
    }
    assert tuple(cases) == BAD_BODY_NAMES
    return cases


if __name__ == '__main__':
    write(mug(), Path(sys.argv[1]))
