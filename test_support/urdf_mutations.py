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
Mutated URDF bodies for the description path's fuzz: what a hostile or careless client sends.

``mutations(folder, count, seed)`` takes three valid bodies (meshes with a visual colour and a
turned ``<inertial>``, primitives weighed by a density, a link among several) and changes each
in one to three ways, chosen by a seeded generator (the same table every run): an attribute
removed or set to a bad value (empty, nan, inf, negative, zero, too few or too many numbers,
xacro, words, a huge number), an element removed, emptied, doubled or renamed, a mesh file
swapped for one that is missing, a directory, a FIFO, a device, relative, in no package, not a
mesh, empty, open or flat, or the text cut short.
"""

import copy
import os
from pathlib import Path
import random
from typing import List, Tuple

from lxml import etree
import trimesh

from .meshes import cube, geometry, inertial, open_box, urdf, write

# Bad attribute values: each a way a number, a list of numbers or a name goes wrong.
BAD_VALUES = ('', ' ', 'nan', 'inf', '-inf', '-1', '0', '0 0 0', '1 1 0', '1 2', '1 2 3 4',
              '1e400', '1e300 1e300 1e300', '-1e-300', '${s}', '$(find x)', 'abc', '1,2,3',
              '0x10', '1 nan 1', 'NaN NaN NaN NaN', '-0.0 -0.0 -0.0', '\u00e9', '1 1 1 1 1 1')
# Tags an element may be renamed to.
TAGS = ('box', 'sphere', 'cylinder', 'mesh', 'geometry', 'origin', 'visual', 'collision',
        'inertial', 'inertia', 'mass', 'material', 'color', 'link', 'joint', 'robot', 'x')


def mesh_files(folder: Path) -> Tuple[str, ...]:
    """Write the good and bad mesh files the mutations name; return their paths."""
    folder = Path(folder)
    write(cube(0.1), folder / 'cube.stl')
    write(open_box((0.1, 0.1, 0.1)), folder / 'open.stl')
    write(trimesh.Trimesh([(0.0, 0.0, 0.0), (0.1, 0.0, 0.0), (0.0, 0.1, 0.0)],
                          [(0, 1, 2), (0, 2, 1)], process=False), folder / 'flat.stl')
    (folder / 'text.stl').write_text('solid nothing\nthis is not a mesh\n')
    (folder / 'empty.stl').write_bytes(b'')
    (folder / 'garbage.obj').write_bytes(bytes(range(256)) * 8)
    (folder / 'folder.stl').mkdir(exist_ok=True)
    if not (folder / 'fifo.stl').exists():
        os.mkfifo(folder / 'fifo.stl')
    bad = ('open.stl', 'flat.stl', 'text.stl', 'empty.stl', 'garbage.obj', 'folder.stl',
           'fifo.stl', 'absent.stl')
    return (str(folder / 'cube.stl'), *(str(folder / name) for name in bad), '/dev/zero',
            'cube.stl', 'package://no_such_package/cube.stl', 'file://' + str(folder / 'cube.stl'),
            'http://example.com/cube.stl', '')


def bases(cube_path: str) -> List[Tuple[str, str, float]]:
    """Return the valid bodies mutated, each as (URDF, body_link, density)."""
    meshes = urdf([
        inertial(1.0, (0.01, 0.001, 0.0, 0.02, 0.0, 0.025), xyz=(0.0, 0.0, 0.01),
                 rpy=(0.1, 0.2, 0.3)),
        geometry('mesh', filename=cube_path, scale=(1.0, 2.0, 1.0)),
        geometry('box', size=(0.1, 0.1, 0.1), xyz=(0.0, 0.0, 0.1)),
        geometry('mesh', filename=cube_path, element='visual').replace(
            '</visual>', '<material name="m"><color rgba="0.5 0.5 0.5 1"/></material></visual>'),
    ], link='tool')
    primitives = urdf([
        geometry('sphere', radius=0.05),
        geometry('cylinder', radius=0.02, length=0.2, xyz=(0.0, 0.0, 0.1), rpy=(1.5, 0.0, 0.0)),
        geometry('box', size=(0.05, 0.05, 0.05), element='visual'),
    ], link='ball')
    several = urdf([inertial(2.0, (0.02, 0.0, 0.0, 0.02, 0.0, 0.02)),
                    geometry('box', size=(0.2, 0.1, 0.1))], link='arm',
                   extra_links=['base', 'hand'])
    return [(meshes, 'tool', 0.0), (primitives, 'ball', 1000.0), (several, 'arm', 0.0)]


def mutations(folder: Path, count: int, seed: int = 0) -> List[Tuple[str, str, float]]:
    """Return ``count`` mutated bodies as (URDF, body_link, density), the same for a seed."""
    files = mesh_files(folder)
    rng = random.Random(seed)
    found = []
    for index in range(count):
        text, link, density = bases(files[0])[index % 3]
        root = etree.fromstring(text.encode())
        for _ in range(rng.randint(1, 3)):
            _mutate(root, rng, files)
        text = etree.tostring(root, encoding='unicode')
        if rng.random() < 0.05:
            text = text[:rng.randrange(len(text))]
        if rng.random() < 0.1:
            link = rng.choice(('', 'nowhere', 'base', link))
        found.append((text, link, density))
    return found


def _mutate(root: etree._Element, rng: random.Random, files: Tuple[str, ...]) -> None:
    """Change ``root`` in one way: an attribute, an element or a mesh file."""
    elements = [e for e in root.iter() if isinstance(e.tag, str)]
    element = rng.choice(elements)
    meshes = [e for e in elements if e.tag == 'mesh']
    kind = rng.randrange(8)
    if kind == 0 and meshes:
        rng.choice(meshes).set('filename', rng.choice(files))
    elif kind <= 2 and element.attrib:
        name = rng.choice(sorted(element.attrib))
        element.set(name, rng.choice(BAD_VALUES))
    elif kind == 3 and element.attrib:
        del element.attrib[rng.choice(sorted(element.attrib))]
    elif kind == 4 and element is not root:
        element.getparent().remove(element)
    elif kind == 5:
        for child in list(element):
            element.remove(child)
    elif kind == 6 and element is not root:
        element.addnext(copy.deepcopy(element))
    else:
        element.tag = rng.choice(TAGS)
