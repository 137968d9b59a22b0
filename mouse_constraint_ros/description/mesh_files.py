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
Mesh files named by a URDF: where they are (``package://``, ``file://``, absolute) and their load.

A ``package://name/path`` is looked up with ``ament_index_python`` (the share directory of
``name`` on ``AMENT_PREFIX_PATH``), as robot_state_publisher's users expect. Relative paths have
no base (``robot_description`` is text, not a file): the node makes them absolute when it is
given the file (``relative_meshes``), and refuses them otherwise, saying the forms that work.
trimesh reads the file, bounded: at most ``MAX_MESH_BYTES`` on disk and ``MAX_MESH_FACES``
triangles, so a stray 100 MB scan cannot stall the node; a link's files together at most
``MAX_LINK_MESH_BYTES`` (checked before any is read) and its references ``MAX_LINK_FACES``
triangles (checked after each file is read once, before any is scaled or hulled).

This package finds its own ``package://`` files where the index does not list it
(``own_share``).
"""

import os
import stat
from typing import Callable, Dict, List, Optional, Tuple
from urllib.parse import unquote, urlparse

import numpy as np
import trimesh

from .own_share import own_share, PACKAGE

# The largest mesh file read (bytes) and the most triangles kept: a collision mesh is a
# simplified surface; a scan of millions of triangles is decimated first (e.g. in MeshLab).
MAX_MESH_BYTES = 16 * 1024 * 1024
MAX_MESH_FACES = 200000
# The bytes of the distinct mesh files of one link, and the triangles of all its mesh
# references (a file named twice counts twice): the load's work is bounded before it is done.
MAX_LINK_MESH_BYTES = 64 * 1024 * 1024
MAX_LINK_FACES = 400000

# Finds a ROS package's share directory by name, or raises LookupError.
PackageFinder = Callable[[str], str]


def ament_share(package: str) -> str:
    """
    Return the share directory of ``package`` from the ament index, or raise LookupError.

    This package finds its own where the index does not list it (``own_share``).
    """
    try:
        return _indexed_share(package)
    except LookupError:
        share = own_share() if package == PACKAGE else None
        if share is None:
            raise
        return share


def _indexed_share(package: str) -> str:
    try:
        from ament_index_python.packages import (get_package_share_directory,
                                                 PackageNotFoundError)
    except ImportError as error:  # pragma: no cover - ament_index_python is pinned
        raise LookupError(f'ament_index_python is not importable ({error})') from None
    try:
        return get_package_share_directory(package)
    except PackageNotFoundError:
        raise LookupError(f'package {package!r} is not on AMENT_PREFIX_PATH') from None
    except OSError:
        raise LookupError('AMENT_PREFIX_PATH is not set (no ROS workspace is sourced)') from None


def mesh_path(uri: str, *, find_package: PackageFinder = ament_share) -> str:
    """
    Return the file path of a URDF mesh ``filename``; raise ValueError saying how to fix it.

    The path must name a regular file (not a FIFO, a device, a directory) of at most
    ``MAX_MESH_BYTES``: both are checked without reading it.

    :param uri: ``package://name/path``, ``file:///abs/path`` or an absolute path.
    :param find_package: the share directory of a package name (the ament index's).
    """
    parsed = urlparse(uri)
    if parsed.scheme == 'package':
        try:
            share = find_package(parsed.netloc)
        except LookupError as error:
            raise ValueError(
                f'mesh {uri!r} cannot be resolved: {error}; source the workspace that '
                f'installs {parsed.netloc!r} (its share/ holds the mesh) or name the file as '
                'file:///absolute/path') from None
        path = os.path.join(share, unquote(parsed.path).lstrip('/'))
    elif parsed.scheme == 'file':
        path = unquote(parsed.path)
    elif not parsed.scheme and os.path.isabs(uri):
        path = uri
    else:
        raise ValueError(
            f'mesh {uri!r} is neither package://, file:// nor an absolute path: '
            'robot_description is text with no directory of its own to resolve it against; '
            'give the node its file (robot_description_file, urdf:=, make run URDF=)')
    try:
        status = os.stat(path)
    except (OSError, ValueError):
        raise ValueError(f'mesh {uri!r}: no such file {path!r}') from None
    if not stat.S_ISREG(status.st_mode):
        kind = 'a directory' if stat.S_ISDIR(status.st_mode) else (
            'not a regular file (a FIFO, a device or a socket)')
        raise ValueError(f'mesh {uri!r}: {path!r} is {kind}: name a mesh file (STL, OBJ, PLY)')
    if status.st_size > MAX_MESH_BYTES:
        raise ValueError(
            f'mesh {uri!r} is {status.st_size / 2 ** 20:.1f} MiB, over the limit of '
            f'{MAX_MESH_BYTES / 2 ** 20:g} MiB a mesh file may have: simplify it (a collision '
            'mesh needs a few thousand triangles)')
    return path


def read_mesh(uri: str, path: str) -> trimesh.Trimesh:
    """
    Return the triangle mesh of the file ``path`` (``mesh_path``'s), unscaled; raise ValueError.

    :param uri: the URDF's ``filename``, to name it.
    :param path: its file.
    """
    try:
        mesh = trimesh.load(path, force='mesh')
    except Exception as error:  # trimesh raises many kinds on a file it cannot read
        raise ValueError(f'mesh {uri!r} cannot be read: {_one_line(error)}') from None
    if not isinstance(mesh, trimesh.Trimesh) or not len(mesh.faces):
        raise ValueError(f'mesh {uri!r} holds no triangles')
    if len(mesh.faces) > MAX_MESH_FACES:
        raise ValueError(f'mesh {uri!r} has {len(mesh.faces)} triangles, more than '
                         f'{MAX_MESH_FACES}: simplify it')
    if not np.isfinite(mesh.vertices).all():
        raise ValueError(f'mesh {uri!r} has non-finite vertices')
    return mesh


class MeshFiles:
    """
    The mesh files of one link, each read once, within the link's bounds before any is read.

    ``add`` resolves a reference and checks its file (``mesh_path``); ``read`` checks the
    distinct files' bytes together (``MAX_LINK_MESH_BYTES``), reads each once, and checks the
    triangles of every reference together (``MAX_LINK_FACES``: a file named 50 times counts 50
    times), before any is scaled, checked for closure or hulled.

    :param find_package: see ``mesh_path``.
    """

    def __init__(self, find_package: PackageFinder = ament_share) -> None:
        """Start with no reference."""
        self._find_package = find_package
        self._references: List[Tuple[str, str]] = []
        self._paths: Dict[str, str] = {}
        self._meshes: Dict[str, trimesh.Trimesh] = {}
        self._closed: Dict[str, bool] = {}

    def add(self, uri: str) -> None:
        """Take the reference ``uri``; raise ValueError on a file that cannot be one."""
        path = self._paths.get(uri) or mesh_path(uri, find_package=self._find_package)
        self._paths[uri] = path
        self._references.append((uri, path))

    def read(self) -> None:
        """Read every file once; raise ValueError when the link's meshes are over the bounds."""
        paths = {path: uri for uri, path in self._references}
        total = sum(os.path.getsize(path) for path in paths)
        if total > MAX_LINK_MESH_BYTES:
            raise ValueError(
                f'its {len(paths)} mesh files are {total / 2 ** 20:.1f} MiB together, over the '
                f'limit of {MAX_LINK_MESH_BYTES / 2 ** 20:g} MiB: simplify them')
        for path, uri in paths.items():
            self._meshes[path] = read_mesh(uri, path)
        faces = sum(len(self._meshes[path].faces) for _, path in self._references)
        if faces > MAX_LINK_FACES:
            raise ValueError(
                f'its {len(self._references)} mesh references have {faces} triangles together, '
                f'more than {MAX_LINK_FACES} (a file counts once for each reference): simplify '
                'the meshes or name fewer')

    def mesh(self, uri: str, *, scale=None, closed: bool = True) -> trimesh.Trimesh:
        """
        Return the mesh of the read reference ``uri``, scaled (a copy); raise ValueError.

        :param scale: the URDF's ``scale`` (x, y, z, or one factor), or None.
        :param closed: refuse a mesh that is not a closed surface (a collision mesh bounds a
            volume: the grab asks what lies inside, the inertia integrates over it).
        """
        path = self._paths[uri]
        mesh = self._meshes[path]
        if closed:
            if path not in self._closed:
                self._closed[path] = bool(mesh.is_watertight)
            if not self._closed[path]:
                raise ValueError(
                    f'mesh {uri!r} is not a closed surface (it has boundary or non-manifold '
                    'edges): a collision mesh must bound a volume; close it or use its convex '
                    'hull')
        mesh = mesh.copy()
        if scale is not None:
            mesh.apply_scale(np.broadcast_to(np.asarray(scale, dtype=float), 3))
        return mesh


def _one_line(error: Optional[BaseException]) -> str:
    return ' '.join(str(error).split()) or type(error).__name__
