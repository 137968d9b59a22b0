"""
The physics core: one rigid body held by the mouse constraint. Imports numpy only, never rclpy.

See ``shared/seed/mouse-constraint.md`` for the constraint; the ``constraint`` module states the
two sign corrections made to it.
"""

from .body import RigidBody
from .constraint import MouseConstraint
from .simulation import MouseSimulation, Settings, STANDARD_GRAVITY
from .state import BodyState

__all__ = ['BodyState', 'MouseConstraint', 'MouseSimulation', 'RigidBody', 'Settings',
           'STANDARD_GRAVITY']
