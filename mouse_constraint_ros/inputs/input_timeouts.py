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
When the node lets go of an input nobody renews: the target and the external wrench.

A user target older than ``target_timeout`` releases the body (it falls free, as when
``~/release`` is called); a wrench older than ``wrench_timeout`` is removed (``HeldWrench``
holds it until then). A timeout of 0 means never. Ages are in the node's time: its clock, or
the simulated clock with ``publish_clock``; an age never reads negative, even just after the
clock restarted. Plain integers and floats only.
"""


def timed_out(since_ns: int, now_ns: int, timeout: float) -> bool:
    """Return whether an input taken at ``since_ns`` is older than ``timeout`` (s; 0: never)."""
    return timeout > 0.0 and now_ns - since_ns > timeout * 1e9


def input_age(since_ns: int, now_ns: int) -> float:
    """Return how old (s, >= 0) an input taken at ``since_ns`` is at ``now_ns``."""
    return max(0.0, (now_ns - since_ns) * 1e-9)


def target_release_text(timeout: float) -> str:
    """Return what the node logs when its target times out."""
    return f'no target for {timeout:g} s: releasing the body'


def wrench_removal_text(timeout: float) -> str:
    """Return what the node logs when its wrench times out."""
    return f'no wrench for {timeout:g} s: removing it'
