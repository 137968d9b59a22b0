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
A description's work is bounded before it is done, and the hull keeps trimesh's vertices.

The link's mesh files are checked together before any is read (their bytes), read once each,
and their references counted together (their triangles) before any is scaled or hulled; the
hulls' vertices together are bounded as the floor's contact test needs. The hull (Qhull without
merging) gives the vertices trimesh's hull gives on the shapes bodies are made of, so a body's
contact points, and its physics, stay those of trimesh's hull.
"""

import numpy as np
import pytest
import trimesh

from mouse_constraint_ros.description import hull, urdf_link
from mouse_constraint_ros.description.hull import hull_vertices, HullError
from mouse_constraint_ros.description.mesh_files import (MAX_LINK_FACES, MAX_LINK_MESH_BYTES,
                                                         MAX_MESH_BYTES)
from mouse_constraint_ros.description.urdf_link import body_model
from test_support.meshes import cube, ellipsoid_hull, geometry, inertial, mug, urdf, write

WEIGHT = inertial(1.0, (0.01, 0.0, 0.0, 0.01, 0.0, 0.01))

SHAPES = {
    'mug': mug,
    'cube': lambda: cube(0.1),
    'subdivided box': lambda: trimesh.creation.box((0.1, 0.2, 0.3)).subdivide().subdivide(),
    'icosphere': lambda: trimesh.creation.icosphere(3, radius=0.05),
    'cylinder': lambda: trimesh.creation.cylinder(0.05, 0.1, sections=48),
    'fine cylinder': lambda: trimesh.creation.cylinder(0.05, 0.1, sections=2000),
    'ellipsoid hull': lambda: ellipsoid_hull(500, (0.1, 0.05, 0.03)),
    'torus': lambda: trimesh.creation.torus(0.1, 0.02),
    'capsule': lambda: trimesh.creation.capsule(0.1, 0.03),
    'annulus': lambda: trimesh.creation.annulus(0.02, 0.05, 0.1),
    'cone': lambda: trimesh.creation.cone(0.05, 0.1, sections=200),
}


@pytest.mark.parametrize('name', list(SHAPES))
def test_the_hull_has_the_vertices_of_trimeshs_hull_in_its_order(name):
    """The same floats in the same order: the contact points of the body do not change."""
    mesh = SHAPES[name]()
    np.testing.assert_array_equal(hull_vertices(mesh.vertices), mesh.convex_hull.vertices)


@pytest.mark.parametrize('points, words', [
    ([(0.1, 0.2, 0.3)] * 5, 'at one point'),
    ([(t, 2.0 * t, 0.0) for t in range(6)], 'on a line'),
    ([(0.0, 0.0, 0.0), (1.0, 0.0, 0.0), (0.0, 1.0, 0.0), (1.0, 1.0, 0.0)], 'in a plane'),
])
def test_points_without_volume_have_no_hull(points, words):
    """A point, a line, a plane: refused, saying which."""
    with pytest.raises(HullError, match=words):
        hull_vertices(np.array(points, dtype=float))


def _count_reads(monkeypatch) -> list:
    """Record each file trimesh reads; fail on any hull taken."""
    reads = []
    load = trimesh.load

    def counted(path, *args, **kwargs):
        reads.append(path)
        return load(path, *args, **kwargs)

    def no_hull(*_args, **_kwargs):
        raise AssertionError('a hull was taken')
    monkeypatch.setattr(trimesh, 'load', counted)
    monkeypatch.setattr(urdf_link, 'hull_vertices', no_hull)
    return reads


def test_many_references_to_one_mesh_are_refused_by_their_sum_before_a_hull(tmp_path,
                                                                            monkeypatch):
    """The file is read once; its triangles times its references pass the link's bound."""
    mesh = trimesh.creation.cylinder(0.05, 0.1, sections=5000)
    path = write(mesh, tmp_path / 'cylinder.stl')
    references = MAX_LINK_FACES // len(mesh.faces) + 1
    reads = _count_reads(monkeypatch)
    text = urdf([WEIGHT] + [geometry('mesh', filename=str(path))] * references)
    with pytest.raises(ValueError) as refused:
        body_model(text)
    assert str(refused.value) == (
        f"link 'body': its {references} mesh references have {references * len(mesh.faces)} "
        f'triangles together, more than {MAX_LINK_FACES} (a file counts once for each '
        'reference): simplify the meshes or name fewer')
    assert reads == [str(path)]


def test_mesh_files_over_the_links_bound_are_refused_unread(tmp_path, monkeypatch):
    """Files each within their bound but over the link's together: refused before any read."""
    count = MAX_LINK_MESH_BYTES // MAX_MESH_BYTES + 1
    names = []
    for k in range(count):
        with open(tmp_path / f'{k}.stl', 'wb') as file:  # sparse: no room on the disk
            file.truncate(MAX_MESH_BYTES)
        names.append(str(tmp_path / f'{k}.stl'))
    reads = _count_reads(monkeypatch)
    with pytest.raises(ValueError, match=f"link 'body': its {count} mesh files are "):
        body_model(urdf([WEIGHT] + [geometry('mesh', filename=n) for n in names]))
    assert reads == []


def test_hulls_over_the_contact_tests_bound_are_refused_naming_the_link(tmp_path,
                                                                        monkeypatch):
    """The hulls' vertices together are bounded (here made 10: two cubes have 16)."""
    path = write(cube(0.1), tmp_path / 'cube.stl')
    monkeypatch.setattr(urdf_link, 'MAX_VERTICES', 10)
    with pytest.raises(ValueError, match="link 'tool': the hulls of its collision meshes have "
                                         '16 vertices together, more than 10'):
        body_model(urdf([WEIGHT] + [geometry('mesh', filename=str(path))] * 2, link='tool'))


def _record_hull_inputs(monkeypatch) -> list:
    """Record how many points each Qhull call of ``hull`` is given (it imports it per call)."""
    import scipy.spatial
    sizes = []
    convex_hull = scipy.spatial.ConvexHull

    def recorded(points, *args, **kwargs):
        sizes.append(len(points))
        return convex_hull(points, *args, **kwargs)
    monkeypatch.setattr(scipy.spatial, 'ConvexHull', recorded)
    return sizes


def test_points_on_circles_past_the_bound_give_qhull_a_bounded_sample(monkeypatch):
    """40 000 points on two circles, all vertices: Qhull never sees more than the bound."""
    mesh = trimesh.creation.cylinder(0.05, 0.2, sections=20000)
    sizes = _record_hull_inputs(monkeypatch)
    vertices = hull_vertices(mesh.vertices)
    assert max(sizes) <= hull.MAX_HULL_INPUT < len(mesh.vertices)
    # Of the sample, only the two centres of the caps, if taken, are no vertices.
    assert hull.MAX_HULL_INPUT - 2 <= len(vertices) <= hull.MAX_HULL_INPUT
    assert {tuple(v) for v in vertices} <= {tuple(v) for v in mesh.vertices.tolist()}


def test_inner_points_past_the_bound_are_dropped_and_the_hull_is_exact(monkeypatch):
    """An ellipsoid's 3000 surface points among 30 000 inside it: trimesh's hull, to the bit."""
    surface = ellipsoid_hull(3000, (0.1, 0.05, 0.03)).vertices
    rng = np.random.default_rng(5)
    inside = rng.uniform(-1.0, 1.0, (60000, 3))
    inside = inside[(inside ** 2).sum(axis=1) < 0.8][:30000] * (0.1, 0.05, 0.03)
    points = np.vstack([inside[:15000], surface, inside[15000:]])
    sizes = _record_hull_inputs(monkeypatch)
    vertices = hull_vertices(points)
    assert max(sizes) <= hull.MAX_HULL_INPUT < len(points)
    np.testing.assert_array_equal(vertices, trimesh.convex.convex_hull(points).vertices)
