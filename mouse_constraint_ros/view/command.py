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
The ``mouse_view`` command: the page on http://127.0.0.1:8080, until Ctrl-C.

``mouse_view [--host HOST] [--port PORT] [--allow-origin URL]`` serves the web view of
``mouse_constraint`` in its namespace (``--ros-args -r __ns:=/robot``) and prints the address
to open. It binds the loopback address unless ``--host`` names another, which it warns about in
one line: whoever reaches that address can drag the body and press the node's buttons. A busy
port is taken as the next free one (the printed address says which); ``--port 0`` asks the
system for any. Pages of other origins are refused the websocket unless ``--allow-origin``
names them (``server``). An address it cannot serve on is one error line and exit 2, as a bad
argument is.
"""

import argparse
import sys
from typing import List, Optional

import rclpy
from rclpy.signals import SignalHandlerOptions
from rclpy.utilities import remove_ros_args

from .node import MouseViewNode
from .server import HIGHEST_PORT, ServeError, start
from ..timing.spin import Interrupted, NodeRun

LOOPBACK = '127.0.0.1'
DEFAULT_PORT = 8080
# The exit status of a bad argument (argparse's), and of an address the view cannot serve on.
USAGE_ERROR = 2


def _port(text: str) -> int:
    value = int(text)
    if not 0 <= value <= HIGHEST_PORT:
        raise argparse.ArgumentTypeError(f'a port is 0 .. {HIGHEST_PORT}, got {text}')
    return value


def build_parser() -> argparse.ArgumentParser:
    """Return the command's argument parser; every option's help names its default."""
    parser = argparse.ArgumentParser(
        prog='mouse_view',
        description='Serve the web view of mouse_constraint: the body in a browser, dragged '
                    'with the mouse.',
        epilog='open the printed address in a browser: press on the body and drag it; '
               'add --ros-args -r __ns:=/robot to view /robot/mouse_constraint')
    parser.add_argument('--host', default=LOOPBACK,
                        help='address to bind (default: %(default)s, this machine only)')
    parser.add_argument('--port', type=_port, default=DEFAULT_PORT,
                        help='port to serve on, the next free one if busy; 0: any '
                             '(default: %(default)s)')
    parser.add_argument('--allow-origin', action='append', default=[], metavar='URL',
                        help='also take the websocket from pages of this origin, e.g. '
                             "http://robot.local:8080 (default: the view's own address only)")
    return parser


def host_warning(host: str) -> Optional[str]:
    """Return the one-line warning for a non-loopback ``host``, or None for the loopback."""
    if host in (LOOPBACK, 'localhost', '::1'):
        return None
    return (f'serving on {host}: anyone who reaches this address can drag the body and pause '
            'or reset the node (the page has no login)')


def page_address(host: str, port: int) -> str:
    """
    Return the address to open for a server bound to ``host``:``port``.

    Bound to every address, the view is opened on the loopback of the same family: asyncio
    binds ``::`` to IPv6 only.
    """
    shown = {'0.0.0.0': LOOPBACK, '': LOOPBACK, '::': '::1'}.get(host, host)
    return f'http://[{shown}]:{port}' if ':' in shown else f'http://{shown}:{port}'


def main(args: Optional[List[str]] = None) -> int:
    """Serve the view until Ctrl-C, SIGTERM or SIGHUP; exit 0 then, 2 on bad arguments."""
    argv = sys.argv if args is None else args
    options = build_parser().parse_args(remove_ros_args(argv)[1:])
    from .scene import ViewScene  # viser's page: not for --help
    rclpy.init(args=argv, signal_handler_options=SignalHandlerOptions.NO)
    with NodeRun() as run:
        try:
            server = start(options.host, options.port, allowed=options.allow_origin,
                           stop=run.stop)
        except ServeError as error:
            print(f'mouse_view: cannot serve on {error}', file=sys.stderr, flush=True)
            return USAGE_ERROR
        except Interrupted:
            return 0
        run.close(server.stop)
        node = run.node = MouseViewNode(
            scene_factory=lambda parameters: ViewScene(server, parameters))
        warning = host_warning(options.host)
        if warning is not None:
            node.get_logger().warning(warning)
        print(f'mouse_view: open {page_address(options.host, server.get_port())} '
              f'(viewing {node.target_node})', flush=True)
        return run.serve()


if __name__ == '__main__':
    sys.exit(main())
