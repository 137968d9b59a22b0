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
Shared fixtures: DDS isolation, a fresh rclpy context per test, one colcon build a session.

Each test is marked with its tier here (unit, ros, system), and ``alone`` when it needs the
machine to itself (``make test`` runs those last, in one process).

Every test process uses its own ROS_DOMAIN_ID (derived from the pid, away from the default 0,
or ``MOUSE_TEST_DOMAIN_ID`` when set, so that concurrent test runs can be kept apart for certain)
and localhost-only discovery, so tests never see a developer's nodes or each other's, and the
participant profile config/fast_discovery.xml, so that the processes a test starts find each
other within 0.4 s. Under ``pytest -n`` (pytest-xdist) the workers of one run take domains
spread apart by their index, so that they never share one.
"""

import gc
import hashlib
import os
from pathlib import Path
import subprocess
import sys


def _domain_id() -> int:
    """Return this test process's ROS_DOMAIN_ID, in 40 .. 99."""
    worker = os.environ.get('PYTEST_XDIST_WORKER')  # gw0, gw1, ... under pytest -n
    if worker is None:
        return 40 + os.getpid() % 60
    run = int(hashlib.sha256(os.environ.get('PYTEST_XDIST_TESTRUNUID', '').encode()).hexdigest(),
              16)
    workers = int(os.environ.get('PYTEST_XDIST_WORKER_COUNT', '1'))
    return 40 + (run + int(worker[2:]) * 60 // max(workers, 1)) % 60


os.environ['ROS_DOMAIN_ID'] = os.environ.get('MOUSE_TEST_DOMAIN_ID', str(_domain_id()))
os.environ['ROS_AUTOMATIC_DISCOVERY_RANGE'] = 'LOCALHOST'
# Participants announce themselves every 0.25 s, not every 3 s: a process matches the others
# within 0.4 s where a lost first exchange made it wait up to 3 s (the profile says why).
os.environ['FASTRTPS_DEFAULT_PROFILES_FILE'] = str(
    Path(__file__).resolve().parent.parent / 'config' / 'fast_discovery.xml')

import pytest  # noqa: E402 (after the environment is set, as rclpy reads it)

# Modules whose tests start executables as processes (or build with colcon): the system tier.
SYSTEM_MODULES = {'test_cli_refusals', 'test_hardening', 'test_launch', 'test_processes',
                  'test_demo', 'test_recorder', 'test_startup_refusals'}


# Modules whose system tests hold the wall clock to account (a rate, a push's length, a flood, a
# recording that must miss no message of a burst) or draw in software (the browser): they run
# alone on the machine, after the others. The other system tests wait on their processes, not on
# the clock, and run beside each other (make test: one worker per core).
# A test of another module that needs it is marked alone itself.
ALONE_MODULES = {'test_demo', 'test_hardening', 'test_recorder', 'test_sim_controls'}


TIERS = ('unit', 'ros', 'system')
# Fixtures that run nodes in-process: the ros tier.
IN_PROCESS = {'ros', 'simulated_body', 'simulated_body_factory'}


def pytest_configure(config) -> None:
    """Register the ``alone`` marker (the tiers' markers are in setup.cfg)."""
    config.addinivalue_line('markers', 'alone: a system or browser test that runs with nothing '
                                       'beside it (the wall clock, a burst, a browser)')


def pytest_collection_modifyitems(items) -> None:
    """
    Mark each test with its tier, and ``alone`` the system and browser tests that need the machine.

    system: its module starts processes; ros: it takes the ``ros`` fixture or a simulated body
    (a node in-process); unit: everything else (pure code). alone: a browser test, or a system
    test of a module in ALONE_MODULES.
    """
    for item in items:
        module = item.module.__name__.rpartition('.')[2]
        if not any(item.get_closest_marker(tier) for tier in TIERS):
            # Not marked by the test itself (a process test in a mostly in-process module).
            if module in SYSTEM_MODULES:
                item.add_marker(pytest.mark.system)
            elif IN_PROCESS & set(getattr(item, 'fixturenames', ())):
                item.add_marker(pytest.mark.ros)
            else:
                item.add_marker(pytest.mark.unit)
        if item.get_closest_marker('browser') or (item.get_closest_marker('system')
                                                  and module in ALONE_MODULES):
            item.add_marker(pytest.mark.alone)


def pytest_sessionfinish(session) -> None:
    """Close the browser the browser tier's pages shared (test_support/browser_page.py)."""
    browser_page = sys.modules.get('test_support.browser_page')
    if browser_page is not None:
        browser_page.close_browser()


def pytest_collection_finish(session) -> None:
    """Freeze what collection made: the cyclic collector's full passes never scan it again."""
    gc.freeze()


@pytest.fixture(autouse=True)
def collector_paused_in_alone_tests(request):
    """
    Pause the cyclic collector for a test marked alone; it runs again after it.

    A full pass of the collector in this process took up to 150 ms, longer than the node's
    catch-up bound (0.1 s): a node spun in this process on the wall clock (test_recorder's at
    200 Hz) dropped the ticks of that pause, and a 0.1 s push then covered too few of them.
    What a test creates is collected after it.
    """
    if request.node.get_closest_marker('alone') is None:
        yield
        return
    gc.disable()
    try:
        yield
    finally:
        gc.enable()


@pytest.fixture(scope='session')
def colcon_install(tmp_path_factory) -> Path:
    """
    Build the package with colcon into a temporary install, once a session; return its prefix.

    The tests that take it read the install (and run what is in it); none changes it.
    """
    base = tmp_path_factory.mktemp('colcon')
    bin_folder = Path(sys.executable).parent
    environment = {'PATH': f'{bin_folder}:/usr/bin:/bin', 'HOME': str(base),
                   'COLCON_HOME': str(base / 'colcon_home')}
    build = subprocess.run(
        [str(bin_folder / 'colcon'), '--log-base', str(base / 'log'), 'build', '--base-paths',
         str(Path(__file__).resolve().parent.parent), '--build-base', str(base / 'build'),
         '--install-base', str(base / 'install'), '--event-handlers', 'console_direct-'],
        capture_output=True, text=True, cwd=base, env=environment, timeout=300)
    assert build.returncode == 0, build.stdout + build.stderr
    return base / 'install' / 'mouse_constraint_ros'


@pytest.fixture
def ros():
    """Yield a ``RosHarness`` with its own context; shut it down afterwards."""
    from test_support.ros_harness import RosHarness
    harness = RosHarness()
    yield harness
    harness.shutdown()
