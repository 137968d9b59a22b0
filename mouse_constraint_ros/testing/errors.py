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

"""The errors of ``SimulatedBody``: an input the node refused, a wait that failed, a closed one."""


class InputRefused(ValueError):
    """
    The node refused an input the harness sent; ``key`` and ``reason`` are the node's.

    :param key: the refusal's key ('frame', 'workspace', 'grab off body', 'wrench force' ...).
    :param reason: the node's reason, as it logs it after 'ignoring ...'.
    """

    def __init__(self, key: str, reason: str) -> None:
        """Keep the key beside the reason."""
        super().__init__(reason)
        self.key = key


class NeverHeld(AssertionError):
    """``step_until``'s predicate did not hold within its ticks."""


class HarnessClosed(RuntimeError):
    """The harness was closed: it steps, drains and sends nothing more."""

    def __init__(self, what: str) -> None:
        """Say what was asked of the closed harness."""
        super().__init__(f'{what}: this SimulatedBody is closed (its node and executor are '
                         'gone); make a new one')
