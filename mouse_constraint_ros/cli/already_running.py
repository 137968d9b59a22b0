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
Whether a ``mouse_constraint`` node already runs in a namespace of this ROS domain.

``make demo`` starts its own node in the root namespace; another one there (``make run`` left
running) would take the demo's grab and targets and publish on the same topics. Before it
starts anything, the demo runs ``python -m mouse_constraint_ros.cli.already_running``, which
looks at the graph for up to ``DISCOVERY_SECONDS`` (a running node is seen at once when the
first discovery announcements meet, else at Fast DDS's next periodic one) and, when it sees
one, says so in one line, with its namespace and domain, and exits 1 at once.
"""

import argparse
import os
import sys
import time
from typing import List, Optional, Tuple

import rclpy
from rclpy.node import Node

from .exit_status import INTERRUPTED_STATUS
from ..wire.interface import NODE_NAME, node_name

DISCOVERY_SECONDS = 3.0
POLL_SECONDS = 0.05


def running(node: Node, *, namespace: str, seconds: float = DISCOVERY_SECONDS) -> List[str]:
    """
    Return the full names of the ``mouse_constraint`` nodes in ``namespace`` seen in the graph.

    :param node: a node of this domain to look with.
    :param namespace: the namespace to look in ('/' for the root).
    :param seconds: how long to look while none is seen.
    """
    deadline = time.monotonic() + seconds
    while True:
        found = _found(node.get_node_names_and_namespaces(), namespace)
        if found or time.monotonic() >= deadline:
            return found
        time.sleep(POLL_SECONDS)


def _found(nodes: List[Tuple[str, str]], namespace: str) -> List[str]:
    return sorted({node_name(space, name) for name, space in nodes
                   if name == NODE_NAME and space == namespace})


def main(argv: Optional[List[str]] = None) -> int:
    """Exit 1 with one line when a mouse_constraint runs in the namespace, else 0."""
    parser = argparse.ArgumentParser(
        prog='python -m mouse_constraint_ros.cli.already_running',
        description='Exit 1 when a mouse_constraint node already runs in NAMESPACE.')
    parser.add_argument('--namespace', default='/', help='the namespace (default: /)')
    parser.add_argument('--seconds', type=float, default=DISCOVERY_SECONDS,
                        help=f'how long to look (s, default {DISCOVERY_SECONDS:g})')
    arguments = parser.parse_args(argv)
    domain = os.environ.get('ROS_DOMAIN_ID') or '0'
    context = rclpy.Context()
    rclpy.init(args=[], context=context)
    try:
        node = Node('mouse_constraint_already_running', context=context)
        found = running(node, namespace=arguments.namespace, seconds=arguments.seconds)
        node.destroy_node()
    except KeyboardInterrupt:
        return INTERRUPTED_STATUS
    finally:
        rclpy.try_shutdown(context=context)
    if found:
        print(f'a mouse_constraint is already running: {", ".join(found)} in namespace '
              f'{arguments.namespace} on ROS_DOMAIN_ID {domain}; stop it (Ctrl-C in its '
              'terminal) or run in another domain (ROS_DOMAIN_ID=n)', file=sys.stderr)
        return 1
    return 0


if __name__ == '__main__':
    sys.exit(main())
