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
The body as RViz draws it: one marker per piece of its link, or the box (no rclpy here).

``drawn_pieces`` says what RViz draws of each piece of a ``BodyGeometry``, placed in the link
frame: its visual pieces, or its collision pieces where the link has no ``<visual>``.

==========  ==============  =====================================================================
piece       marker type     drawn
==========  ==============  =====================================================================
box         CUBE            its edges, at its origin
sphere      SPHERE          its diameter on every axis, at its origin
cylinder    CYLINDER        diameter, diameter, length (RViz's cylinder is along z, as URDF's)
mesh        MESH_RESOURCE   the file RViz loads itself, at the URDF's ``scale``: a ``package://``
                            or ``file://`` URI as the URDF names it, an absolute path as its
                            ``file://`` URI
mesh        TRIANGLE_LIST   a mesh named any other way: its triangles, scaled
==========  ==============  =====================================================================

Each keeps its ``<material>`` colour, or takes the body's. ``placed`` puts the pieces at the
link's pose in the world: a piece's pose is the link pose composed with its origin (x + R t,
q_link q_piece). ``piece_marker`` turns one into a ``visualization_msgs/Marker``: the node's
``body`` namespace numbers them 0, 1, ..., and ``mouse_marker`` hangs them, in the link frame,
on its interactive marker. The box body (``BodyGeometry.box``) is one CUBE of ``box_size`` at
the body's pose.
"""

import os
from pathlib import Path
from typing import List, NamedTuple, Sequence, Tuple
from urllib.parse import urlparse

from geometry_msgs.msg import Point
import numpy as np
from std_msgs.msg import ColorRGBA
from visualization_msgs.msg import Marker

from ..description import BodyGeometry
from ..description.body_geometry import Piece
from ..physics import BodyState
from ..physics.algebra import Quaternion, Vector3
from ..wire.messages import fill_point, set_stamp

RGBA = Tuple[float, float, float, float]
IDENTITY = (0.0, 0.0, 0.0, 1.0)


class DrawnPiece(NamedTuple):
    """
    What RViz draws of one piece: a marker type, its pose, scale and colour.

    :param kind: the ``visualization_msgs/Marker`` type.
    :param position: the piece's origin (m), in the frame it is placed in.
    :param orientation: its orientation (x, y, z, w) there.
    :param scale: the marker's scale (see the module's table).
    :param color: RGBA in [0, 1].
    :param mesh_resource: the URI RViz loads (MESH_RESOURCE), else ''.
    :param triangles: the vertices of the triangles, three a triangle, in the piece's frame
        (TRIANGLE_LIST), else none.
    """

    kind: int
    position: Vector3
    orientation: Quaternion
    scale: Vector3
    color: RGBA
    mesh_resource: str = ''
    triangles: Tuple[Vector3, ...] = ()


def mesh_resource(uri: str) -> str:
    """
    Return the URI RViz loads a mesh from, or '' when it names the file no way RViz resolves.

    :param uri: the URDF's mesh ``filename``: ``package://`` and ``file://`` are kept, an
        absolute path becomes its ``file://`` URI (percent-encoded where it must be).
    """
    scheme = urlparse(uri).scheme
    if scheme in ('package', 'file'):
        return uri
    if not scheme and os.path.isabs(uri):
        return Path(uri).as_uri()
    return ''


def transform_pose(transform: np.ndarray) -> Tuple[Vector3, Quaternion]:
    """Return the position and the unit quaternion (x, y, z, w) of a 4 x 4 rigid transform."""
    position = tuple(float(c) for c in transform[:3, 3])
    rotation = transform[:3, :3]
    if not (rotation - np.eye(3)).any():
        return position, IDENTITY
    from scipy.spatial.transform import Rotation  # a turned piece's: the box has none
    return position, tuple(float(c) for c in Rotation.from_matrix(rotation).as_quat())


def _drawn(piece: Piece, color: RGBA) -> DrawnPiece:
    position, orientation = transform_pose(piece.transform)
    rgba = tuple(float(c) for c in (color if piece.color is None else piece.color))
    if piece.kind == 'box':
        return DrawnPiece(Marker.CUBE, position, orientation, tuple(piece.size), rgba)
    if piece.kind == 'sphere':
        diameter = 2.0 * piece.size[0]
        return DrawnPiece(Marker.SPHERE, position, orientation, (diameter,) * 3, rgba)
    if piece.kind == 'cylinder':
        radius, length = piece.size
        return DrawnPiece(Marker.CYLINDER, position, orientation,
                          (2.0 * radius, 2.0 * radius, length), rgba)
    resource = mesh_resource(piece.uri)
    if resource:
        return DrawnPiece(Marker.MESH_RESOURCE, position, orientation, tuple(piece.scale), rgba,
                          mesh_resource=resource)
    corners = piece.mesh.vertices[piece.mesh.faces].reshape(-1, 3)
    return DrawnPiece(Marker.TRIANGLE_LIST, position, orientation, (1.0, 1.0, 1.0), rgba,
                      triangles=tuple(tuple(float(c) for c in v) for v in corners))


def drawn_pieces(geometry: BodyGeometry, color: RGBA) -> Tuple[DrawnPiece, ...]:
    """
    Return what RViz draws of the link, in the link frame: its visuals, else its collisions.

    :param geometry: the body's shape.
    :param color: the colour of a piece without one of its own.
    """
    return tuple(_drawn(piece, color) for piece in geometry.visuals or geometry.collisions)


def compose(a: Quaternion, b: Quaternion) -> Quaternion:
    """Return the Hamilton product a b of two quaternions (x, y, z, w): b's turn, then a's."""
    ax, ay, az, aw = a
    bx, by, bz, bw = b
    return (aw * bx + ax * bw + ay * bz - az * by,
            aw * by - ax * bz + ay * bw + az * bx,
            aw * bz + ax * by - ay * bx + az * bw,
            aw * bw - ax * bx - ay * by - az * bz)


def placed(pieces: Sequence[DrawnPiece], pose: BodyState) -> Tuple[DrawnPiece, ...]:
    """
    Return the link-frame ``pieces`` placed by the link frame's ``pose`` in the world.

    A piece's position is x + R(q) t and its orientation q q_piece, of the link pose (x, q) and
    the piece's origin (t, q_piece): a piece at the link's origin is at the link's pose.
    """
    return tuple(piece._replace(position=pose.world_point(piece.position),
                                orientation=compose(pose.orientation, piece.orientation))
                 for piece in pieces)


def piece_marker(piece: DrawnPiece, *, frame_id: str = '', stamp_ns: int = 0,
                 namespace: str = '', marker_id: int = 0) -> Marker:
    """
    Return the marker of one drawn piece.

    :param frame_id: the frame of its pose; '' in an interactive marker's control (the pose is
        then relative to the interactive marker's).
    :param stamp_ns: the stamp (ns).
    :param namespace: the marker's namespace.
    :param marker_id: its id in the namespace.
    """
    marker = Marker(ns=namespace, id=marker_id, type=piece.kind, action=Marker.ADD)
    marker.header.frame_id = frame_id
    set_stamp(marker.header.stamp, stamp_ns)
    fill_point(marker.pose.position, piece.position)
    o = marker.pose.orientation
    o.x, o.y, o.z, o.w = piece.orientation
    fill_point(marker.scale, piece.scale)
    r, g, b, a = piece.color
    marker.color = ColorRGBA(r=r, g=g, b=b, a=a)
    marker.mesh_resource = piece.mesh_resource
    if piece.triangles:
        marker.points = [Point(x=x, y=y, z=z) for x, y, z in piece.triangles]
    return marker


def body_markers(pieces: Sequence[DrawnPiece], *, pose: BodyState, frame_id: str,
                 stamp_ns: int, namespace: str = 'body', previous: int = 0) -> List[Marker]:
    """
    Return the markers of the link-frame ``pieces`` at the link's ``pose``, ids 0, 1, ...

    :param previous: how many the namespace held before: the ids past ``pieces`` up to it are
        deleted (a new ``robot_description`` with fewer pieces leaves none behind in RViz).
    """
    markers = [piece_marker(piece, frame_id=frame_id, stamp_ns=stamp_ns, namespace=namespace,
                            marker_id=index)
               for index, piece in enumerate(placed(pieces, pose))]
    for index in range(len(pieces), previous):
        gone = Marker(ns=namespace, id=index, action=Marker.DELETE)
        gone.header.frame_id = frame_id
        set_stamp(gone.header.stamp, stamp_ns)
        markers.append(gone)
    return markers
