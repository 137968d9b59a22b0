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
One floor contact as the solve keeps it: the names of its slots.

A contact is a list of ``SLOTS`` floats (Box2D's contact solver keeps a struct per constraint
point, b2ContactConstraintPoint, with the same fields); a list, not an object, because the
sweeps read each contact's slots some ten times a substep and unpack them all at once
(``CONTACT`` gives that order). Each slot has a name here, and code reads and writes a contact
by these names, never by a bare number:

- ``POINT``: the contact point's index in the shape (``CollisionShape.contacts``), which names
  the contact from one substep to the next;
- ``LEVER_X`` .. ``LEVER_Z``: r, the point from the COM (m, world frame);
- ``SEPARATION``: s, the point's height above the plane (m; negative: below it);
- ``NORMAL_TURN_*``, ``TANGENT_TURN_*``, ``BITANGENT_TURN_*``: I_w^-1 (r x d) for d = z, x and
  y, the angular velocity a unit impulse along d gives;
- ``NORMAL_STIFFNESS``: K along z, the point's velocity change per unit normal impulse
  (1 / m + (r x z) . I_w^-1 (r x z));
- ``NORMAL_MASS``, ``TANGENT_MASS``, ``BITANGENT_MASS``: 1 / K along z, x and y, the effective
  masses;
- ``GOAL``: the least normal velocity the contact asks (m/s): -s / h ahead of the plane, zero
  touching it;
- ``NORMAL_IMPULSE``, ``TANGENT_IMPULSE``, ``BITANGENT_IMPULSE``: the accumulated impulses
  (N s), from which the next substep's contact of the same point warm starts;
- ``BOUNCE``: the normal velocity the contact bounces to, or None when it does not bounce.
"""

POINT = 0
LEVER_X, LEVER_Y, LEVER_Z = 1, 2, 3
SEPARATION = 4
NORMAL_TURN_X, NORMAL_TURN_Y, NORMAL_TURN_Z = 5, 6, 7
TANGENT_TURN_X, TANGENT_TURN_Y, TANGENT_TURN_Z = 8, 9, 10
BITANGENT_TURN_X, BITANGENT_TURN_Y, BITANGENT_TURN_Z = 11, 12, 13
NORMAL_STIFFNESS = 14
NORMAL_MASS, TANGENT_MASS, BITANGENT_MASS = 15, 16, 17
GOAL = 18
NORMAL_IMPULSE, TANGENT_IMPULSE, BITANGENT_IMPULSE = 19, 20, 21
BOUNCE = 22
SLOTS = 23

# Every slot's name in order: what ``floor_contact``'s sweeps unpack a contact into.
CONTACT = ('point', 'lever_x', 'lever_y', 'lever_z', 'separation',
           'normal_turn_x', 'normal_turn_y', 'normal_turn_z',
           'tangent_turn_x', 'tangent_turn_y', 'tangent_turn_z',
           'bitangent_turn_x', 'bitangent_turn_y', 'bitangent_turn_z',
           'normal_stiffness', 'normal_mass', 'tangent_mass', 'bitangent_mass', 'goal',
           'normal_impulse', 'tangent_impulse', 'bitangent_impulse', 'bounce')
IMPULSES = slice(NORMAL_IMPULSE, BITANGENT_IMPULSE + 1)
LEVER = slice(LEVER_X, LEVER_Z + 1)
