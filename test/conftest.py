"""
Shared fixtures: DDS isolation and a fresh rclpy context per test.

Every test process uses its own ROS_DOMAIN_ID (derived from the pid, away from the default 0,
or ``MOUSE_TEST_DOMAIN_ID`` when set, so that concurrent test runs can be kept apart for certain)
and localhost-only discovery, so tests never see a developer's nodes or each other's.
"""

import os

os.environ['ROS_DOMAIN_ID'] = os.environ.get('MOUSE_TEST_DOMAIN_ID', str(40 + os.getpid() % 60))
os.environ['ROS_AUTOMATIC_DISCOVERY_RANGE'] = 'LOCALHOST'

import pytest  # noqa: E402 (after the environment is set, as rclpy reads it)


@pytest.fixture
def ros():
    """Yield a ``RosHarness`` with its own context; shut it down afterwards."""
    from ros_helpers import RosHarness
    harness = RosHarness()
    yield harness
    harness.shutdown()
