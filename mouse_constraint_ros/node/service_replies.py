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
What the node's services answer: ``~/pause``, ``~/step``, ``~/reset`` and ``~/release``.

Each reply says what happened, or why nothing did, in one line a user reads in
``ros2 service call``'s output (and the browser view's panel). ``~/step`` is refused while the
physics runs (a step between timer ticks would be a tick off the grid), while a simulated
clock has not started (there is no time to stamp it with) and while the node's clock still reads
the latest tick's stamp (a /clock that stands still: the step would repeat the stamp). Times
are the simulated time, the seconds the body has been stepped since start, to the microsecond:
the node's clock may read seconds since 1970, which say nothing at a glance. Plain Python only.
"""

from typing import Optional, Sequence


def simulated(seconds: float) -> str:
    """Return a simulated time as the replies show it: '12.345678 s simulated'."""
    return f'{seconds:.6f} s simulated'


def pause_reply(pause: bool, paused: bool, simulated_s: float) -> str:
    """
    Return the reply to ``~/pause`` with ``pause`` (true: pause) while ``paused`` or not.

    :param simulated_s: the simulated time now (s).
    """
    if pause == paused:
        return 'already paused' if pause else 'already running'
    return f'{"paused at" if pause else "running from"} {simulated(simulated_s)}'


def step_refusal(paused: bool, waiting_for: Optional[str],
                 stands_at: Optional[int] = None) -> Optional[str]:
    """
    Return why ``~/step`` cannot run now, or None when it can.

    :param paused: whether the physics is paused.
    :param waiting_for: what the node's clock waits for (``'/clock on <topic>'``), or None.
    :param stands_at: the node's time (ns) when its clock still reads the latest tick's stamp
        (a /clock that stands still), or None.
    """
    if not paused:
        return ('running: ~/step advances a paused simulation by one tick; pause it first '
                '(~/pause with data: true)')
    if waiting_for is not None:
        return f'waiting for {waiting_for}: no time to stamp a step with'
    if stands_at is not None:
        return (f"the node's clock stands at {stands_at * 1e-9:.9f} s, the stamp of the latest "
                'tick: a step would publish a second state of that stamp; step once the clock '
                'moves on')
    return None


def step_reply(dt: float, simulated_s: float) -> str:
    """Return the reply to a ``~/step`` that ran one tick of ``dt`` seconds, to ``simulated_s``."""
    return f'one tick of {dt:g} s, to {simulated(simulated_s)}'


def reset_refusal(configured_anchor: Sequence[float], reason: str) -> str:
    """Return why ``~/reset`` changed nothing: the configured anchor could not be restored."""
    return (f'cannot restore the configured anchor {list(configured_anchor)}: {reason}; '
            'nothing reset')


def reset_reply(hold_initial_anchor: bool) -> str:
    """Return the reply to a ``~/reset`` that restored the initial state."""
    return 'back to the initial state' + (
        ', anchor held where it starts' if hold_initial_anchor else ', no target')


def release_reply(had_target: bool) -> str:
    """Return the reply to ``~/release``: whether there was a target to let go of."""
    return 'released' if had_target else 'already free'
