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

``mouse_view [--host HOST] [--port PORT]`` serves the web view of ``mouse_constraint`` in its
namespace (``--ros-args -r __ns:=/robot``) and prints the address to open. It binds the loopback
address unless ``--host`` names another, which it warns about in one line: whoever reaches that
address can drag the body and press the node's buttons. A busy port is taken as the next free
one (the printed address says which); ``--port 0`` asks the system for any.
"""

import argparse
import sys
from typing import List, Optional

import rclpy
from rclpy.experimental import EventsExecutor
from rclpy.signals import SignalHandlerOptions
from rclpy.utilities import remove_ros_args
import viser

from .node import MouseViewNode
from .scene import ViewScene
from ..timing.spin import spin_until, StopRequest

LOOPBACK = '127.0.0.1'
DEFAULT_PORT = 8080
# Where the camera starts (m, world): the shipped body hangs about 1 m up at the origin.
INITIAL_CAMERA, INITIAL_LOOK_AT = (1.2, -1.6, 1.4), (0.0, 0.0, 0.9)


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
    parser.add_argument('--port', type=int, default=DEFAULT_PORT,
                        help='port to serve on, the next free one if busy; 0: any '
                             '(default: %(default)s)')
    return parser


def host_warning(host: str) -> Optional[str]:
    """Return the one-line warning for a non-loopback ``host``, or None for the loopback."""
    if host in (LOOPBACK, 'localhost', '::1'):
        return None
    return (f'serving on {host}: anyone who reaches this address can drag the body and pause '
            'or reset the node (the page has no login)')


def page_address(host: str, port: int) -> str:
    """Return the address to open for a server bound to ``host``:``port``."""
    shown = LOOPBACK if host in ('0.0.0.0', '') else host
    return f'http://[{shown}]:{port}' if ':' in shown else f'http://{shown}:{port}'


def refuse_share_url(*_args, **_kwargs) -> None:
    """Refuse viser's share link: it would open a public tunnel to this view."""
    return None


def serve(host: str, port: int) -> viser.ViserServer:
    """
    Start the viser server on ``host``:``port`` serving the viewer only.

    The share button is hidden and a share request from a page is refused, so the view never
    opens viser's tunnel to the outside.
    """
    server = viser.ViserServer(host=host, port=port, label='mouse_constraint', verbose=False)
    server.request_share_url = refuse_share_url
    server.gui.configure_theme(show_share_button=False)
    server.initial_camera.position = INITIAL_CAMERA
    server.initial_camera.look_at = INITIAL_LOOK_AT
    return server


def main(args: Optional[List[str]] = None) -> int:
    """Serve the view until Ctrl-C, SIGTERM or SIGHUP; exit 0 then, 2 on bad arguments."""
    argv = sys.argv if args is None else args
    options = build_parser().parse_args(remove_ros_args(argv)[1:])
    rclpy.init(args=argv, signal_handler_options=SignalHandlerOptions.NO)
    server = node = None
    try:
        with StopRequest() as stop:
            server = serve(options.host, options.port)
            node = MouseViewNode(scene_factory=lambda parameters: ViewScene(server, parameters))
            warning = host_warning(options.host)
            if warning is not None:
                node.get_logger().warning(warning)
            print(f'mouse_view: open {page_address(options.host, server.get_port())} '
                  f'(viewing {node.target_node})', flush=True)
            executor = EventsExecutor(context=node.context)
            executor.add_node(node)
            spin_until(executor, stop)
    finally:
        if node is not None:
            node.destroy_node()
        if server is not None:
            server.stop()
        rclpy.try_shutdown()
    return 0


if __name__ == '__main__':
    sys.exit(main())
