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
The node's grab input: where a grab lands on the body, the anchor set there, the target held.

A grab passes the targets' gate (frame, finite, workspace), then ``grab`` says where on the
body it lands (a robot: on the nearest of its links, ``RobotBody.land``); one farther than
``grab_margin`` from the body's shape is refused. The node's own ``anchor`` parameter is set
to that point (``set_anchor``, validated as any parameter change) and the point becomes the
target, untimed (``TargetInput.hold``), after the targets that came before the grab. Every
refusal goes to the node's ``RefusalLog``: a throttled warning, counted.
"""

from typing import Callable, Optional

from geometry_msgs.msg import PointStamped

from .parameters import NodeConfig
from .target_input import TargetInput
from ..inputs.grab import Grab, grab
from ..inputs.target_gate import apart, Refusal
from ..inputs.throttle import RefusalLog
from ..physics import MouseSimulation
from ..physics.algebra import Vector3
from ..wire.messages import point_from_message


class GrabInput:
    """
    The ``grab`` callback: a point on the body made the anchor and the target.

    :param simulation: the body grabbed.
    :param config: the node's configuration (``configure`` replaces it): the body's shape and
        frame, a robot, ``grab_margin``.
    :param target: the target input: its gate, the targets that came first, the target held.
    :param set_anchor: sets the node's ``anchor`` parameter; returns None or why it could not.
    :param refuse: counts and warns about a refused grab.
    """

    def __init__(self, *, simulation: MouseSimulation, config: NodeConfig, target: TargetInput,
                 set_anchor: Callable[[Vector3], Optional[str]], refuse: RefusalLog) -> None:
        """Take grabs on the body of ``config``."""
        self._simulation = simulation
        self._target = target
        self._set_anchor = set_anchor
        self._refuse = refuse
        self.configure(config)

    def configure(self, config: NodeConfig) -> None:
        """Take a new configuration: the body's shape, a robot, the grab's margin."""
        self._config = config

    def on_grab(self, message: PointStamped) -> None:
        """Make a point on the body the anchor and the target; ignore (and say) any other."""
        point = point_from_message(message)
        refusal = self._target.gate.refusal(message.header.frame_id, point)
        if refusal is not None:
            self._refuse(refusal._replace(key='grab ' + refusal.key),
                         f'ignoring grab {refusal.reason}')
            return
        config = self._config
        if config.robot is not None:
            # A robot: the grab lands on the nearest of its links (``RobotBody.land``).
            link, local, distance = self._simulation.land(point)
            landed = Grab(local, distance)
        else:
            landed = grab(config.body_frame.link_state(self._simulation.state), config.geometry,
                          point)
        margin = config.grab_margin
        if not landed.taken(margin):
            off, bound = apart(landed.distance, margin)
            reason = (f'{point}: {off} m off the body, farther than grab_margin {bound} m from '
                      'its shape')
            self._refuse(Refusal('grab off body', reason), f'ignoring grab {reason}')
            return
        self._target.flush()  # a target that came before the grab goes before it
        if config.robot is not None:
            self._simulation.hold(link)
        failure = self._set_anchor(landed.anchor)
        if failure is not None:
            self._refuse(Refusal('grab anchor', f'{point}: {failure}'),
                         f'ignoring grab {point}: {failure}')
            return
        self._target.hold(point)
