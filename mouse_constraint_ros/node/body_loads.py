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
A new ``robot_description`` loaded off the tick, swapped in whole between ticks, or refused.

Reading a URDF and its meshes takes from a millisecond to seconds (a mesh of 200 000
triangles); the tick and the services must not wait for it. At start the node loads its body
before it ticks (``now``). At run time a change that needs a body not loaded yet (another
``robot_description``, ``body_link`` or ``density``) is accepted at once and its whole
configuration is made on a worker thread (``refusal`` starts it); the node ticks on with the
body it has. When the worker is done, a timer of the node's executor (so between two ticks)
applies the configuration whole, or logs its refusal in one line and sets the changed
parameters back to what they were (``finish``): the body is then unchanged. While a body
loads, other changes are refused with the reason (``refusal``), as is a description too long to
read at once. The body loaded last is kept: a change of another parameter (a grab's anchor)
does not read the URDF again.

``mouse_constraint_ros.testing`` waits for the worker (``wait``) and calls ``finish`` itself, so
that a harness's change is applied, or refused, before its next tick.
"""

import threading
from typing import Any, Callable, List, Mapping, Optional, Tuple

from rclpy.clock import Clock, ClockType
from rclpy.node import Node
from rclpy.parameter import Parameter

from .body_parameters import load_body
from .parameters import node_config, NodeConfig
from ..description.text_size import oversized

# How often (s, steady time) the node looks whether a load is done.
POLL_PERIOD = 0.01
# The key of a loaded body: (robot_description, body_link, density).
Key = Tuple[Any, Any, Any]


class _Job:
    """One load on its worker thread: the parameter values, the changes, what it made."""

    def __init__(self, values: Mapping[str, Any], changes: List[Parameter],
                 previous: List[Parameter]) -> None:
        self.values = dict(values)
        self.changes = changes
        self.previous = previous
        self.key: Key = _key(values)
        self.model = None
        self.outcome: Any = None
        self.done = threading.Event()

    def run(self) -> None:
        """Make the configuration (or the reason it is refused); then set ``done``."""
        try:
            self.outcome = node_config(self.values, load=self._load)
        except Exception as error:  # noqa: B902 - the node goes on; the reason is logged
            self.outcome = ' '.join(str(error).split()) or type(error).__name__
            if not isinstance(error, ValueError):
                self.outcome = f'{type(error).__name__}: {self.outcome}'
        finally:
            self.done.set()

    def _load(self, description: str, link: str, density: float):
        self.model = load_body(description, link, density)
        return self.model


class BodyLoads:
    """
    The body loaded last, and the one loading off the tick (see the module).

    :param node: the node whose parameters are set back when a load is refused.
    :param apply: applies a configuration and the changes that made it; returns why it cannot
        be applied (the clock's refusal), or None.
    """

    def __init__(self, node: Node,
                 apply: Callable[[NodeConfig, List[Parameter]], Optional[str]]) -> None:
        """Start with no body loaded."""
        self._node = node
        self._apply = apply
        self._key: Optional[Key] = None
        self._model = None
        self._job: Optional[_Job] = None
        self._timer = None
        self._reverting = False

    @property
    def reverting(self) -> bool:
        """Return whether the node is setting a refused load's parameters back."""
        return self._reverting

    @property
    def loading(self) -> bool:
        """Return whether a body is loading."""
        return self._job is not None

    def now(self, description: str, link: str, density: float):
        """Return the body of the key, loaded here unless it is the one loaded last."""
        key = (description, link, density)
        if key != self._key:
            self._model = load_body(description, link, density)
            self._key = key
            self._warn(self._model)
        return self._model

    def _warn(self, model) -> None:
        """Log the loaded body's warnings (``BodyModel.notes``), one line each."""
        for line in getattr(model, 'notes', ()):
            self._node.get_logger().warning(line)

    def refusal(self, values: Mapping[str, Any], changes: List[Parameter]) -> Optional[str]:
        """
        Return '' for a change taken here, the reason to refuse one, or None: the node goes on.

        Taken here: the node's own change back, and a change that needs a body not loaded yet,
        which starts loading. Refused: any change while a body loads; a description too long to
        read.

        :param values: every parameter's value with the changes.
        :param changes: the changes, set back if the load is refused.
        """
        if self._reverting:
            return ''
        if self._job is not None:
            return ('robot_description: the body of the last change is still loading: set '
                    'this again once it is in (the log says when)')
        description = values['robot_description']
        if not isinstance(description, str) or not description or _key(values) == self._key:
            return None
        too_long = oversized(description)
        if too_long is not None:
            return too_long
        self._start(values, changes)
        return ''

    def _start(self, values: Mapping[str, Any], changes: List[Parameter]) -> None:
        """Start loading the body of ``values`` on a worker; the node ticks on meanwhile."""
        node = self._node
        previous = [node.get_parameter(change.name) for change in changes
                    if node.has_parameter(change.name)]
        job = self._job = _Job(values, changes, previous)
        threading.Thread(target=job.run, name='body_load', daemon=True).start()
        if self._timer is None:  # made once, cancelled between loads
            self._timer = node.create_timer(POLL_PERIOD, self.finish,
                                            clock=Clock(clock_type=ClockType.STEADY_TIME))
        else:
            self._timer.reset()
        node.get_logger().info(f'loading robot_description ({len(values["robot_description"])} '
                               'characters) off the tick; the body changes once it is loaded')

    def wait(self, timeout: Optional[float] = None) -> bool:
        """Wait until the load is done (at most ``timeout`` s); return whether it is."""
        job = self._job
        return job is None or job.done.wait(timeout)

    def finish(self) -> Optional[str]:
        """
        Apply a finished load whole, or refuse it; return the refusal (None: applied or none).

        Called between ticks: by the node's timer, or by whoever steps the node.
        """
        job = self._job
        if job is None or not job.done.is_set():
            return None
        self._job = None
        self._timer.cancel()
        if isinstance(job.outcome, str):
            reason = job.outcome
        else:
            reason = self._apply(job.outcome, job.changes)
        if reason is None:
            self._key, self._model = job.key, job.model
            self._warn(job.model)
            return None
        self._node.get_logger().error(f'robot_description refused: {reason}; the body and the '
                                      'parameters stay as they were')
        self._reverting = True
        try:
            self._node.set_parameters(job.previous)
        finally:
            self._reverting = False
        return reason


def _key(values: Mapping[str, Any]) -> Key:
    """Return the key of the body ``values`` name."""
    return values['robot_description'], values['body_link'], values['density']
