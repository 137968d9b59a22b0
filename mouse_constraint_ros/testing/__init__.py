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
Test your own node against the body: the ``mouse_constraint`` node in-process, in lockstep.

``SimulatedBody`` runs the real node in an rclpy context of its own (discovery off: nothing
outside the process sees its traffic) and steps it on simulated time, draining the executor
after each tick, so that a node added with ``add_node`` sees every tick and its ROS-time timers
fire at exact simulated times::

    import numpy as np
    from mouse_constraint_ros.testing import SimulatedBody

    with SimulatedBody(mass=2.0, floor=True) as body:
        body.grab((0.2, 0.1, 1.05))  # this point of the body is the anchor
        body.target((0.5, 0.2, 1.0))  # drag the anchor there
        body.step(500)  # 0.5 s of simulated time at 1 kHz
        assert np.linalg.norm(body.anchor - (0.5, 0.2, 1.0)) < 1e-3

``body.anchor`` is the dragged point in the world, ``body.pose.position`` the centre of mass;
``body.add_node(node)`` adds your node.

The pytest fixtures ``simulated_body`` and ``simulated_body_factory`` come with the package
(``pytest_plugin``, registered as a pytest entry point). This module imports nothing of rclpy
until one of its names is used, so that the plugin costs pytest nothing at start.
"""

import importlib
from typing import Any

__all__ = ['BodyPose', 'BodyTwist', 'DrainTimeout', 'HarnessClosed', 'InputRefused',
           'MatchTimeout', 'NeverHeld', 'SimulatedBody']

# Where each name lives: imported on first use (PEP 562).
_HOMES = {
    'BodyPose': 'readings',
    'BodyTwist': 'readings',
    'HarnessClosed': 'errors',
    'InputRefused': 'errors',
    'NeverHeld': 'errors',
    'SimulatedBody': 'simulated_body',
    'DrainTimeout': 'lockstep',
    'MatchTimeout': 'lockstep',
}


def __getattr__(name: str) -> Any:
    """Import the module that defines ``name`` when it is first asked for."""
    if name not in _HOMES:
        raise AttributeError(f'module {__name__!r} has no attribute {name!r}')
    return getattr(importlib.import_module(f'.{_HOMES[name]}', __name__), name)


def __dir__():
    """List the public names, imported or not."""
    return sorted(__all__)
