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
A URDF's tree of links and joints, read and checked before any dynamics is built from it.

``robot_structure`` reads the ``<link>`` and ``<joint>`` elements with the standard library's
parser and refuses, in one line naming the joint or link, what the robot mode does not serve:

- a joint of type floating or planar inside the tree, or a ``<mimic>`` joint that follows a
  joint the URDF does not have, or one that is itself a mimic (a mimic joint is served: it moves
  as ``multiplier`` times its leader plus ``offset``, a constraint row of the step);
- a kinematic loop (a link that is the child of two joints, or a cycle), or several roots;
- ``<limit lower upper>`` with lower > upper, a joint axis of zero length, a non-finite number;
- a moving part without mass: the links a joint moves, merged with those fixed to them, must
  weigh something, or the joint-space mass matrix M(q) is singular;
- more than ``MAX_JOINTS`` joints.

The result names the tree's root, its chains and its longest chain's last link (the tool that
``tracked_link`` defaults to).
"""

import math
from typing import Dict, List, NamedTuple, Optional, Tuple
from xml.etree import ElementTree

# The most joints a robot may have: a humanoid with hands has about 60; each joint is a column
# of the Jacobians and M(q) is nv x nv, factored every substep.
MAX_JOINTS = 100
MOVING_JOINTS = ('revolute', 'continuous', 'prismatic')
SERVED_JOINTS = MOVING_JOINTS + ('fixed',)
# The link name that fixes the root to the world (the Gazebo and MoveIt convention).
WORLD_LINK = 'world'
FIXED_BASE = 'fixed'
FLOATING_BASE = 'floating'


class JointSpec(NamedTuple):
    """One ``<joint>`` as the URDF states it."""

    name: str
    kind: str
    parent: str
    child: str
    lower: float
    upper: float
    velocity: float
    effort: float
    mimic: Optional[Tuple[str, float, float]] = None  # (leader joint, multiplier, offset)


class RobotStructure(NamedTuple):
    """The checked tree: its links (in document order), joints, root and longest chain's tip."""

    name: str
    links: Tuple[str, ...]
    joints: Tuple[JointSpec, ...]
    root: str
    tool: str
    root_mass: float = 0.0  # the root link's and what is fixed to it (kg)

    @property
    def fixed_to_world(self) -> bool:
        """Return whether the root is the ``world`` link (the base fixed where it joins)."""
        return self.root == WORLD_LINK

    @property
    def moving_joints(self) -> Tuple[JointSpec, ...]:
        """Return the joints that move (revolute, continuous, prismatic), in document order."""
        return tuple(joint for joint in self.joints if joint.kind in MOVING_JOINTS)


def _number(joint: str, element: ElementTree.Element, attribute: str, default: float) -> float:
    text = element.get(attribute)
    if text is None:
        return default
    try:
        value = float(text)
    except ValueError:
        raise ValueError(f'joint {joint!r}: <{element.tag} {attribute}="{text}"> is not a number'
                         + (' (expand the xacro file first)' if '$' in text else '')) from None
    if math.isnan(value):
        raise ValueError(f'joint {joint!r}: <{element.tag} {attribute}="{text}"> is not a number')
    return value


def _joint(element: ElementTree.Element) -> JointSpec:
    name = element.get('name') or '?'
    kind = element.get('type') or ''
    if kind not in SERVED_JOINTS:
        raise ValueError(
            f'joint {name!r} is of type {kind!r}: the robot mode serves revolute, continuous, '
            'prismatic and fixed joints (a floating base is the parameter base: floating)')
    mimic = element.find('mimic')
    follows = None
    if mimic is not None:
        if kind not in MOVING_JOINTS or not mimic.get('joint'):
            raise ValueError(f'joint {name!r}: <mimic> needs joint=... on a moving joint')
        follows = (mimic.get('joint'), _number(name, mimic, 'multiplier', 1.0),
                   _number(name, mimic, 'offset', 0.0))
    parent, child = element.find('parent'), element.find('child')
    if parent is None or child is None or not parent.get('link') or not child.get('link'):
        raise ValueError(f'joint {name!r} needs <parent link=...> and <child link=...>')
    axis = element.find('axis')
    if kind in MOVING_JOINTS and axis is not None:
        values = (axis.get('xyz') or '').split()
        try:
            xyz = [float(value) for value in values]
        except ValueError:
            xyz = []
        if len(xyz) != 3 or not all(map(math.isfinite, xyz)):
            raise ValueError(f'joint {name!r}: <axis xyz="{axis.get("xyz")}"> must be three '
                             'finite numbers')
        if math.sqrt(sum(value * value for value in xyz)) < 1e-9:
            raise ValueError(f'joint {name!r}: <axis xyz="{axis.get("xyz")}"> has zero length; '
                             'give the direction the joint turns or slides about')
    limit = element.find('limit')
    lower, upper, velocity, effort = -math.inf, math.inf, math.inf, math.inf
    if limit is not None:
        velocity = _number(name, limit, 'velocity', math.inf) or math.inf
        effort = _number(name, limit, 'effort', math.inf) or math.inf
        if velocity < 0.0 or effort < 0.0:
            raise ValueError(f'joint {name!r}: <limit velocity effort> must be >= 0, got '
                             f'{velocity:g} and {effort:g}')
        if kind in ('revolute', 'prismatic'):
            lower = _number(name, limit, 'lower', 0.0)
            upper = _number(name, limit, 'upper', 0.0)
            if lower > upper:
                raise ValueError(f'joint {name!r}: <limit lower="{lower:g}" upper="{upper:g}"> '
                                 'has lower > upper; swap them')
    elif kind in ('revolute', 'prismatic'):
        raise ValueError(f'joint {name!r} of type {kind} needs <limit lower upper effort '
                         'velocity> (URDF requires it; a joint without stops is continuous)')
    return JointSpec(name, kind, parent.get('link'), child.get('link'), lower, upper, velocity,
                     effort, follows)


def _mass(element: ElementTree.Element) -> float:
    mass = element.find('inertial/mass')
    if mass is None:
        return 0.0
    try:
        return max(float(mass.get('value') or 0.0), 0.0)
    except ValueError:
        raise ValueError(f'link {element.get("name")!r}: <mass value="{mass.get("value")}"> is '
                         'not a number') from None


def robot_structure(text: str) -> RobotStructure:
    """
    Return the checked tree of the URDF ``text``; raise ValueError in one line otherwise.

    :param text: the URDF (XML).
    """
    try:
        root = ElementTree.fromstring(text)
    except ElementTree.ParseError as error:
        raise ValueError(f'robot_description is not well-formed XML: {error}') from None
    if root.tag != 'robot':
        raise ValueError(f'robot_description must be a <robot>, got <{root.tag}>')
    links = [link.get('name') or '' for link in root.findall('link')]
    masses = {link.get('name') or '': _mass(link) for link in root.findall('link')}
    joint_elements = root.findall('joint')
    if len(joint_elements) > MAX_JOINTS:
        raise ValueError(f'the URDF has {len(joint_elements)} joints, more than {MAX_JOINTS}: '
                         'the robot mode serves at most that many')
    joints = tuple(_joint(element) for element in joint_elements)
    parent_of: Dict[str, JointSpec] = {}
    for joint in joints:
        for link in (joint.parent, joint.child):
            if link not in masses:
                raise ValueError(f'joint {joint.name!r} names link {link!r}, which the URDF '
                                 'does not have')
        if joint.child in parent_of:
            raise ValueError(
                f'link {joint.child!r} is the child of joints {parent_of[joint.child].name!r} '
                f'and {joint.name!r}: a kinematic loop, which a URDF tree cannot hold')
        parent_of[joint.child] = joint
    by_name = {joint.name: joint for joint in joints}
    for joint in joints:
        if joint.mimic is not None:
            leader = by_name.get(joint.mimic[0])
            if leader is None or leader.kind not in MOVING_JOINTS or leader.mimic is not None:
                raise ValueError(f'joint {joint.name!r} mimics {joint.mimic[0]!r}, which is not '
                                 'a moving joint of its own in the URDF')
    roots = [link for link in links if link not in parent_of]
    if len(roots) != 1:
        raise ValueError(f'the URDF must have one root link, got {len(roots)}: '
                         + (', '.join(map(repr, roots[:5])) or 'a kinematic loop')
                         + ('; join its links by joints for a robot, or set body_link to the '
                            'one to simulate' if roots else ''))
    children: Dict[str, List[JointSpec]] = {}
    for joint in joints:
        children.setdefault(joint.parent, []).append(joint)
    depth = {roots[0]: 0}
    order = [roots[0]]
    for link in order:
        for joint in children.get(link, ()):
            depth[joint.child] = depth[link] + 1
            order.append(joint.child)
    if len(order) != len(links):
        unreached = [link for link in links if link not in depth]
        raise ValueError(f'link {unreached[0]!r} is on a kinematic loop: it cannot be reached '
                         'from the root')
    for joint in joints:
        if joint.kind in MOVING_JOINTS and _moved_mass(joint.child, children, masses) <= 0.0:
            raise ValueError(
                f'joint {joint.name!r} moves links of zero mass ({joint.child!r} and what is '
                'fixed to it): give them <inertial> mass, or make the joint fixed')
    tool = _tool(links, depth)
    return RobotStructure(root.get('name') or '', tuple(links), joints, roots[0], tool,
                          _moved_mass(roots[0], children, masses))


def _moved_mass(link: str, children: Dict[str, List[JointSpec]],
                masses: Dict[str, float]) -> float:
    """Return the mass of ``link`` and every link fixed to it through fixed joints."""
    total, stack = 0.0, [link]
    while stack:
        current = stack.pop()
        total += masses.get(current, 0.0)
        stack.extend(joint.child for joint in children.get(current, ()) if joint.kind == 'fixed')
    return total


def _tool(links: List[str], depth: Dict[str, int]) -> str:
    """Return the last link of the longest chain: the deepest, the first in the file on a tie."""
    deepest = max(depth.values())
    return next(link for link in links if depth[link] == deepest)


def joint_named(structure: RobotStructure, name: str) -> Optional[JointSpec]:
    """Return the joint called ``name``, or None."""
    return next((joint for joint in structure.joints if joint.name == name), None)
