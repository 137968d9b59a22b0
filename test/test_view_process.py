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
``mouse_view`` as a process: where it listens, what it serves, its warning, how it ends.

The listening socket is read from /proc/net/tcp (the kernel's word on the bound address), the
page is fetched over HTTP, and the node is killed and started again under a running view.
"""

import re
import signal
import time
import urllib.request

import pytest

# mouse_view serves its page with viser (requirements/view.txt; no rosdep key: package.xml).
pytest.importorskip('viser', reason='mouse_view needs viser: pip install -r requirements/view.txt')
from test_support import processes, viser_client

pytestmark = pytest.mark.system

IPV6_ADDRESS = re.compile(r'mouse_view: open (http://\[::1\]:\d+) ')
# /proc/net/tcp's hex form of the bound addresses, and its LISTEN state.
LOOPBACK_HEX, ANY_HEX, LISTEN = '0100007F', '00000000', '0A'


def _environment():
    return processes.private_environment()


def _wait_for_line(view: processes.ChildProcess, text: str, *, count: int,
                   timeout: float = 60.0) -> None:
    deadline = time.monotonic() + timeout
    while view.log().count(text) < count:
        assert time.monotonic() < deadline, f'{text!r} not {count} times: {view.log()}'
        time.sleep(0.1)


def _listening_addresses(port: int):
    addresses = set()
    with open('/proc/net/tcp') as table:
        for line in list(table)[1:]:
            local, state = line.split()[1], line.split()[3]
            address, hex_port = local.split(':')
            if state == LISTEN and int(hex_port, 16) == port:
                addresses.add(address)
    return addresses


def test_it_binds_the_loopback_serves_the_viewer_and_ends_with_0():
    """Default host: 127.0.0.1 only; the page's index is served; no warning; SIGINT: exit 0."""
    with processes.ChildProcess([str(viser_client.VIEW), '--port', '0'],
                                environment=_environment()) as view:
        port, target = viser_client.wait_for_address(view)
        assert target == '/mouse_constraint'
        assert _listening_addresses(port) == {LOOPBACK_HEX}
        with urllib.request.urlopen(f'http://127.0.0.1:{port}/', timeout=10) as response:
            assert response.status == 200
            assert b'<html' in response.read().lower()
        assert 'serving on' not in view.log()
        assert view.stop() == 0


def test_another_host_is_warned_about_in_one_line():
    """--host 0.0.0.0 binds every address and says so once; a namespace is followed."""
    command = [str(viser_client.VIEW), '--host', '0.0.0.0', '--port', '0', '--ros-args', '-r',
               '__ns:=/robot']
    with processes.ChildProcess(command, environment=_environment()) as view:
        port, target = viser_client.wait_for_address(view)
        assert target == '/robot/mouse_constraint'
        assert _listening_addresses(port) == {ANY_HEX}
        warnings = [line for line in view.log().splitlines() if 'serving on 0.0.0.0' in line]
        assert len(warnings) == 1 and 'WARN' in warnings[0]
        view.process.send_signal(signal.SIGTERM)
        assert view.process.wait(timeout=10) == 0


def test_a_view_started_beside_a_running_node_finds_it_without_a_word_of_its_absence():
    """The node first, then the view: 'publishes on /pose', never 'no node' while discovering."""
    environment = _environment()
    node = processes.ChildProcess(processes.node_command(), environment=environment)
    try:
        _wait_for_line(node, 'Hz x', count=1)
        with processes.ChildProcess([str(viser_client.VIEW), '--port', '0'],
                                    environment=environment) as view:
            viser_client.wait_for_address(view)
            _wait_for_line(view, '/mouse_constraint publishes on /pose', count=1)
            assert 'no node' not in view.log()
            assert view.stop() == 0
    finally:
        node.close()


def test_every_ipv6_address_prints_an_address_that_opens():
    """--host ::: the printed address is the IPv6 loopback, and the page opens there."""
    command = [str(viser_client.VIEW), '--host', '::', '--port', '0']
    with processes.ChildProcess(command, environment=_environment()) as view:
        deadline = time.monotonic() + 30.0
        while not (match := IPV6_ADDRESS.search(view.log())):
            assert view.alive() and time.monotonic() < deadline, view.log()
            time.sleep(0.1)
        with urllib.request.urlopen(match.group(1), timeout=10) as response:
            assert response.status == 200
        assert view.stop() == 0


def test_the_view_outlives_a_node_that_restarts(tmp_path):
    """
    The node killed and started again under the view: each time it is lost and found.

    The node's DDS participant has a 3 s lease (``processes.SHORT_LEASE_PROFILE``): the view sees
    the killed node gone when its lease runs out, as with Fast DDS's default 20 s lease, sooner.
    """
    environment = _environment()
    node_environment = processes.short_lease_environment(tmp_path, environment)
    with processes.ChildProcess([str(viser_client.VIEW), '--port', '0'],
                                environment=environment) as view:
        port, _ = viser_client.wait_for_address(view)
        _wait_for_line(view, 'no node on /pose', count=1)
        for restart in range(2):
            node = processes.ChildProcess(processes.node_command(), environment=node_environment)
            _wait_for_line(view, '/mouse_constraint publishes on /pose', count=1 + restart)
            node.process.send_signal(signal.SIGKILL)
            node.process.wait(timeout=10)
            node.close()
            _wait_for_line(view, 'no node on /pose', count=2 + restart)
        assert view.alive(), view.log()
        with urllib.request.urlopen(f'http://127.0.0.1:{port}/', timeout=10) as response:
            assert response.status == 200
        assert 'Traceback' not in view.log()
        assert view.stop() == 0
