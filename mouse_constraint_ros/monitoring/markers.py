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
RViz markers of the body, its anchor, the target and the constraint line (no rclpy here).

``marker_array`` turns the core's data into one ``visualization_msgs/MarkerArray``:

============  =========  =========================================================================
namespace     type       what
============  =========  =========================================================================
body          CUBE       the body: a box of ``box_size`` at the COM pose; a URDF link's pieces
                         instead, one marker each at the link's pose (``body_markers``)
anchor        SPHERE     the anchor (dragged point) in the world
target        SPHERE     the target; deleted while the body is free
constraint    LINE_LIST  anchor to target, green (no force) - yellow - red (``reference_force``)
wrench        ARROW      the external force from the COM, one longest box edge per body weight
                         (``wrench_reference``); deleted while no force is applied
felt          ARROW      the force the pointer feels (the ``force`` topic's), from the anchor, at
                         the wrench arrow's scale; deleted while it is zero
floor         CUBE       the floor: a thin square ``FLOOR_SPAN`` longest box edges wide, its top
                         at ``floor_height``, under the COM (so it is under the body wherever it
                         slides); deleted without a floor
contacts      SPHERE_LIST the body's points touching the floor (a box's corners, a hull's
                         vertices); deleted while there are none
============  =========  =========================================================================

The spheres' diameter is ``SPHERE_FRACTION`` of the box's longest edge, the line's width a third
of that, so the markers scale with the body; for a URDF link the box is the one about its
collision pieces (``BodyGeometry.extents``).
"""

import math
from typing import Optional, Sequence, Tuple

from geometry_msgs.msg import Point
from std_msgs.msg import ColorRGBA
from visualization_msgs.msg import Marker, MarkerArray

from .body_markers import body_markers, DrawnPiece
from ..physics import BodyState, Floor, Settings, STANDARD_GRAVITY
from ..physics.algebra import Vector3
from ..physics.settings import force_bound
from ..wire.messages import fill_point, fill_pose, set_stamp

# Sphere diameter as a fraction of the box's longest edge; the line is a third as wide.
SPHERE_FRACTION = 0.1
LINE_FRACTION = SPHERE_FRACTION / 3.0
# Without a force bound the line is red at this many times the body's weight (m g0): yellow when
# the constraint carries the weight of a body at rest.
WEIGHTS_FOR_RED = 2.0

BODY_COLOR = (0.35, 0.55, 0.85, 0.8)
ANCHOR_COLOR = (1.0, 0.55, 0.0, 1.0)
TARGET_COLOR = (0.85, 0.1, 0.85, 1.0)
WRENCH_COLOR = (0.1, 0.8, 0.9, 1.0)
FELT_COLOR = (0.95, 0.85, 0.1, 1.0)
FLOOR_COLOR = (0.5, 0.5, 0.5, 0.6)
CONTACT_COLOR = (0.95, 0.2, 0.2, 1.0)
# The floor's width and thickness in longest box edges.
FLOOR_SPAN = 20.0
FLOOR_THICKNESS = 0.02


def reference_force(settings: Settings) -> float:
    """
    Return the force (N) at which the constraint line turns red: the joint's force bound.

    The bound is the one the joint enforces (``force_bound``): the smaller of ``max_force``
    and ``max_force_per_weight`` m |g|. Without either, ``WEIGHTS_FOR_RED`` times the body's
    weight under standard gravity.

    :param settings: the simulation's settings.
    """
    bound = force_bound(settings)
    if math.isfinite(bound) and bound > 0.0:
        return bound
    return WEIGHTS_FOR_RED * settings.body.mass * abs(STANDARD_GRAVITY[2])


def wrench_reference(settings: Settings) -> float:
    """Return the force (N) the wrench arrow shows one longest box edge long: the weight m g0."""
    return settings.body.mass * abs(STANDARD_GRAVITY[2])


def _wrench_arrow(frame_id: str, stamp_ns: int, origin: Vector3, force: Vector3,
                  length_per_newton: float, width: float, namespace: str = 'wrench',
                  rgba: Sequence[float] = WRENCH_COLOR) -> Marker:
    magnitude = math.hypot(*force)
    if not magnitude > 0.0:
        marker = _deleted(namespace, frame_id, stamp_ns)
        marker.type = Marker.ARROW
        return marker
    arrow = _marker(namespace, Marker.ARROW, frame_id, stamp_ns)
    start, end = Point(), Point()
    fill_point(start, origin)
    fill_point(end, tuple(o + length_per_newton * f for o, f in zip(origin, force)))
    arrow.points = [start, end]
    # ARROW with points: x is the shaft diameter, y the head diameter, z the head length.
    arrow.scale.x, arrow.scale.y, arrow.scale.z = width, 2.0 * width, 3.0 * width
    arrow.color = _color(rgba)
    return arrow


def force_color(force: float, reference: float) -> Tuple[float, float, float, float]:
    """
    Return the RGBA colour of a force: green at 0, yellow at half ``reference``, red from it on.

    :param force: the constraint force's magnitude (N).
    :param reference: the force (N, > 0) that is shown fully red.
    """
    share = force / reference if reference > 0.0 else 1.0
    share = min(1.0, max(0.0, share)) if math.isfinite(share) else 1.0
    return (min(1.0, 2.0 * share), min(1.0, 2.0 * (1.0 - share)), 0.0, 1.0)


def _color(rgba: Sequence[float]) -> ColorRGBA:
    r, g, b, a = rgba
    return ColorRGBA(r=r, g=g, b=b, a=a)


def _marker(namespace: str, kind: int, frame_id: str, stamp_ns: int) -> Marker:
    marker = Marker(ns=namespace, id=0, type=kind, action=Marker.ADD)
    marker.header.frame_id = frame_id
    set_stamp(marker.header.stamp, stamp_ns)
    marker.pose.orientation.w = 1.0
    return marker


def _sphere(namespace: str, *, frame_id: str, stamp_ns: int, center: Vector3, diameter: float,
            rgba: Sequence[float]) -> Marker:
    marker = _marker(namespace, Marker.SPHERE, frame_id, stamp_ns)
    fill_point(marker.pose.position, center)
    marker.scale.x = marker.scale.y = marker.scale.z = diameter
    marker.color = _color(rgba)
    return marker


def _deleted(namespace: str, frame_id: str, stamp_ns: int) -> Marker:
    marker = _marker(namespace, Marker.SPHERE, frame_id, stamp_ns)
    marker.action = Marker.DELETE
    return marker


def marker_array(*, frame_id: str, stamp_ns: int, box_size: Vector3, state: BodyState,
                 anchor: Vector3, target: Optional[Vector3], force: Vector3,
                 reference: float, wrench_force: Optional[Vector3] = None,
                 wrench_reference: float = 1.0, floor: Optional[Floor] = None,
                 contacts: Sequence[Vector3] = (),
                 felt_force: Optional[Vector3] = None,
                 pieces: Optional[Sequence[DrawnPiece]] = None,
                 link_pose: Optional[BodyState] = None, previous_pieces: int = 0) -> MarkerArray:
    """
    Return the markers of one moment of the simulation.

    :param frame_id: the frame of everything (the node's ``frame_id``).
    :param stamp_ns: the stamp (ns), that of the tick the state belongs to.
    :param box_size: the body box's edge lengths (m); for a URDF link, the box about its
        collision pieces, which scales the other markers.
    :param state: the body's (COM's) state; its pose places the box.
    :param anchor: the anchor's world position (m).
    :param target: the target (m), or None for a free body (target and line are deleted).
    :param force: the constraint force (N) that colours the line.
    :param reference: the force (N) at which the line is red, see ``reference_force``.
    :param wrench_force: the external force applied at the COM (N); zero deletes its arrow,
        None leaves the wrench namespace out.
    :param wrench_reference: the force (N) whose arrow is the box's longest edge long, see
        ``wrench_reference``.
    :param floor: the simulation's floor (one not enabled deletes its marker); None leaves the
        floor and contacts namespaces out.
    :param contacts: the world points of the body touching the floor (m): a box's corners, a
        hull's vertices.
    :param felt_force: the force the pointer feels (N, ``messages.felt_force``), drawn from
        the anchor at the wrench arrow's scale; zero deletes its arrow, None leaves it out.
    :param pieces: a URDF link's pieces in the link frame (``body_markers.drawn_pieces``),
        drawn instead of the box at ``link_pose``, ids 0, 1, ... of the body namespace.
    :param link_pose: the link frame's pose; None: ``state``'s (a frame at the COM).
    :param previous_pieces: the body markers the previous array drew: the ids past
        ``pieces`` are deleted.
    """
    if pieces is None:
        body = _marker('body', Marker.CUBE, frame_id, stamp_ns)
        fill_pose(body, state)
        fill_point(body.scale, box_size)
        body.color = _color(BODY_COLOR)
        markers = [body]
    else:
        markers = body_markers(pieces, pose=state if link_pose is None else link_pose,
                               frame_id=frame_id, stamp_ns=stamp_ns, previous=previous_pieces)
    diameter = SPHERE_FRACTION * max(box_size)
    markers.append(_sphere('anchor', frame_id=frame_id, stamp_ns=stamp_ns, center=anchor,
                           diameter=diameter, rgba=ANCHOR_COLOR))
    if target is None:
        markers += [_deleted('target', frame_id, stamp_ns),
                    _deleted('constraint', frame_id, stamp_ns)]
    else:
        markers.append(_sphere('target', frame_id=frame_id, stamp_ns=stamp_ns, center=target,
                               diameter=diameter, rgba=TARGET_COLOR))
        line = _marker('constraint', Marker.LINE_LIST, frame_id, stamp_ns)
        start, end = Point(), Point()
        fill_point(start, anchor)
        fill_point(end, target)
        line.points = [start, end]
        line.scale.x = LINE_FRACTION * max(box_size)
        line.color = _color(force_color(math.hypot(*force), reference))
        markers.append(line)
    if floor is not None:
        markers += _floor_markers(frame_id, stamp_ns, floor, state.position, box_size, contacts)
    longest = max(box_size)
    if wrench_force is not None:
        markers.append(_wrench_arrow(frame_id, stamp_ns, state.position, wrench_force,
                                     longest / wrench_reference, LINE_FRACTION * longest))
    if felt_force is not None:
        markers.append(_wrench_arrow(frame_id, stamp_ns, anchor, felt_force,
                                     longest / wrench_reference, LINE_FRACTION * longest,
                                     'felt', FELT_COLOR))
    return MarkerArray(markers=markers)


def _floor_markers(frame_id: str, stamp_ns: int, floor: Floor, position: Vector3,
                   box_size: Vector3, contacts: Sequence[Vector3]) -> list:
    """Return the floor's plate under ``position`` and the contact points' spheres."""
    if not floor.enabled:
        plate = _deleted('floor', frame_id, stamp_ns)
        plate.type = Marker.CUBE
    else:
        longest = max(box_size)
        thickness = FLOOR_THICKNESS * longest
        plate = _marker('floor', Marker.CUBE, frame_id, stamp_ns)
        fill_point(plate.pose.position,
                   (position[0], position[1], floor.height - 0.5 * thickness))
        fill_point(plate.scale, (FLOOR_SPAN * longest, FLOOR_SPAN * longest, thickness))
        plate.color = _color(FLOOR_COLOR)
    if not contacts:
        spheres = _deleted('contacts', frame_id, stamp_ns)
        spheres.type = Marker.SPHERE_LIST
        return [plate, spheres]
    spheres = _marker('contacts', Marker.SPHERE_LIST, frame_id, stamp_ns)
    spheres.points = []
    for point in contacts:
        corner = Point()
        fill_point(corner, point)
        spheres.points.append(corner)
    spheres.scale.x = spheres.scale.y = spheres.scale.z = 0.5 * SPHERE_FRACTION * max(box_size)
    spheres.color = _color(CONTACT_COLOR)
    return [plate, spheres]
