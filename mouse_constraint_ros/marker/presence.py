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
Which feedback publishers a drag hangs on, and whether one of them left the graph.

RViz's interactive marker client signs its feedback with its node's fully qualified name
(``client_id``; ``/rviz`` unless RViz is renamed). At a press, the feedback publishers of the
node of that name are the ones the drag hangs on; when none has that name (a client that signs
otherwise), every feedback publisher then on the graph is. The drag ends when one of them
leaves: its RViz closed or crashed, whether or not another RViz stays. Two clients of one name
cannot be told apart, so either one leaving ends the drag.
"""

from typing import FrozenSet, Iterable, Tuple

# A feedback publisher on the graph: its node's fully qualified name and its endpoint's gid.
Endpoint = Tuple[str, Tuple[int, ...]]


def watched(client_id: str, endpoints: Iterable[Endpoint]) -> FrozenSet[Tuple[int, ...]]:
    """Return the gids a drag by ``client_id`` hangs on, among the publishers ``endpoints``."""
    endpoints = list(endpoints)
    own = frozenset(gid for name, gid in endpoints if name == client_id)
    return own or frozenset(gid for _name, gid in endpoints)


def departed(hung_on: FrozenSet[Tuple[int, ...]], endpoints: Iterable[Endpoint]) -> bool:
    """
    Return whether a publisher the drag hangs on is no longer among ``endpoints``.

    With none known (the graph did not list the press's publisher yet), whether none is left.
    """
    present = {gid for _name, gid in endpoints}
    return not present if not hung_on else not hung_on <= present
