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
What every mode of the observer process shares: its QoS, its lines to the bench, its spin.

The observer (``bench.observer``, its exercise mode ``bench.observer_exercise``) records with
``RECORD_QOS`` and publishes targets with ``TARGET_QOS``; it tells the bench process where it
is by lines on stdout (``say``) and spins its executor for a given wall time (``spin_for``).
"""

import sys
import time

from rclpy.qos import HistoryPolicy, QoSProfile, ReliabilityPolicy

# Deep enough that a slow spell of the observer never loses messages on its side.
RECORD_QOS = QoSProfile(history=HistoryPolicy.KEEP_LAST, depth=5000,
                        reliability=ReliabilityPolicy.RELIABLE)
# The node's target subscription and mouse_target's publisher: RELIABLE, depth 1.
TARGET_QOS = QoSProfile(history=HistoryPolicy.KEEP_LAST, depth=1,
                        reliability=ReliabilityPolicy.RELIABLE)


def say(text: str) -> None:
    """Write one line on stdout for the bench process that reads it."""
    sys.stdout.write(text + '\n')
    sys.stdout.flush()


def spin_for(executor, seconds: float) -> None:
    """Spin for ``seconds`` of wall time."""
    deadline = time.monotonic() + seconds
    while True:
        left = deadline - time.monotonic()
        if left <= 0.0:
            return
        executor.spin_once(timeout_sec=min(left, 0.05))
