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
The frames the node publishes in: ``frame_id`` (the world) and ``body_frame_id`` (the body).

tf2 refuses a frame id with a leading slash and a transform from a frame to itself, so both are
checked here, at start and on a change, rather than by the first broadcast. An empty
``body_frame_id`` is the body's own name: the URDF link's, which RViz's RobotModel draws on, or
``body`` for the box.
"""

from typing import Any, Mapping, Tuple

from ..physics.validation import shown


def frames_from(values: Mapping[str, Any], link: str) -> Tuple[str, str]:
    """
    Return the checked ``(frame_id, body_frame_id)`` of parameter ``values``.

    :param values: the node's parameter values.
    :param link: the body's own frame name, taken for an empty ``body_frame_id``.
    :raises ValueError: one line naming the parameter.
    """
    frame_id = values['frame_id']
    if not isinstance(frame_id, str) or not frame_id:
        raise ValueError(f'frame_id must be a non-empty string, got {shown(frame_id)}')
    _no_slash('frame_id', frame_id)
    body = values['body_frame_id']
    if not isinstance(body, str):
        raise ValueError(f'body_frame_id must be a string, got {shown(body)}')
    body = body or link
    _no_slash('body_frame_id', body)
    if body == frame_id:
        raise ValueError(f'body_frame_id must differ from frame_id, both are {shown(body)}: '
                         'tf2 refuses a transform from a frame to itself')
    return frame_id, body


def _no_slash(name: str, frame: str) -> None:
    """Raise ValueError when ``frame`` starts with a slash, which tf2 refuses."""
    if frame.startswith('/'):
        raise ValueError(f'{name} must not start with a slash, got {shown(frame)}: tf2 '
                         f'refuses such frame ids (use {shown(frame.lstrip("/"))})')
