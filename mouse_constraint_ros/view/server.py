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
The view's web server (viser's): a start that cannot hang, and a websocket that keeps to itself.

viser binds its port in a thread of its own and waits for it without a bound: a port out of
range, a busy last port or an address not of this machine killed that thread and left the view
waiting for ever, deaf to Ctrl-C. ``start`` binds the address itself first (``free_port``:
the port, or the next free one, as viser would take it), refuses in one line what cannot be
served (``ServeError``), and waits for viser in a way a stop request ends.

viser's websocket takes messages of up to 50 MB from any page, keeps a silent client for some
40 s, and prints a traceback for each malformed message. The view's own messages are small, so
``start`` serves it with:

- ``MAX_MESSAGE_BYTES`` per message: a larger one closes that connection (six clients sending
  50 MB lists had taken the view to gigabytes);
- the handshake's ``Origin`` limited to the view's own page (``origin_taken``) and those
  allowed with ``--allow-origin``: a page from elsewhere (a web site, a ``file://`` page) that
  opened the view's websocket could drag the body; a client with no Origin (not a browser) is
  taken;
- a keepalive ping every ``PING_PERIOD``: a client that does not answer within
  ``ANSWER_SECONDS`` (a frozen browser) is dropped within ``DROP_SECONDS`` (viser's websocket
  keeps it some 40 s), and a drag it held ends as a release would (viser ends the drags of a
  client it loses);
- the websocket library's failure logs throttled to one short line per ``LOG_PERIOD``.

The options go to websockets' ``serve`` through a wrapper installed while viser starts its
server (viser has no hook for them), and removed once it has.
"""

import contextlib
import errno
import http
import ipaddress
import logging
import socket
import threading
import time
from typing import Collection, Iterator, Optional, Set, TYPE_CHECKING
import urllib.parse

from ..inputs.throttle import Throttle
from ..timing.spin import Interrupted, StopRequest

if TYPE_CHECKING:
    import viser

# The largest message a page may send (bytes): the view's are a few hundred.
MAX_MESSAGE_BYTES = 256 * 1024
# A keepalive ping this often (s); a client that does not answer one within ANSWER_SECONDS is
# dropped, its close awaited CLOSE_SECONDS at most: a frozen page is let go within DROP_SECONDS.
PING_PERIOD, ANSWER_SECONDS, CLOSE_SECONDS = 0.5, 1.0, 0.5
DROP_SECONDS = PING_PERIOD + ANSWER_SECONDS + CLOSE_SECONDS
# How long viser may take to start its server (s), and how often a stop request is looked at.
START_SECONDS, STOP_POLL = 20.0, 0.05
# One log line per reason at most this often (s).
LOG_PERIOD = 2.0
# Where the camera starts (m, world): the shipped body hangs about 1 m up at the origin.
INITIAL_CAMERA, INITIAL_LOOK_AT = (1.2, -1.6, 1.4), (0.0, 0.0, 0.9)
HIGHEST_PORT = 65535
# The thread that starts viser's server.
START_THREAD = 'mouse_view start'


class ServeError(Exception):
    """The view cannot serve: the message says where and why, in one line."""


def free_port(host: str, port: int) -> int:
    """
    Return the port to serve on: ``port`` or the next free one (0: any, the system's choice).

    :raises ServeError: the host is no address of this machine, or no port is free.
    """
    try:
        family, kind, _, _, address = socket.getaddrinfo(
            host, None, type=socket.SOCK_STREAM, flags=socket.AI_PASSIVE)[0]
    except (socket.gaierror, UnicodeError) as error:
        raise ServeError(f'{host}: {getattr(error, "strerror", None) or error}') from None
    for candidate in (range(port, HIGHEST_PORT + 1) if port else (0,)):
        with socket.socket(family, kind) as probe:
            # As asyncio's server binds on Unix: a port in TIME_WAIT is free.
            probe.setsockopt(socket.SOL_SOCKET, socket.SO_REUSEADDR, 1)
            try:
                probe.bind((address[0], candidate, *address[2:]))
            except OSError as error:
                if error.errno == errno.EADDRINUSE:
                    continue
                raise ServeError(f'{host} port {candidate}: {error.strerror}') from None
            return candidate
    raise ServeError(f'{host}: no free port from {port} to {HIGHEST_PORT}')


def origin_taken(origin: Optional[str], host: Optional[str], *, names: Collection[str],
                 allowed: Collection[str] = ()) -> bool:
    """
    Return whether a websocket handshake with this ``Origin`` and ``Host`` header is taken.

    Taken: no Origin (a client that is not a browser: no page can open it), an origin in
    ``allowed``, or the view's own page: the page's origin is the address the websocket is
    opened on (``Host``), and that address is an IP address or one of ``names`` (this machine's
    names). A page from elsewhere (a web site, a ``file://`` page, whose Origin is ``null``) is
    refused, and so is a name that is not this machine's, which a page could have pointed at it
    (DNS rebinding).
    """
    if origin is None or origin in allowed:
        return True
    page = urllib.parse.urlsplit(origin)
    if page.scheme not in ('http', 'https') or host is None:
        return False
    if page.netloc.lower() != host.lower():
        return False
    name = page.hostname or ''
    with contextlib.suppress(ValueError):
        ipaddress.ip_address(name)
        return True
    return name in names


def machine_names(host: str) -> Set[str]:
    """Return the names a page of the view may be opened by: loopback, this machine, ``host``."""
    return {'localhost', host.lower(), socket.gethostname().lower(), socket.getfqdn().lower()}


class _ThrottledLog(logging.Filter):
    """A logging filter: one line per kind of record per LOG_PERIOD, without its traceback."""

    def __init__(self) -> None:
        super().__init__()
        self._line = ''
        self._throttle = Throttle(self._keep, period=LOG_PERIOD)

    def _keep(self, line: str) -> None:
        self._line = line

    def filter(self, record: logging.LogRecord) -> bool:  # noqa: A003 (logging's name)
        """Let the record through, shortened, unless one of its kind just went."""
        message = record.getMessage()
        exception = record.exc_info[1] if record.exc_info else None
        text = message if exception is None else (
            f'{message}: {type(exception).__name__}: {exception}')
        if not self._throttle(f'{message} {type(exception).__name__}', lambda: text):
            return False
        record.msg, record.args = self._line, ()
        record.exc_info = record.exc_text = None
        return True


@contextlib.contextmanager
def _guarded_websockets(host: str, allowed: Collection[str]) -> Iterator[None]:
    """Serve websockets with the view's bounds while viser starts (see the module)."""
    import websockets.asyncio.server  # with viser, when the server starts: not for --help
    original = websockets.asyncio.server.serve
    names = machine_names(host)

    def serve(handler, address, port, *, process_request=None, **options):
        def guarded(connection, request):
            headers = request.headers
            if headers.get('Upgrade', '').lower() == 'websocket' and not origin_taken(
                    headers.get('Origin'), headers.get('Host'), names=names, allowed=allowed):
                return connection.respond(
                    http.HTTPStatus.FORBIDDEN,
                    'mouse_view takes its websocket from its own page only '
                    '(mouse_view --allow-origin ORIGIN takes another)\n')
            return None if process_request is None else process_request(connection, request)

        options.update(max_size=MAX_MESSAGE_BYTES, ping_interval=PING_PERIOD,
                       ping_timeout=ANSWER_SECONDS, close_timeout=CLOSE_SECONDS)
        return original(handler, address, port, process_request=guarded, **options)

    websockets.asyncio.server.serve = serve
    try:
        yield
    finally:
        websockets.asyncio.server.serve = original


def refuse_share_url(*_args, **_kwargs) -> None:
    """Refuse viser's share link: it would open a public tunnel to this view."""
    return None


def _viser_server(host: str, port: int, allowed: Collection[str]) -> 'viser.ViserServer':
    import viser  # when the server starts: not for --help
    with _guarded_websockets(host, allowed):
        server = viser.ViserServer(host=host, port=port, label='mouse_constraint',
                                   verbose=False)
    logger = logging.getLogger('websockets.server')
    if not any(isinstance(f, _ThrottledLog) for f in logger.filters):
        logger.addFilter(_ThrottledLog())
    server.request_share_url = refuse_share_url
    server.gui.configure_theme(show_share_button=False)
    server.initial_camera.position = INITIAL_CAMERA
    server.initial_camera.look_at = INITIAL_LOOK_AT
    return server


def start(host: str, port: int, *, allowed: Collection[str] = (),
          stop: Optional[StopRequest] = None,
          timeout: float = START_SECONDS) -> 'viser.ViserServer':
    """
    Start the viser server on ``host``:``port`` (or the next free port), the viewer only.

    The share button is hidden and a share request from a page refused: the view never opens
    viser's tunnel to the outside.

    :param allowed: Origin headers taken besides the view's own (``--allow-origin``).
    :param stop: a stop request that ends the wait (Ctrl-C while the server starts).
    :raises ServeError: it cannot serve there (why, in one line).
    :raises Interrupted: a stop was requested while it started.
    """
    port = free_port(host, port)
    started: dict = {}
    done, lock = threading.Event(), threading.Lock()

    def run() -> None:
        try:
            server = _viser_server(host, port, allowed)
        except BaseException as error:  # Handed to the waiting thread.
            started['error'] = error
            server = None
        with lock:
            started.setdefault('server', server)
            done.set()
        if started['server'] is not server:  # The wait was given up: no one will stop it.
            server.stop()

    threading.Thread(target=run, name=START_THREAD, daemon=True).start()
    deadline = time.monotonic() + timeout
    while not done.is_set():
        late = None
        if stop:
            late = Interrupted(stop.signal)
        elif time.monotonic() > deadline:
            late = ServeError(f'{host} port {port}: the server did not start in {timeout:g} s')
        if late is not None:
            with lock:
                if not done.is_set():
                    started['server'] = None
                    raise late
        done.wait(STOP_POLL)
    if 'error' in started:
        error = started['error']
        raise ServeError(f'{host} port {port}: {error}') from error
    return started['server']
