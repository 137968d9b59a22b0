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
``mouse_view`` under faults and hostile clients: it refuses, bounds and drops, and never hangs.

An address it cannot serve on ends it with one line and exit 2; pages of other origins are
refused the websocket; a huge message closes its connection without the memory it asked for;
junk is logged in a throttled line, not a traceback per message; a client that stops answering
(a frozen browser) is dropped within ``DROP_SECONDS`` and its drag released. The clients
are raw websocket clients (``test_support.viser_client``), as a hostile page would write them.
"""

import signal
import socket
import subprocess
import threading
import time

import numpy as np
import pytest
from rclpy.parameter import Parameter

# mouse_view serves its page with viser (requirements/view.txt; no rosdep key: package.xml).
pytest.importorskip('viser', reason='mouse_view needs viser: pip install -r requirements/view.txt')
from websockets.exceptions import ConnectionClosedError, InvalidStatus

from mouse_constraint_ros.node.mouse_constraint_node import MouseConstraintNode
from mouse_constraint_ros.pointer.geometry import world_point
from mouse_constraint_ros.timing.spin import Interrupted, StopRequest
from mouse_constraint_ros.view import server as view_server
from mouse_constraint_ros.view.node import MouseViewNode
from mouse_constraint_ros.view.scene import ViewScene
from test_support import processes, viser_client
from test_support.viser_client import VIEW

AT_REST = {'gravity': [0.0, 0.0, 0.0], 'hold_initial_anchor': False}
# A message as large as viser itself takes (50 MB), as a hostile client sent six of.
HUGE = 50 * 1024 * 1024


def _run_view(*arguments: str) -> subprocess.CompletedProcess:
    return subprocess.run([str(VIEW), *arguments], capture_output=True, text=True, timeout=60,
                          env=processes.private_environment())


def _refusal(result: subprocess.CompletedProcess) -> str:
    """Return the one error line of a view that exited 2 at once, nothing on stdout."""
    assert result.returncode == 2, (result.stdout, result.stderr)
    assert 'Traceback' not in result.stderr and 'open http' not in result.stdout
    errors = [line for line in result.stderr.splitlines() if line.startswith('mouse_view:')]
    assert len(errors) == 1, result.stderr
    return errors[0]


@pytest.mark.system
@pytest.mark.parametrize('port', ['-1', '65536', '99999999'])
def test_a_port_out_of_range_is_a_usage_error(port):
    """A port outside 0 .. 65535 is refused by the argument parser, as --port abc is."""
    line = _refusal(_run_view('--port', port))
    assert line == f'mouse_view: error: argument --port: a port is 0 .. 65535, got {port}'


@pytest.mark.system
@pytest.mark.parametrize('host, reason', [
    ('10.255.255.1', 'Cannot assign requested address'),
    ('no.such.host.invalid', 'Name or service not known'),
])
def test_an_address_not_of_this_machine_ends_the_view_in_one_line(host, reason):
    """A host it cannot bind: one line naming it and why, exit 2, never a wait for ever."""
    line = _refusal(_run_view('--host', host, '--port', '8173'))
    assert line.startswith(f'mouse_view: cannot serve on {host}') and line.endswith(reason)


@pytest.mark.system
def test_the_last_port_busy_ends_the_view_in_one_line():
    """The last port busy: no next one to take, one line, exit 2."""
    with socket.socket() as busy:
        try:
            busy.bind(('127.0.0.1', view_server.HIGHEST_PORT))
        except OSError as error:
            pytest.skip(f'port {view_server.HIGHEST_PORT} is taken here: {error}')
        busy.listen()
        line = _refusal(_run_view('--port', str(view_server.HIGHEST_PORT)))
    assert line == ('mouse_view: cannot serve on 127.0.0.1: no free port from 65535 to 65535')


def test_a_stop_while_the_server_starts_ends_the_wait():
    """Ctrl-C while viser starts: the wait ends, and the server started late is stopped."""
    before = threading.active_count()
    stop = StopRequest()
    stop.signal = signal.SIGINT
    with pytest.raises(Interrupted):
        view_server.start('127.0.0.1', 0, stop=stop)
    # The abandoned server is stopped once started: every thread it ran ends.
    deadline = time.monotonic() + 30.0
    while threading.active_count() > before:
        assert time.monotonic() < deadline, threading.enumerate()
        time.sleep(0.05)


@pytest.fixture
def server():
    """Yield a viser server on a free loopback port, stopped afterwards."""
    started = view_server.start('127.0.0.1', 0, allowed=['http://robot.local:8080'])
    yield started
    started.stop()


@pytest.mark.parametrize('origin', [
    'http://evil.example', 'null', 'https://127.0.0.1.evil.example', 'file://'])
def test_a_page_of_another_origin_is_refused_the_websocket(server, origin):
    """A web site or a file:// page (Origin: null) cannot open the view's websocket."""
    with pytest.raises(InvalidStatus) as refused:
        viser_client.connect(server.get_port(), origin=origin).close()
    assert refused.value.response.status_code == 403
    assert b'--allow-origin' in refused.value.response.body


def test_the_views_own_pages_and_clients_without_an_origin_are_taken(server):
    """Its own page by any loopback name, an allowed origin, and a non-browser client."""
    port = server.get_port()
    for host, origin in (('127.0.0.1', f'http://127.0.0.1:{port}'),
                         ('localhost', f'http://localhost:{port}'),
                         ('127.0.0.1', 'http://robot.local:8080'), ('127.0.0.1', None)):
        with viser_client.connect(port, host=host, origin=origin) as client:
            assert client.recv(timeout=10)  # the scene comes


@pytest.mark.parametrize('origin, host, taken', [
    ('http://192.168.1.5:8080', '192.168.1.5:8080', True),  # its own page on the LAN
    ('http://[::1]:8080', '[::1]:8080', True),
    ('http://myhost:8080', 'myhost:8080', True),  # this machine's name
    ('http://evil.example:8080', 'evil.example:8080', False),  # DNS rebinding
    ('http://127.0.0.1:9999', '127.0.0.1:8080', False),  # another port's page
    ('ftp://127.0.0.1:8080', '127.0.0.1:8080', False),
    ('http://127.0.0.1:8080', None, False),
])
def test_an_origin_is_taken_only_for_the_address_it_opened(origin, host, taken):
    """The page's origin must be the websocket's own address, by IP or this machine's name."""
    assert view_server.origin_taken(origin, host, names={'localhost', 'myhost'}) is taken


def test_a_huge_message_closes_its_connection(server):
    """A message over MAX_MESSAGE_BYTES: the connection is closed as too big (1009)."""
    with viser_client.connect(server.get_port()) as client:
        client.recv(timeout=10)
        with pytest.raises(ConnectionClosedError) as closed:
            client.send(bytes(view_server.MAX_MESSAGE_BYTES + 1))
            while True:
                client.recv(timeout=10)
    assert closed.value.rcvd.code == 1009


@pytest.mark.system
def test_hostile_clients_neither_grow_the_view_nor_flood_its_log():
    """Six 50 MB messages keep the view's memory; forty junk messages log a few short lines."""
    with processes.ChildProcess([str(VIEW), '--port', '0'],
                                environment=processes.private_environment()) as view:
        port, _ = viser_client.wait_for_address(view)
        with viser_client.connect(port) as client:
            client.recv(timeout=10)
        before = processes.rss_bytes(view.pid)
        payload = bytes(HUGE)
        for _ in range(6):
            with pytest.raises(ConnectionClosedError):
                with viser_client.connect(port, max_size=None) as client:
                    client.send(payload)
                    while True:
                        client.recv(timeout=10)
        grown = processes.rss_bytes(view.pid) - before
        assert grown < 20 * 1024 * 1024, f'the view grew {grown / 2 ** 20:.0f} MiB'
        for _ in range(40):
            with pytest.raises(ConnectionClosedError):
                with viser_client.connect(port) as client:
                    client.send(b'\xc1 junk')  # 0xc1 is never valid msgpack
                    while True:
                        client.recv(timeout=10)
        # Its whole log once it has ended: every line of the forty, and of its stop.
        assert view.stop() == 0
        log = view.log()
        failures = [line for line in log.splitlines() if 'connection handler failed' in line]
        assert 1 <= len(failures) <= 2, log
        assert 'Traceback' not in log


def _nodes(ros, server):
    node = ros.add(MouseConstraintNode(context=ros.context, parameter_overrides=[
        Parameter(name, value=value) for name, value in AT_REST.items()]))
    view = ros.add(MouseViewNode(scene_factory=lambda p: ViewScene(server, p),
                                 context=ros.context))
    return node, view


def _ready(view: MouseViewNode) -> bool:
    return (view.scene.shown is not None and view.follower.parameters_known
            and view.target_publisher.get_subscription_count() > 0
            and all(c.service_is_ready() for c in view.node_services.clients.values()))


def test_a_frozen_browser_is_dropped_and_its_drag_released(ros, server):
    """A dragging client that stops answering: dropped and released within DROP_SECONDS."""
    node, view = _nodes(ros, server)
    client = viser_client.RawClient(server.get_port())
    client.send(viser_client.camera((0.0, -3.0, 1.0), (0.0, 0.0, 1.0)))
    try:
        assert viser_client.spin_reading(ros, client, lambda: _ready(view))
        grabbed = world_point(view.scene.shown, (0.1, -0.1, 0.02))
        pointer = np.add(grabbed, (0.0, 0.0, 0.2))
        client.send(viser_client.drag('start', start=grabbed, end=grabbed))
        client.send(viser_client.drag('update', start=grabbed, end=pointer))
        assert viser_client.spin_reading(ros, client, lambda: node.simulation.target is not None)
        client.read_for(1.0)  # a live client answers the pings: it stays held
        ros.spin_for(0.1)
        assert node.simulation.target is not None
        frozen = time.monotonic()
        assert ros.spin_until(lambda: node.simulation.target is None, timeout=30.0)
        released = time.monotonic() - frozen
        closing = client.closed_by_server(timeout=5.0)
    finally:
        client.close()
    assert closing is not None and closing.code == 1011  # keepalive ping timeout
    assert released < view_server.DROP_SECONDS + 1.0, released
