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
The mechanics of lockstep: a context that keeps to itself, an executor drained until idle.

``isolated_context`` initializes an rclpy context with automatic discovery off
(``ROS_AUTOMATIC_DISCOVERY_RANGE=OFF`` while rcl reads it, no static peers): its participant
finds no other, in this process or another, so two test processes on one machine never see
each other's ``/clock`` or ``target``, whatever their domain. Its own nodes match one another
at once.

``drain`` runs every callback that is ready, and the ones those make ready, until a pass finds
none: a message published in a callback is delivered within the same drain (the middleware
delivers to a reader of the same participant before ``publish`` returns). A coroutine that
waits on a future is resumed each pass without counting as progress. Wall time appears only
as a watchdog: a drain that never goes idle raises ``DrainTimeout`` naming what kept it busy.

``unmatched`` says which of a node's publishers, subscriptions and clients on another node's
topics and services have not matched them, and why where the QoS says (``wait_matched``).
"""

from collections import Counter
import os
import time
from typing import Iterator, List

import rclpy
from rclpy.context import Context
from rclpy.executors import Executor, ShutdownException, TimeoutException
from rclpy.node import Node
from rclpy.qos import qos_check_compatible, QoSCompatibility

DISCOVERY_RANGE = 'ROS_AUTOMATIC_DISCOVERY_RANGE'
STATIC_PEERS = 'ROS_STATIC_PEERS'


class DrainTimeout(AssertionError):
    """The executor did not go idle within the watchdog's wall time."""


class MatchTimeout(AssertionError):
    """A node's endpoints did not match the body's within the watchdog's wall time."""


def isolated_context(*, domain_id: int = None) -> Context:
    """
    Return an initialized rclpy context whose nodes discover nothing outside it.

    :param domain_id: the DDS domain (default: ``ROS_DOMAIN_ID`` or 0); with discovery off it
        separates nothing more, and any free one does.
    """
    context = Context()
    saved = {key: os.environ.get(key) for key in (DISCOVERY_RANGE, STATIC_PEERS)}
    os.environ[DISCOVERY_RANGE] = 'OFF'
    os.environ.pop(STATIC_PEERS, None)
    try:
        # No command line: the test runner's arguments are not ROS arguments.
        rclpy.init(args=[], context=context, domain_id=domain_id)
    finally:
        for key, value in saved.items():
            if value is None:
                os.environ.pop(key, None)
            else:
                os.environ[key] = value
    return context


def _entity_name(entity) -> str:
    for attribute in ('topic_name', 'srv_name'):
        name = getattr(entity, attribute, None)
        if name:
            return f'{type(entity).__name__} {name}'
    period = getattr(entity, 'timer_period_ns', None)
    if period is not None:
        return f'timer of {period * 1e-9:g} s'
    return type(entity).__name__


def drain(executor: Executor, *, timeout: float) -> int:
    """
    Run the ready callbacks of ``executor`` until none is ready; return how many ran.

    :param timeout: wall seconds after which a drain that still finds work raises.
    :raises DrainTimeout: the executor kept finding work for ``timeout`` seconds.
    :raises Exception: what a callback raised, as ``spin_once`` raises it.
    """
    deadline = time.monotonic() + timeout
    ran = 0
    # Coroutines resumed that still wait: resuming them again is no progress.
    waiting = set()
    busy = Counter()
    while True:
        progress = False
        try:
            while True:
                handler, entity, _node = executor.wait_for_ready_callbacks(timeout_sec=0.0)
                handler()
                error = handler.exception()
                if error is not None:
                    raise error
                key = id(handler)
                if handler.done():
                    waiting.discard(key)
                elif key in waiting:
                    continue
                else:
                    waiting.add(key)
                progress = True
                ran += 1
                busy[_entity_name(entity)] += 1
        except TimeoutException:
            pass
        except ShutdownException:
            return ran
        if not progress:
            return ran
        if time.monotonic() > deadline:
            names = ', '.join(f'{name} ({count})' for name, count in busy.most_common(3))
            raise DrainTimeout(f'the executor did not go idle in {timeout:g} s of wall time: '
                               f'{ran} callbacks ran, most often {names}')


def _matches(node: Node, body: Node) -> Iterator[tuple]:
    """Yield (what, matched, reason) for each endpoint of ``node`` on ``body``'s names."""
    body_subscriptions = {s.topic_name: s for s in body.subscriptions}
    body_publishers = {p.topic_name: p for p in body.publishers}
    for publisher in node.publishers:
        subscription = body_subscriptions.get(publisher.topic_name)
        if subscription is not None:
            yield (f'publisher on {publisher.topic_name}',
                   publisher.get_subscription_count() > 0,
                   _incompatible(publisher.qos_profile, subscription.qos_profile))
    for subscription in node.subscriptions:
        publisher = body_publishers.get(subscription.topic_name)
        if publisher is not None and not subscription.topic_name.endswith('/rosout'):
            yield (f'subscription to {subscription.topic_name}',
                   subscription.get_publisher_count() > 0,
                   _incompatible(publisher.qos_profile, subscription.qos_profile))
    services = {s.srv_name for s in body.services}
    for client in node.clients:
        if client.srv_name in services:
            yield f'client of {client.srv_name}', client.service_is_ready(), ''


def _incompatible(publisher_qos, subscription_qos) -> str:
    compatibility, reason = qos_check_compatible(publisher_qos, subscription_qos)
    return '' if compatibility == QoSCompatibility.OK else f' ({reason.strip()})'


def unmatched(node: Node, body: Node) -> List[str]:
    """Return what of ``node`` on ``body``'s topics and services has not matched yet."""
    return [what + reason for what, matched, reason in _matches(node, body) if not matched]


def wait_matched(executor: Executor, node: Node, body: Node, *, timeout: float,
                 drain_timeout: float) -> None:
    """
    Drain ``executor`` until ``node``'s endpoints on ``body``'s names have matched.

    :raises MatchTimeout: naming each endpoint still unmatched after ``timeout`` wall seconds.
    """
    deadline = time.monotonic() + timeout
    while True:
        missing = unmatched(node, body)
        if not missing:
            return
        if time.monotonic() > deadline:
            raise MatchTimeout(f'{node.get_fully_qualified_name()} did not match '
                               f'{body.get_fully_qualified_name()} in {timeout:g} s: '
                               + '; '.join(missing))
        drain(executor, timeout=drain_timeout)
        time.sleep(0.001)
