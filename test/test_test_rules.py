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
CONTRIBUTING.md's rule for tests: no sleep waits for an event; a test waits on the event itself.

Every ``time.sleep`` (however imported) and Playwright's ``wait_for_timeout`` in test/ and
test_support/ is found by reading the modules' syntax trees; each must be in ``ALLOWED``, by
module, function and argument (one sleep each), with why it is not a wait for something: a
poll's interval between looks at an observable condition under a deadline, or the time that is
itself the case under test.
"""

import ast
from pathlib import Path
from typing import Dict, Iterator, Tuple

ROOT = Path(__file__).resolve().parent.parent
FOLDERS = ('test', 'test_support')

POLL = 'the interval of a poll on an observable condition, under a deadline'
# (module, function, the sleep's argument) -> why that sleep is not synchronisation.
ALLOWED: Dict[Tuple[str, str, str], str] = {
    ('test_support/browser_page.py', 'wait_for', '0.05'): POLL,
    ('test_support/viser_client.py', 'wait_for_address', '0.1'): POLL + ' (the printed address)',
    ('test/test_view_process.py', '_wait_for_line', '0.1'): POLL + ' (a log line)',
    ('test/test_view_process.py', 'test_every_ipv6_address_prints_an_address_that_opens',
     '0.1'): POLL + ' (the printed address)',
    ('test/test_view_faults.py', 'test_a_stop_while_the_server_starts_ends_the_wait', '0.05'):
        POLL + " (the server's threads ended)",
    ('test/test_makefile.py', 'wait', '0.02'): POLL + ' (waitpid, WNOHANG)',
    ('test/test_makefile.py', 'wait_until', '0.02'): POLL,
    ('test/test_startup_signals.py',
     'test_a_signal_during_start_up_exits_0_without_a_traceback', '0.001'):
        POLL + " (the node's signal handlers)",
    ('test/test_startup_signals.py',
     'test_a_signal_during_start_up_exits_0_without_a_traceback', 'delay'):
        'the parametrized delay before the signal: the moment of start-up under test',
    ('test/test_startup_signals.py', 'test_a_second_signal_soon_after_the_first_still_exits_0',
     'gap'): 'the parametrized gap between two signals: the case under test',
    ('test/test_ctl_robustness.py',
     'test_ctrl_c_while_the_command_starts_is_exit_130_without_a_traceback', '0.001'):
        POLL + ' (rclpy mapped)',
    ('test/test_ctl_robustness.py',
     'test_ctrl_c_while_the_command_starts_is_exit_130_without_a_traceback', 'delay'):
        'the parametrized delay before Ctrl-C: the moment of start-up under test',
    ('test/test_ctl_robustness.py', 'step', '1.5'):
        'a service that answers late: the slow node under test',
    ('test/test_loop_timer.py',
     'test_a_late_loop_call_runs_its_tick_before_the_messages_queued_meanwhile', '0.03'):
        "the loop's call made 30 ms late: the lateness under test",
    ('test/test_view_browser.py', '_shift_at_the_release_holds', '0.03'):
        'shift pressed 30 ms before the button is let go: the gesture under test',
    ('test_support/hardening_tools.py', 'flood_main', '0.0002'): 'pacing a stream at its rate',
}


def _is_sleep(call: ast.Call, time_names: set, sleep_names: set) -> bool:
    function = call.func
    if isinstance(function, ast.Attribute):
        if function.attr == 'wait_for_timeout':  # Playwright's sleep
            return True
        return (function.attr == 'sleep' and isinstance(function.value, ast.Name)
                and function.value.id in time_names)
    return isinstance(function, ast.Name) and function.id in sleep_names


def sleeps(source: str) -> Iterator[Tuple[str, str, int]]:
    """Yield (innermost function, the argument as written, line) of each sleep in ``source``."""
    tree = ast.parse(source)
    # The names time goes by (``import time``, ``import time as clock``), and its sleep's.
    time_names = {'time'} | {alias.asname or alias.name for node in ast.walk(tree)
                             if isinstance(node, ast.Import)
                             for alias in node.names if alias.name == 'time'}
    sleep_names = {alias.asname or alias.name for node in ast.walk(tree)
                   if isinstance(node, ast.ImportFrom) and node.module == 'time'
                   for alias in node.names if alias.name == 'sleep'}

    def visit(node: ast.AST, function: str) -> Iterator[Tuple[str, str, int]]:
        for child in ast.iter_child_nodes(node):
            if isinstance(child, (ast.FunctionDef, ast.AsyncFunctionDef)):
                yield from visit(child, child.name)
                continue
            if isinstance(child, ast.Call) and _is_sleep(child, time_names, sleep_names):
                argument = ', '.join(ast.unparse(a) for a in [*child.args, *child.keywords])
                yield function, argument, child.lineno
            yield from visit(child, function)
    yield from visit(tree, '<module>')


def found() -> Dict[Tuple[str, str, str], list]:
    """Return the lines of every sleep in test/ and test_support/, by (module, function, arg)."""
    places: Dict[Tuple[str, str, str], list] = {}
    for folder in FOLDERS:
        for path in sorted((ROOT / folder).rglob('*.py')):
            module = path.relative_to(ROOT).as_posix()
            for function, argument, line in sleeps(path.read_text()):
                places.setdefault((module, function, argument), []).append(line)
    return places


def test_no_test_sleeps_to_wait_for_an_event():
    """Every sleep in a test or its support is allowed, once, and says why it waits for nothing."""
    unexplained = sorted(f'{module}:{lines[-1]} ({function}: sleep({argument}))'
                         for (module, function, argument), lines in found().items()
                         if (module, function, argument) not in ALLOWED or len(lines) > 1)
    assert not unexplained, (
        'a sleep waits for an event: wait on the event instead (a message, a page state, a '
        f'file, a log line, a process state), or allow it here saying why: {unexplained}')


def test_every_allowed_sleep_is_still_there_and_says_why():
    """No entry outlives its sleep, and each names its reason."""
    places = found()
    assert not set(ALLOWED) - set(places), set(ALLOWED) - set(places)
    assert all(reason.strip() for reason in ALLOWED.values())


def test_the_finder_sees_each_way_of_sleeping():
    """``time.sleep``, a ``sleep`` imported from time (renamed too), Playwright's wait."""
    source = ('import time\nfrom time import sleep as nap\n'
              'def a():\n    time.sleep(1)\n'
              'def b(page):\n    def inner():\n        nap(1)\n    page.wait_for_timeout(500)\n'
              'time.sleep(2)\n'
              'def c(clock):\n    clock.sleep(1)\n    time.monotonic()\n')
    assert sorted(sleeps(source)) == [('<module>', '2', 9), ('a', '1', 4), ('b', '500', 8),
                                      ('inner', '1', 7)]


def test_the_finder_sees_time_imported_under_another_name():
    """``import time as clock``: ``clock.sleep`` is a sleep; another object's ``sleep`` is not."""
    source = ('import time as clock\n'
              'def a(timer):\n    clock.sleep(0.5)\n    timer.sleep(1)\n')
    assert list(sleeps(source)) == [('a', '0.5', 3)]
