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
What the web view costs: ``mouse_view`` with a browser attached, the node with and without it.

One ``mouse_constraint_node`` (config/params.yaml as shipped: 1 kHz, pose and twist every tick)
runs throughout. Window 1: the node alone. Then ``mouse_view --port 0`` starts and Debian's
chromium (headless, SwiftShader WebGL, 1280x720, driven by Playwright) opens its page; after
the first frames and a warm-up, window 2: the node, the view and the browser together. CPU is
utime + stime of all of a process's threads over the window, in % of one core (the browser's
is summed over its processes); the push rate is the websocket frames the page received per
second (poses, at most 60 a second, and the panel's numbers, 5 a second).

Standalone: ``python -m bench.view_cost [--quick]`` prints the section as JSON.
"""

import os
from pathlib import Path
import re
import sys
import time

from bench import ros_process

from test_support import processes

SECONDS = 10.0
QUICK_SECONDS = 3.0
WARMUP = 2.0
# After the page's first websocket frame: SwiftShader's first render and the scene's replay.
PAGE_WARMUP = 5.0
CHROMIUM = '/usr/bin/chromium'
CHROMIUM_ARGS = ['--headless', '--no-sandbox', '--disable-gpu', '--disable-background-networking',
                 '--disable-component-update', '--disable-sync', '--no-first-run']
ADDRESS = re.compile(r'mouse_view: open (http://\S+)')
PARAMS_FILE = ros_process.ROOT / 'config' / 'params.yaml'


def _descendants(pid: int, word: str):
    """Return the pids below ``pid`` whose command line contains ``word``."""
    children = {}
    for entry in Path('/proc').iterdir():
        if not entry.name.isdigit():
            continue
        try:
            fields = (entry / 'stat').read_text().rsplit(')', 1)[1].split()
            command = (entry / 'cmdline').read_bytes().decode(errors='replace')
        except OSError:
            continue
        children.setdefault(int(fields[1]), []).append((int(entry.name), command))
    found, stack = [], [pid]
    while stack:
        for child, command in children.get(stack.pop(), []):
            stack.append(child)
            if word in command:
                found.append(child)
    return found


def _cpu(pids) -> float:
    total = 0.0
    for pid in pids:
        try:
            total += processes.cpu_seconds(pid)
        except OSError:
            pass
    return total


def _window(pids_by_name, seconds: float, wait=time.sleep) -> dict:
    start_wall, start = time.monotonic(), {n: _cpu(p) for n, p in pids_by_name.items()}
    wait(seconds)
    wall = time.monotonic() - start_wall
    return {name: 100.0 * (_cpu(pids) - start[name]) / wall
            for name, pids in pids_by_name.items()}, wall


def _address(view: processes.ChildProcess, timeout: float = 30.0) -> str:
    deadline = time.monotonic() + timeout
    while time.monotonic() < deadline:
        match = ADDRESS.search(view.log())
        if match:
            return match.group(1)
        if not view.alive():
            raise RuntimeError(f'mouse_view exited: {view.log()[-2000:]}')
        time.sleep(0.1)
    raise RuntimeError(f'mouse_view printed no address in {timeout:g} s')


def run(quick: bool = False) -> dict:
    """Return the section: the node alone, then the node, the view and a browser."""
    began = time.perf_counter()
    seconds = QUICK_SECONDS if quick else SECONDS
    if not os.access(CHROMIUM, os.X_OK):
        return {'title': 'The web view', 'text': f'Not measured: no {CHROMIUM}.', 'rows': [],
                'elapsed_s': time.perf_counter() - began}
    from playwright.sync_api import sync_playwright
    node_command = processes.node_command('--params-file', str(PARAMS_FILE))
    with ros_process.start(node_command) as node:
        time.sleep(WARMUP)
        alone, _ = _window({'node': [node.pid]}, seconds)
        view_command = [str(processes.BIN / 'mouse_view'), '--port', '0']
        with ros_process.start(view_command) as view, sync_playwright() as playwright:
            browser = playwright.chromium.launch(executable_path=CHROMIUM, args=CHROMIUM_ARGS)
            try:
                page = browser.new_page(viewport={'width': 1280, 'height': 720})
                frames = []
                page.on('websocket', lambda socket: socket.on(
                    'framereceived', lambda _payload: frames.append(time.monotonic())))
                page.goto(_address(view), timeout=60_000)
                deadline = time.monotonic() + 60.0
                while not frames and time.monotonic() < deadline:
                    page.wait_for_timeout(100)
                page.wait_for_timeout(1e3 * PAGE_WARMUP)
                chromium = _descendants(os.getpid(), 'chromium')
                counted = len(frames)
                shared, wall = _window(
                    {'node': [node.pid], 'view': [view.pid], 'browser': chromium}, seconds,
                    wait=lambda s: page.wait_for_timeout(1e3 * s))
                push_rate = (len(frames) - counted) / wall
            finally:
                browser.close()
            if not view.alive() or not node.alive():
                raise RuntimeError('the node or the view exited during the run')
    load = os.getloadavg()[0]
    rows = [
        {'window': 'node alone', 'node_cpu': alone['node'], 'load': load},
        {'window': 'node + mouse_view + one browser', 'node_cpu': shared['node'],
         'view_cpu': shared['view'], 'browser_cpu': shared['browser'],
         'push_rate': push_rate, 'load': load},
    ]
    figures = {'view_cpu_pct': shared['view'], 'node_cpu_alone_pct': alone['node'],
               'node_cpu_with_view_pct': shared['node'], 'browser_cpu_pct': shared['browser'],
               'frames_per_s': push_rate}
    return {
        'title': 'The web view: mouse_view and the node, with one headless browser',
        'text': (f'Command: `python -m bench.view_cost`. One node (config/params.yaml, 1 kHz) '
                 f'throughout; {seconds:g} s windows: the node alone, then with `mouse_view` and '
                 'headless chromium (SwiftShader) on its page.'),
        'columns': [['window', 'window', ''], ['node_cpu', 'node CPU (% core)', '.1f'],
                    ['view_cpu', 'mouse_view CPU (% core)', '.1f'],
                    ['browser_cpu', 'browser CPU (% core)', '.1f'],
                    ['push_rate', 'frames to the page (1/s)', '.1f'],
                    ['load', 'load', '.1f']],
        'rows': rows,
        'notes': [
            f'mouse_view: {shared["view"]:.1f} % of a core with one browser; the node '
            f'{alone["node"]:.1f} % alone, {shared["node"]:.1f} % with the view subscribed to '
            'its pose and twist (sent at 1 kHz, read at most every 4 ms).',
            f'The page received {push_rate:.1f} websocket frames a second: the poses, at most 60 '
            'a second, and the panel; viser sends what was queued together in one frame.',
            f'The browser: {shared["browser"]:.1f} % of a core, rendering with SwiftShader '
            '(software WebGL) on the same cores; a machine with a GPU renders there.',
        ],
        'figures': figures,
        'elapsed_s': time.perf_counter() - began,
    }


if __name__ == '__main__':
    import json
    print(json.dumps(run(quick='--quick' in sys.argv), indent=1, default=str))
