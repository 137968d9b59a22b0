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
The whole robot's parameters: a ``robot_description`` of several links and no ``body_link``.

``robot_from`` loads the robot (``description.robot_description``: the checked tree, then
Pinocchio's model) and its links' collision pieces once per description, base and base pose,
and says which link is tracked (``pose``, ``twist``, TF's body frame). Pinocchio and the URDF
libraries load with the first robot: the box and single-link routes never import them.
"""

import functools
import math
from typing import Any, Mapping, NamedTuple, Optional, Tuple

from ..physics.body import RigidBody
from ..physics.state import BodyState
from ..physics.validation import finite_vector, shown

# (name, default, description, bounds), as ``parameters.ParameterSpec`` takes them.
ROBOT_PARAMETERS: Tuple[tuple, ...] = (
    ('base', 'fixed',
     'A robot (robot_description of several links, no body_link): fixed (its root link at '
     'base_pose, an arm on a table) or floating (the whole robot free). A root link named world '
     'fixes it where its joint puts it.', None),
    ('base_pose', [0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 1.0],
     "A robot's root link pose in frame_id: x y z (m), then the quaternion x y z w; where a "
     'floating base starts.', None),
    ('initial_joint_positions', [0.0],
     "A robot's joint positions at start and after a reset (rad or m), in joint_states' order; "
     '[0.0]: every joint at zero (or its nearest limit).', None),
    ('tracked_link', '',
     "A robot's link whose frame pose, twist and TF's body frame are; empty: the last link of "
     "the URDF's longest chain (its tool).", None),
)


class RobotConfig(NamedTuple):
    """What the robot parameters make: the robot, its links' pieces, which link is tracked."""

    robot: Any  # description.robot_description.Robot
    links: Any  # description.robot_links.RobotLinks
    tracked_link: str
    base_state: BodyState
    joint_positions: Optional[Tuple[float, ...]] = None
    key: tuple = ()  # ``robot_key`` of the parameters it was made of


def is_robot(values: Mapping[str, Any]) -> bool:
    """Return whether the parameters ask for a whole robot: several links, no body_link."""
    text = values['robot_description']
    if not isinstance(text, str) or not text or values['body_link']:
        return False
    return text.count('<link') > 1


def robot_key(values: Mapping[str, Any]) -> tuple:
    """Return what names a robot in parameter ``values``: what a restart must change."""
    return (values['robot_description'], values['base'], tuple(values['base_pose']),
            values['tracked_link'])


def robot_from(values: Mapping[str, Any]) -> Optional[RobotConfig]:
    """Return the robot of parameter ``values``, or None for a single body; ValueError if bad."""
    base = values['base']
    if base not in ('fixed', 'floating'):
        raise ValueError(f'base must be fixed or floating, got {shown(base)}')
    pose = finite_vector('base_pose', values['base_pose'], 7)
    try:
        state = BodyState(pose[:3], pose[3:]).validated()
    except ValueError as error:
        raise ValueError(f'base_pose: {error}') from None
    positions = values['initial_joint_positions']
    try:
        positions = tuple(float(x) for x in positions)
    except (TypeError, ValueError):
        raise ValueError('initial_joint_positions must be numbers, got '
                         f'{shown(positions)}') from None
    if not all(map(math.isfinite, positions)):
        raise ValueError(f'initial_joint_positions must be finite, got {shown(positions)}')
    tracked = values['tracked_link']
    if not isinstance(tracked, str):
        raise ValueError(f'tracked_link must be a string, got {shown(tracked)}')
    if not is_robot(values):
        if positions != (0.0,):
            raise ValueError(f'initial_joint_positions {shown(list(positions))} is for a robot '
                             '(robot_description of several links, no body_link): the body '
                             'has no joints')
        if tracked:
            raise ValueError(f'tracked_link {tracked!r} is for a robot (robot_description of '
                             'several links, no body_link)')
        return None
    robot, links = _loaded(values['robot_description'], base, state.position, state.orientation)
    tracked = tracked or robot.structure.tool
    if tracked not in robot.model.link_frames:
        raise ValueError(f'tracked_link {tracked!r} is not a link of the robot; its links: '
                         + ', '.join(robot.structure.links))
    joints = robot.model.joints
    if positions == (0.0,) and len(joints) != 1:
        positions = None
    elif len(positions) != len(joints):
        raise ValueError(f'initial_joint_positions must have {len(joints)} elements (the '
                         f"robot's joints), got {len(positions)}: {shown(list(positions))}")
    return RobotConfig(robot, links, tracked, state, positions, robot_key(values))


@functools.lru_cache(maxsize=2)
def _loaded(text: str, base: str, position: tuple, orientation: tuple):
    """Return the robot and its links' pieces, loaded once per description and base."""
    from ..description.robot_description import load_robot
    from ..description.robot_links import robot_links
    robot = load_robot(text, base=base, base_position=position, base_orientation=orientation)
    return robot, robot_links(text)


def stand_in_body(config: RobotConfig) -> RigidBody:
    """
    Return the rigid body the node's single-body checks see: the robot's mass and inertia.

    The force bound in body weights and the lever check of the anchor read it; the step reads
    the robot's own M(q).
    """
    import numpy as np
    import pinocchio
    model = config.robot.model.model
    data = model.createData()
    q = pinocchio.neutral(model)
    pinocchio.ccrba(model, data, q, np.zeros(model.nv))
    inertia = data.Ig.inertia
    moments = (inertia[0, 0], inertia[0, 1], inertia[0, 2], inertia[1, 1], inertia[1, 2],
               inertia[2, 2])
    mass = config.robot.model.mass
    if min(np.linalg.eigvalsh(inertia)) <= 1e-9 * mass:
        return RigidBody.solid_box(mass, (0.1, 0.1, 0.1))
    return RigidBody(mass, tuple(float(m) for m in moments))
