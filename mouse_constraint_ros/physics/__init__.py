"""
The physics core: one rigid body held by the mouse constraint. Imports numpy only, never rclpy.

The constraint is Irlan Robson's, from his note "The Mouse Constraint (and its Jacobian)" (the
"seed" note of the docstrings); the ``constraint`` module states the two sign corrections made
to it, and ``limits`` the ranges of the settings.
"""

from .body import RigidBody
from .floor import Floor
from .mouse_joint import MouseConstraint
from .simulation import MouseSimulation, Settings, STANDARD_GRAVITY
from .state import BodyState

__all__ = ['BodyState', 'Floor', 'MouseConstraint', 'MouseSimulation', 'RigidBody', 'Settings',
           'STANDARD_GRAVITY']
