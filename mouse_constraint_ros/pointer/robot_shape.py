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
A whole robot as the node has it, for a client: its links' pieces and poses, a ray on them.

``RobotShape`` keeps the robot of the node's parameters (``robot_description`` of several links
and no ``body_link``, as ``node.robot_parameters.is_robot`` says; ``base``, ``base_pose`` and
``tracked_link``): the model the node loads (``description.robot_description.load_robot``) and
every link's collision and visual pieces in its link frame (``description.robot_links``). It is
loaded again only when one of those parameters changes. Pinocchio and the URDF libraries load
with the first robot: a client of a box or of one link never imports them. A description this
process cannot read (a collision mesh this machine does not have) leaves no robot, and
``error`` says why; a visual mesh it cannot read leaves the robot drawn by its collision
pieces, and ``error`` says so.

``link_poses`` places every link from the joint positions the node publishes (``joint_states``)
by the model's forward kinematics (``RobotModel.link_poses``); a floating base, which
``joint_states`` does not carry, is placed so that the tracked link is at the pose the node
publishes. ``ray_robot_hit`` is a click's ray on every link's collision pieces: the nearest hit
and its link. ``nearest_link`` is where the node lands a grab: the link whose collision pieces
lie nearest the point (``RobotBody.land``).
"""

import math
from typing import Dict, Optional, Sequence, Tuple

from .body_shape import ray_body_hit
from .geometry import local_point, Pose, unit_pose
from .node_readouts import ViewParameters
from ..description.body_geometry import BodyGeometry
from ..node.robot_parameters import is_robot
from ..physics.algebra import Vector3

# The node's parameters that make the robot.
ROBOT_SHAPE_PARAMETERS = ('robot_description', 'body_link', 'base', 'base_pose', 'tracked_link')


class RobotShape:
    """The robot of the node's parameters as last known (none at first)."""

    def __init__(self) -> None:
        """Start with no robot."""
        self._key: Optional[Tuple] = None
        self._data = None
        self.robot = None  # description.robot_description.Robot
        self.links = None  # description.robot_links.RobotLinks, with the visuals
        self.tracked_link = ''
        self.error: Optional[str] = None
        # The links that have collision pieces, each as a BodyGeometry: what a click meets.
        self.geometries: Dict[str, BodyGeometry] = {}

    def update(self, parameters: ViewParameters) -> bool:
        """
        Take the robot of ``parameters``; return whether it changed.

        :param parameters: the node's parameters as known (``ROBOT_SHAPE_PARAMETERS`` of them).
        """
        key = tuple(getattr(parameters, name) for name in ROBOT_SHAPE_PARAMETERS)
        if key == self._key:
            return False
        self._key = key
        self.robot = self.links = self._data = None
        self.geometries, self.tracked_link, self.error = {}, '', None
        if not is_robot(parameters._asdict()):
            return True
        try:
            self._load(parameters)
        except ValueError as error:
            self.robot = self.links = None
            self.geometries = {}
            self.error = f'the robot is not drawn: {error}'
        return True

    def _load(self, parameters: ViewParameters) -> None:
        from ..description.robot_description import load_robot
        from ..description.robot_links import robot_links
        pose = parameters.base_pose
        base = unit_pose(Pose(pose[:3], pose[3:]))
        if base is None:
            raise ValueError(f'base_pose {pose} holds no pose')
        text = parameters.robot_description
        robot = load_robot(text, base=parameters.base, base_position=base.position,
                           base_orientation=base.orientation)
        try:
            links = robot_links(text, visuals=True)
        except ValueError as error:  # a visual mesh this machine does not have
            links = robot_links(text)
            self.error = f'the robot is drawn by its collision pieces: {error}'
        tracked = parameters.tracked_link or robot.structure.tool
        if tracked not in robot.model.link_frames:
            raise ValueError(f'tracked_link {tracked!r} is not a link of the robot')
        self.robot, self.links, self.tracked_link = robot, links, tracked
        self.geometries = {link: BodyGeometry(link, (0.0, 0.0, 0.0), pieces)
                           for link, pieces in links.pieces.items() if pieces}
        self._data = robot.model.model.createData()

    @property
    def joint_names(self) -> Tuple[str, ...]:
        """Return the moving joints' names, in ``joint_states`` order (none without a robot)."""
        return () if self.robot is None else tuple(j.name for j in self.robot.model.joints)

    def link_poses(self, names: Sequence[str], positions: Sequence[float], *,
                   tracked: Optional[Pose] = None) -> Optional[Dict[str, Pose]]:
        """
        Return every link's pose for the joint positions of a ``joint_states``, or None.

        :param names: the joints' names, as the message lists them.
        :param positions: their positions (rad or m).
        :param tracked: the tracked link's pose the node published: where a floating base is
            placed from (None: at the origin).
        :returns: each link's name to its pose (world frame); None without a robot, or when a
            joint of the robot is missing or not finite.
        """
        if self.robot is None:
            return None
        model = self.robot.model
        given = dict(zip(names, positions))
        try:
            ordered = [float(given[joint.name]) for joint in model.joints]
        except (KeyError, TypeError, ValueError):
            return None
        if not all(math.isfinite(p) for p in ordered):
            return None
        q = model.configuration(ordered)
        if tracked is not None:
            q = model.with_link_at(q, self.tracked_link, tracked.position, tracked.orientation,
                                   self._data)
        return {name: Pose(position, orientation)
                for name, (position, orientation) in model.link_poses(q, self._data).items()}


def ray_robot_hit(origin: Sequence[float], direction: Sequence[float], *,
                  poses: Dict[str, Pose],
                  geometries: Dict[str, BodyGeometry]) -> Optional[Tuple[str, Vector3]]:
    """
    Return the link a ray first meets and where (world), or None when it meets none.

    :param origin: the ray's origin, world frame (m).
    :param direction: its direction (any non-zero length).
    :param poses: each link's pose (``RobotShape.link_poses``).
    :param geometries: the links' collision pieces in their frames (``RobotShape.geometries``).
    """
    best: Optional[Tuple[float, str, Vector3]] = None
    for link, geometry in geometries.items():
        pose = poses.get(link)
        hit = None if pose is None else ray_body_hit(origin, direction, pose=pose,
                                                     geometry=geometry)
        if hit is None:
            continue
        distance = math.dist(hit, tuple(float(c) for c in origin))
        if best is None or distance < best[0]:
            best = (distance, link, hit)
    return None if best is None else best[1:]


def nearest_link(point: Sequence[float], *, poses: Dict[str, Pose],
                 geometries: Dict[str, BodyGeometry]) -> Tuple[str, float]:
    """
    Return the link whose collision pieces lie nearest a world point, and how far (m).

    As the node lands a grab: the first link of the nearest in ``poses``' order on a tie;
    ('', inf) without any.
    """
    best = ('', math.inf)
    for link, pose in poses.items():
        geometry = geometries.get(link)
        if geometry is None:
            continue
        distance = geometry.distance(local_point(point, pose))
        if distance < best[1]:
            best = (link, distance)
    return best
