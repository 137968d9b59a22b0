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
Which targets the node takes: the policy of ``mouse_constraint``'s ``target`` subscription.

A target (frame, x, y, z) is taken when its frame is the node's ``frame_id`` (an empty frame
counts as it: the node makes no tf lookup), its coordinates are finite and it lies within
``workspace_radius`` of the origin. Otherwise it is refused, for the first of these three
reasons that applies, each with a key ('frame', 'finite', 'workspace') under which a caller
can throttle repeated refusals. Plain floats and strings only, so that the node and the command
line tools apply the same policy without loading one another.
"""

from dataclasses import dataclass
import math
from typing import NamedTuple, Optional, Sequence, Tuple

# The keys of the refusals, in the order the checks run.
REASONS = ('frame', 'finite', 'workspace')


class Refusal(NamedTuple):
    """Why a target is refused: ``key`` is one of ``REASONS``; ``reason`` is for a person."""

    key: str
    reason: str


def apart(value: float, bound: float) -> Tuple[str, str]:
    """
    Return ``value`` and the ``bound`` it passed as texts that differ: ``%g``, else every digit.

    ``%g`` keeps six digits, so that 100.00000001 exceeding 100 would read "100 exceeds 100".
    """
    shown = (f'{value:g}', f'{bound:g}')
    return shown if shown[0] != shown[1] else (repr(float(value)), repr(float(bound)))


@dataclass(frozen=True)
class TargetGate:
    """
    The node's target policy for its ``frame_id`` and ``workspace_radius`` (m).

    ``reason`` texts read after 'ignoring target ' (the node) or 'target refused: ' (a CLI).
    """

    frame_id: str
    workspace_radius: float
    # The node's frame_id when this gate takes a device's poses in another (device_frame_id).
    node_frame_id: str = ''

    def refusal(self, frame: str, point: Sequence[float]) -> Optional[Refusal]:
        """
        Return None when the node takes ``point`` (x, y, z in m) in ``frame``, else why not.

        :param frame: the target's frame_id; '' is the node's frame.
        :param point: the target's x, y, z.
        """
        x, y, z = map(float, point)
        return self._refusal(frame, (x, y, z), None)

    def circle_refusal(self, frame: str, center: Sequence[float],
                       radius: float) -> Optional[Refusal]:
        """
        Return None when the node takes every point of a horizontal circle, else why not.

        The point of the circle farthest from the origin is checked: the one in the direction
        of the centre's horizontal offset (any point when the centre is on the z axis), so the
        circle is taken exactly when that point is.

        :param frame: the targets' frame_id; '' is the node's frame.
        :param center: the circle's centre x, y, z (m).
        :param radius: the circle's radius (m).
        """
        cx, cy, cz = (float(c) for c in center)
        radius = float(radius)
        offset = math.hypot(cx, cy)
        ux, uy = ((cx / offset, cy / offset) if 0.0 < offset < math.inf else (1.0, 0.0))
        farthest = (cx + radius * ux, cy + radius * uy, cz)
        return self._refusal(frame, farthest, f'{farthest} on the circle around '
                                              f'{(cx, cy, cz)} of radius {radius:g} m')

    def _refusal(self, frame: str, point: Tuple[float, float, float],
                 described: Optional[str]) -> Optional[Refusal]:
        # On the node's path for every target: the reason text is only built for a refusal.
        if frame and frame != self.frame_id:
            if self.node_frame_id and self.node_frame_id != self.frame_id:
                return Refusal('frame', f'in frame {frame!r}: this node works in '
                                        f'{self.node_frame_id!r} and takes device poses in '
                                        f'{self.frame_id!r} (device_frame_id); no tf lookup '
                                        'is made')
            return Refusal('frame', f'in frame {frame!r}: this node works in '
                                    f'{self.frame_id!r} (no tf lookup is made)')
        x, y, z = point
        if not (math.isfinite(x) and math.isfinite(y) and math.isfinite(z)):
            return Refusal('finite', f'{described or point}: not finite')
        if math.hypot(x, y, z) > self.workspace_radius:
            return Refusal('workspace', f'{described or point}: farther than workspace_radius '
                                        f'{self.workspace_radius:g} m from the origin of '
                                        f'{self.frame_id!r}')
        return None
