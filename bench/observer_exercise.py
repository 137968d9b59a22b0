#!/usr/bin/env python3
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
The observer's ``exercise`` mode: every path of the node driven for a while (``bench.memory``).

Targets round a circle at a high rate, now and then a bad one (non-finite, foreign frame,
beyond the workspace), the ``~/reset`` and ``~/release`` services, a parameter change; it
subscribes to everything the node publishes. Prints ``progress <s>`` every second and writes
the counts. ``bench.observer`` runs it.
"""

import math
import time

from bench.observer_io import RECORD_QOS, say, spin_for, TARGET_QOS
from diagnostic_msgs.msg import DiagnosticArray
from geometry_msgs.msg import PointStamped, PoseStamped, TwistStamped
import numpy as np
from rcl_interfaces.msg import Parameter, ParameterType, ParameterValue
from rcl_interfaces.srv import SetParameters
from rclpy.node import Node
from std_srvs.srv import Trigger
from visualization_msgs.msg import MarkerArray

from test_support.ros_harness import spin_until


def observe_exercise(node: Node, executor, options) -> dict:
    """Drive the node's paths for ``options.seconds``; return what was sent and received."""
    counts = {'pose': 0, 'twist': 0, 'markers': 0, 'diagnostics': 0}

    def counter(name):
        def count(_raw) -> None:
            counts[name] += 1
        return count

    for message_type, topic, name in ((PoseStamped, 'pose', 'pose'),
                                      (TwistStamped, 'twist', 'twist'),
                                      (MarkerArray, 'mouse_constraint/markers', 'markers'),
                                      (DiagnosticArray, '/diagnostics', 'diagnostics')):
        node.create_subscription(message_type, topic, counter(name), RECORD_QOS, raw=True)
    publisher = node.create_publisher(PointStamped, 'target', TARGET_QOS)
    reset = node.create_client(Trigger, 'mouse_constraint/reset')
    release = node.create_client(Trigger, 'mouse_constraint/release')
    set_parameters = node.create_client(SetParameters, 'mouse_constraint/set_parameters')
    if not spin_until(executor, lambda: publisher.get_subscription_count() > 0
                      and reset.service_is_ready() and set_parameters.service_is_ready(), 30.0):
        raise SystemExit('the node did not show up')
    say('ready')
    sent = {'targets': 0, 'bad_targets': 0, 'resets': 0, 'releases': 0, 'parameter_sets': 0}
    bad = [((math.nan, 0.0, 1.0), options.frame), ((0.0, 0.0, 1.0), 'elsewhere'),
           ((1e9, 0.0, 0.0), options.frame), ((math.inf, 0.0, 0.0), options.frame)]
    message = PointStamped()
    start = time.monotonic()
    period = 1.0 / options.target_rate
    next_target = start
    next_second = start + 1.0
    while True:
        now = time.monotonic()
        elapsed = now - start
        if elapsed >= options.seconds:
            break
        if now >= next_target:
            next_target += period
            count = sent['targets'] + sent['bad_targets']
            if count % options.bad_every == options.bad_every - 1:
                point, frame = bad[sent['bad_targets'] % len(bad)]
                sent['bad_targets'] += 1
            else:
                angle = 2.0 * math.pi * elapsed / options.period
                point = (options.center[0] + options.radius * math.cos(angle),
                         options.center[1] + options.radius * math.sin(angle),
                         options.center[2])
                frame = options.frame
                sent['targets'] += 1
            message.header.frame_id = frame
            message.header.stamp.sec, message.header.stamp.nanosec = divmod(
                time.time_ns(), 1_000_000_000)
            message.point.x, message.point.y, message.point.z = point
            publisher.publish(message)
        if now >= next_second:
            next_second += 1.0
            second = int(round(elapsed))
            if second % 7 == 0:
                reset.call_async(Trigger.Request())
                sent['resets'] += 1
            if second % 11 == 0:
                release.call_async(Trigger.Request())
                sent['releases'] += 1
            if second % 13 == 0:
                value = ParameterValue(type=ParameterType.PARAMETER_DOUBLE,
                                       double_value=20.0 if second % 26 else 30.0)
                set_parameters.call_async(SetParameters.Request(
                    parameters=[Parameter(name='marker_rate_hz', value=value)]))
                sent['parameter_sets'] += 1
            say(f'progress {elapsed:.1f}')
        executor.spin_once(timeout_sec=max(0.0, min(next_target, next_second)
                                           - time.monotonic()))
    spin_for(executor, 0.5)
    say(f'end {time.time_ns()}')
    return {**{f'sent_{k}': np.int64(v) for k, v in sent.items()},
            **{f'received_{k}': np.int64(v) for k, v in counts.items()}}
