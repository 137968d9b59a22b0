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
Raw websocket clients of the web view, as a hostile page or a frozen browser would be.

``wait_for_address`` reads the port a ``mouse_view`` process serves on from its log.

``connect`` opens the view's websocket as viser's page does (its subprotocol), with any Origin
header; ``RawClient`` speaks the protocol by hand (websockets' sans-I/O client on a plain
socket), so a test decides when it reads, and so when it answers the server's pings: a client
that stops reading is a browser frozen by SIGSTOP.
"""

import re
import socket
import time
from typing import Callable, Optional, Tuple

import msgspec
import viser
from viser import _messages
from websockets.client import ClientProtocol
from websockets.frames import Frame
from websockets.protocol import State
from websockets.sync.client import ClientConnection, connect as websocket_connect
from websockets.typing import Subprotocol
from websockets.uri import parse_uri

from test_support import processes

SUBPROTOCOL = Subprotocol(f'viser-v{viser.__version__}')
VIEW = processes.BIN / 'mouse_view'
# The line mouse_view prints when it serves on the loopback: its port and the node it views.
ADDRESS = re.compile(r'mouse_view: open http://127\.0\.0\.1:(\d+) \(viewing (\S+)\)')


def wait_for_address(view: processes.ChildProcess, timeout: float = 30.0) -> Tuple[int, str]:
    """Return the port and the viewed node a ``mouse_view`` process printed, once it has."""
    deadline = time.monotonic() + timeout
    while time.monotonic() < deadline:
        match = ADDRESS.search(view.log())
        if match:
            return int(match.group(1)), match.group(2)
        assert view.alive(), view.log()
        time.sleep(0.1)
    raise AssertionError(f'mouse_view printed no address in {timeout:g} s: {view.log()}')


def encode(message: _messages.Message) -> bytes:
    """Return ``message`` as the page sends it (msgpack)."""
    return msgspec.msgpack.encode(message.as_serializable_dict())


def camera(position, look_at) -> bytes:
    """Return the page's camera message: viser takes a client as connected after the first."""
    return encode(_messages.ViewerCameraMessage(
        wxyz=(1.0, 0.0, 0.0, 0.0), position=tuple(position), fov=1.0, near=0.01, far=100.0,
        image_height=720, image_width=1280, look_at=tuple(look_at), up_direction=(0.0, 0.0, 1.0)))


def drag(phase: str, *, start, end, name: str = '/body') -> bytes:
    """Return the page's message for a left drag of scene node ``name`` (world points, m)."""
    return encode(_messages.SceneNodeDragMessage(
        phase=phase, name=name, instance_index=None, start_position=tuple(start),
        start_screen_pos=(640.0, 360.0), end_position=tuple(end),
        end_screen_pos=(650.0, 350.0), button='left', modifier=None))


def connect(port: int, *, host: str = '127.0.0.1', origin: Optional[str] = None,
            **options) -> ClientConnection:
    """Open the view's websocket at ``host`` as its page would, with ``origin``."""
    return websocket_connect(f'ws://{host}:{port}/', origin=origin,
                             subprotocols=[SUBPROTOCOL], compression=None, open_timeout=10,
                             proxy=None, **options)


class RawClient:
    """
    A websocket client that reads only when told: it answers pings only while it reads.

    :param port: the view's port on the loopback.
    """

    def __init__(self, port: int) -> None:
        """Open the socket and do the handshake."""
        self.protocol = ClientProtocol(parse_uri(f'ws://127.0.0.1:{port}/'),
                                       subprotocols=[SUBPROTOCOL])
        self.socket = socket.create_connection(('127.0.0.1', port), timeout=10.0)
        self.protocol.send_request(self.protocol.connect())
        self._flush()
        while self.protocol.state is State.CONNECTING:
            self._receive()
        if self.protocol.handshake_exc is not None:
            raise self.protocol.handshake_exc

    def _flush(self) -> None:
        for data in self.protocol.data_to_send():
            if data:
                self.socket.sendall(data)

    def _receive(self) -> bool:
        data = self.socket.recv(1 << 16)
        if data:
            self.protocol.receive_data(data)
        else:
            self.protocol.receive_eof()
        self.protocol.events_received()
        self._flush()  # the pongs the protocol queued
        return bool(data)

    def send(self, payload: bytes) -> None:
        """Send one binary message."""
        self.protocol.send_binary(payload)
        self._flush()

    def read_for(self, seconds: float) -> None:
        """Read (and so answer pings) for ``seconds``."""
        deadline = time.monotonic() + seconds
        while time.monotonic() < deadline and self.protocol.state is State.OPEN:
            self.socket.settimeout(max(deadline - time.monotonic(), 1e-3))
            try:
                self._receive()
            except TimeoutError:
                break

    def closed_by_server(self, timeout: float) -> Optional[Frame]:
        """
        Read what the server sent while frozen, up to its close; return its close frame.

        :returns: None when the connection is still open after ``timeout`` seconds.
        """
        self.socket.settimeout(timeout)
        try:
            while self.protocol.state is State.OPEN:
                # Data only: no pong goes out, as from a frozen page.
                data = self.socket.recv(1 << 16)
                if not data:
                    break
                self.protocol.receive_data(data)
        except (TimeoutError, ConnectionError):
            pass
        return self.protocol.close_rcvd

    def close(self) -> None:
        """Close the socket."""
        self.socket.close()


def spin_reading(ros, client: RawClient, condition: Callable[[], bool], *,
                 timeout: float = 30.0) -> bool:
    """
    Spin ``ros`` (a RosHarness) and read ``client`` in turns until ``condition()`` holds.

    The timeout is generous: a wait that holds returns at once, and on a machine busy with a
    parallel test run discovery and the first frames can take many seconds.
    """
    deadline = time.monotonic() + timeout
    while not condition():
        if time.monotonic() > deadline:
            return False
        ros.spin_for(0.01)
        client.read_for(0.01)
    return True
