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

"""nav_msgs/Odometry as precompiled CDR (see ``layout``)."""

import struct
from typing import Iterable, Tuple

from nav_msgs.msg import Odometry

from .layout import (Compiler, covariance, ENCAPSULATION_LE, fill_fields, fill_stamp, frame_text,
                     Layout, NANOSECONDS_PER_SECOND, Vector, ZERO_COVARIANCE)


class OdometryLayout(Layout):
    """
    nav_msgs/Odometry: ``pack(stamp_ns, position, orientation, linear, angular)``.

    The frame ids and the two covariances (36 doubles each, row-major) are held by the layout,
    as they change rarely; setting any of them compiles the layout again.

    :param frame_id: the header's frame id (the pose's frame).
    :param child_frame_id: the twist's frame.
    :param pose_covariance: the pose's covariance; zeros by default.
    :param twist_covariance: the twist's covariance; zeros by default.
    """

    message_type = Odometry
    _PROBE = ((0.0,) * 3, (0.0,) * 4, (0.0,) * 3, (0.0,) * 3)

    def __init__(self, frame_id: str, child_frame_id: str, *,
                 pose_covariance: Iterable[float] = ZERO_COVARIANCE,
                 twist_covariance: Iterable[float] = ZERO_COVARIANCE) -> None:
        super().__init__()
        self._frame_id = frame_text('frame_id', frame_id)
        self._child_frame_id = frame_text('child_frame_id', child_frame_id)
        self._pose_covariance = covariance('pose_covariance', pose_covariance)
        self._twist_covariance = covariance('twist_covariance', twist_covariance)
        self._rebuild()

    def configure(self, **changes) -> None:
        """
        Set any of ``frame_id``, ``child_frame_id``, ``pose_covariance``, ``twist_covariance``.

        The layout is compiled again once, and only if something changed.
        """
        checks = {'frame_id': frame_text, 'child_frame_id': frame_text,
                  'pose_covariance': covariance, 'twist_covariance': covariance}
        unknown = set(changes) - set(checks)
        if unknown:
            raise ValueError(f'unknown Odometry layout settings: {sorted(unknown)}')
        new = {name: checks[name](name, value) for name, value in changes.items()}
        if any(getattr(self, '_' + name) != value for name, value in new.items()):
            for name, value in new.items():
                setattr(self, '_' + name, value)
            self._rebuild()

    frame_id = property(lambda self: self._frame_id,
                        lambda self, value: self.configure(frame_id=value),
                        doc="The header's frame id.")
    child_frame_id = property(lambda self: self._child_frame_id,
                              lambda self, value: self.configure(child_frame_id=value),
                              doc="The twist's frame id.")
    pose_covariance = property(lambda self: self._pose_covariance,
                               lambda self, value: self.configure(pose_covariance=value),
                               doc="The pose's 6x6 covariance, row-major.")
    twist_covariance = property(lambda self: self._twist_covariance,
                                lambda self, value: self.configure(twist_covariance=value),
                                doc="The twist's 6x6 covariance, row-major.")

    def _strings(self) -> Tuple[str, ...]:
        return (self._frame_id, self._child_frame_id)

    def _compile(self, compiler: Compiler) -> None:
        compiler.primitives('i')
        compiler.primitives('I')
        self._frame_bytes = compiler.string(self._frame_id)
        self._child_bytes = compiler.string(self._child_frame_id)
        compiler.primitives('d', 7)
        self._pose_covariance_bytes = compiler.doubles(self._pose_covariance)
        compiler.primitives('d', 6)
        self._twist_covariance_bytes = compiler.doubles(self._twist_covariance)

    def pack(self, stamp_ns: int, position: Vector, orientation: Vector, linear: Vector,
             angular: Vector) -> bytes:
        """
        Return the bytes of the odometry with this pose and twist.

        :raises ValueError: as ``PoseStampedLayout.pack``.
        """
        fields = (position, orientation, linear, angular)
        if self._struct is None:
            return self._fallback(stamp_ns, *fields)
        sec, nanosec = divmod(stamp_ns, NANOSECONDS_PER_SECOND)
        try:
            return self._struct.pack(
                ENCAPSULATION_LE, sec, nanosec, self._frame_bytes, self._child_bytes,
                *position, *orientation, self._pose_covariance_bytes,
                *linear, *angular, self._twist_covariance_bytes)
        except (struct.error, TypeError) as error:
            raise self._error(stamp_ns, fields, error) from None

    def message(self, stamp_ns: int, position: Vector, orientation: Vector, linear: Vector,
                angular: Vector) -> Odometry:
        message = Odometry()
        message.header.frame_id = self._frame_id
        message.child_frame_id = self._child_frame_id
        fill_stamp(message.header.stamp, stamp_ns)
        fill_fields(message.pose.pose.position, 'xyz', position)
        fill_fields(message.pose.pose.orientation, 'xyzw', orientation)
        message.pose.covariance = list(self._pose_covariance)
        fill_fields(message.twist.twist.linear, 'xyz', linear)
        fill_fields(message.twist.twist.angular, 'xyz', angular)
        message.twist.covariance = list(self._twist_covariance)
        return message
