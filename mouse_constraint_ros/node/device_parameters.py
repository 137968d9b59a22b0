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
The device parameters: a haptic device's frame, its map into the world, its force output.

``parameters.PARAMETERS`` takes ``DEVICE_PARAMETERS`` into the node's one table; ``device_from``
turns their values into a ``DeviceConfig`` or raises ValueError naming the parameter. A pose on
``target_pose`` is in ``device_frame_id`` (empty: ``frame_id``) and is mapped into ``frame_id``
by ``physics.device_map.DeviceMap``; the force goes back through the same map, on ``force``
(WrenchStamped, in the device's frame), on ``force_array`` (Float64MultiArray: fx, fy, fz), or
both. ``tick_source`` says whether the device's poses run the ticks (``timing.device_clock``).
No ROS here.
"""

from typing import Any, Mapping, NamedTuple

from .timer_limits import FINITE_MAX
from ..physics.device_map import device_map, DeviceMap, SCALE_RANGE
from ..physics.validation import scalar, shown

# What ``force_output`` takes: which of the force's two messages go out with publish_force.
FORCE_OUTPUTS = ('wrench', 'array', 'both')
# What ``tick_source`` takes: the node's own clock, or the device's poses.
TICK_SOURCES = ('clock', 'target_pose')
IDENTITY_POSE = [0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 1.0]

# (name, default, description, bounds), as ``parameters.ParameterSpec`` takes them.
DEVICE_PARAMETERS = (
    ('force_output', 'wrench',
     'With publish_force: wrench (geometry_msgs/WrenchStamped on force), array '
     '(std_msgs/Float64MultiArray [fx, fy, fz] on force_array, for a ros2_control forward '
     'command controller) or both, from the same tick.', None),
    ('device_frame_id', '',
     'The frame a haptic device driver stamps its poses on target_pose with, and the frame of '
     'the force sent back; empty = frame_id.', None),
    ('device_scale', 1.0,
     'Position scale s from the device frame into frame_id: p = offset + s R p_device.',
     SCALE_RANGE),
    ('device_pose', IDENTITY_POSE,
     'The device frame in frame_id: offset x y z (m), then R as a unit quaternion qx qy qz qw.',
     None),
    ('device_force_scale', 1.0,
     'Force scale f back to the device: f_device = f R^T F. The handle feels a coupling k as '
     's f k; f = s keeps the power.', SCALE_RANGE),
    ('tick_source', 'clock',
     "What runs the ticks: clock (the node's own) or target_pose (each valid device pose runs "
     "one tick at once, its force right after; the node's own clock again after "
     'device_timeout without one).', None),
    ('device_timeout', 0.1,
     'Once a pose came on target_pose: the force is zero while no valid pose came for this '
     'long (s), so a device never renders a stale force; with tick_source target_pose, the '
     "node's own ticks run again after it. 0 = never.", (0.0, FINITE_MAX)),
)


class DeviceConfig(NamedTuple):
    """The device side of the node: its frame, its map, its force output, its timeout."""

    frame_id: str = ''
    mapping: DeviceMap = DeviceMap()
    force_output: str = 'wrench'
    timeout: float = 0.1
    tick_source: str = 'clock'

    def pose_frame(self, world_frame: str) -> str:
        """Return the frame the node takes poses on ``target_pose`` in."""
        return self.frame_id or world_frame


def device_from(values: Mapping[str, Any]) -> DeviceConfig:
    """Return the checked ``DeviceConfig`` of parameter ``values``; raise ValueError why not."""
    frame = values['device_frame_id']
    if not isinstance(frame, str):
        raise ValueError(f'device_frame_id must be a string, got {shown(frame)}')
    output = values['force_output']
    if output not in FORCE_OUTPUTS:
        raise ValueError(f'force_output must be one of {", ".join(FORCE_OUTPUTS)}, got '
                         f'{shown(output)}')
    mapping = device_map(values['device_scale'], values['device_pose'],
                         values['device_force_scale'])
    timeout = scalar('device_timeout', values['device_timeout'], at_least=0.0)
    source = values['tick_source']
    if source not in TICK_SOURCES:
        raise ValueError(f'tick_source must be one of {", ".join(TICK_SOURCES)}, got '
                         f'{shown(source)}')
    return DeviceConfig(frame, mapping, output, timeout, source)
