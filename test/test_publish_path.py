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
The publish path: raw CDR equal to the messages, and publish_rate_hz on the tick grid.

What a subscriber receives from the raw publishing is compared field for field with the
messages ``fill_pose`` / ``fill_twist`` / ``fill_odometry`` fill, for random states and frame
ids (a frame id holding a NUL takes the message path). The publish rate is pinned by stamps and
counts on a simulated clock, with no timing.
"""

import math
import random
import string

from geometry_msgs.msg import PoseStamped, TwistStamped
from nav_msgs.msg import Odometry
import numpy as np
import pytest
from rclpy.node import Node
from rclpy.parameter import Parameter
from rclpy.serialization import deserialize_message, serialize_message

from mouse_constraint_ros.node.mouse_constraint_node import MouseConstraintNode
from mouse_constraint_ros.node.parameters import DEFAULTS, node_config
from mouse_constraint_ros.physics import BodyState
from mouse_constraint_ros.timing.publish_ticks import (MAX_BATCH_SECONDS, PublishTicks,
                                                       ticks_per_callback)
from mouse_constraint_ros.wire.messages import fill_odometry, fill_pose, fill_twist, set_stamp
from mouse_constraint_ros.wire.state_publishers import StatePublishers
from test_support.ros_harness import SimClock, stamp_of

NS = 1_000_000_000


def due_ticks(rate_hz: float, publish_rate_hz: float, count: int) -> list:
    """Return the publishing ticks among 0 .. count - 1."""
    ticks = PublishTicks(rate_hz, publish_rate_hz)
    return [n for n in range(count) if ticks.due(n)]


@pytest.mark.parametrize('rate_hz, publish_rate_hz', [
    (1000.0, 100.0), (1000.0, 250.0), (500.0, 1.0), (240.0, 60.0), (1000.0, 1000.0)])
def test_a_dividing_publish_rate_picks_every_kth_tick_from_tick_zero(rate_hz, publish_rate_hz):
    """With r / p whole: ticks 0, k, 2k, ... with k = r / p."""
    k = int(rate_hz / publish_rate_hz)
    assert k == rate_hz / publish_rate_hz
    assert due_ticks(rate_hz, publish_rate_hz, 20 * k) == list(range(0, 20 * k, k))


def test_zero_publishes_every_tick():
    """publish_rate_hz 0: every tick, and the node skips the schedule (every_tick)."""
    ticks = PublishTicks(1000.0, 0.0)
    assert ticks.every_tick and not PublishTicks(1000.0, 999.0).every_tick
    assert due_ticks(1000.0, 0.0, 50) == list(range(50))


@pytest.mark.parametrize('rate_hz, publish_rate_hz', [
    (1000.0, 300.0), (1000.0, 333.0), (1000.0, 999.0), (240.0, 100.0), (1000.0, 33.3)])
def test_a_publish_rate_that_does_not_divide_keeps_the_mean_rate_exact(rate_hz,
                                                                       publish_rate_hz):
    """
    Gaps are the two whole numbers around r / p, and any run of ticks holds p / r of them.

    The count over ticks a .. b is floor(b p / r) - floor((a - 1) p / r), within one of
    (b - a + 1) p / r.
    """
    count = 5000
    due = due_ticks(rate_hz, publish_rate_hz, count)
    ratio = rate_hz / publish_rate_hz
    assert set(np.diff(due)) <= {math.floor(ratio), math.ceil(ratio)}
    marks = np.zeros(count, dtype=int)
    marks[due] = 1
    cumulative = np.concatenate([[0], np.cumsum(marks)])
    rng = np.random.default_rng(7)
    for start, length in zip(rng.integers(0, count // 2, 200), rng.integers(1, count // 2, 200)):
        published = cumulative[start + length] - cumulative[start]
        assert abs(published - length * publish_rate_hz / rate_hz) < 1.0


@pytest.mark.parametrize('rate_hz, publish_rate_hz', [
    (1000.0, 0.0), (1000.0, 1000.0), (1000.0, 100.0), (1000.0, 300.0), (1000.0, 1.0),
    (10000.0, 100.0), (250.0, 60.0), (1.0, 0.5)])
def test_a_callback_runs_one_publish_period_of_ticks_within_the_batch_bound(
        rate_hz, publish_rate_hz):
    """The timer's batch: whole ticks within one publish period and the batch bound, >= 1."""
    batch = ticks_per_callback(rate_hz, publish_rate_hz)
    assert batch >= 1
    if publish_rate_hz == 0.0:
        assert batch == 1
        return
    period = min(1.0 / publish_rate_hz, MAX_BATCH_SECONDS)
    assert batch == 1 or batch / rate_hz <= period * (1.0 + 1e-9)
    assert (batch + 1) / rate_hz > period or batch == 1


def test_the_node_timer_fires_once_per_batch_and_follows_the_publish_rate(ros):
    """100 Hz at 1 kHz: a 10 ms timer (10 ticks a call); back to every tick: 1 ms."""
    node = sim_node(ros, rate_hz=1000.0, publish_rate_hz=100.0)
    assert node.ticker.timer.timer_period_ns == 10_000_000
    assert node.set_parameters([Parameter('publish_rate_hz', value=0.0)])[0].successful
    assert node.ticker.timer.timer_period_ns == 1_000_000
    assert node.set_parameters([Parameter('publish_rate_hz', value=300.0)])[0].successful
    assert node.ticker.timer.timer_period_ns == 3_000_000


@pytest.mark.parametrize('publish_rate_hz', [-1.0, 1000.5, math.nan])
def test_publish_ticks_refuse_a_rate_outside_zero_or_the_tick_rate(publish_rate_hz):
    """Neither 0 nor in (0, rate_hz]: ValueError."""
    with pytest.raises(ValueError, match='publish_rate_hz'):
        PublishTicks(1000.0, publish_rate_hz)


@pytest.mark.parametrize('changes, reason', [
    ({'publish_rate_hz': 1500.0}, r'publish_rate_hz must be 0.0 \(every tick\) or within '
                                  r'\(0, rate_hz\] = \(0, 1000.0\], got 1500.0'),
    ({'rate_hz': 50.0, 'publish_rate_hz': 100.0}, r'\(0, 50.0\], got 100.0'),
    ({'publish_rate_hz': -1.0}, 'publish_rate_hz must be >= 0.0'),
    ({'publish_rate_hz': math.nan}, 'publish_rate_hz must be finite'),
    ({'publish_tf': 1}, 'publish_tf must be true or false'),
    ({'publish_odometry': 'yes'}, 'publish_odometry must be true or false'),
    ({'body_frame_id': 7}, 'body_frame_id must be a string, got 7'),
    ({'body_frame_id': '/body'}, "body_frame_id must not start with a slash.*use 'body'"),
    ({'body_frame_id': 'world'}, 'body_frame_id must differ from frame_id'),
])
def test_publishing_parameters_are_validated(changes, reason):
    """Each bad value is refused with a one-line reason naming the parameter."""
    with pytest.raises(ValueError, match=reason):
        node_config(dict(DEFAULTS, **changes))


def test_publishing_parameters_reach_the_configuration():
    """Valid values come through as given."""
    config = node_config(dict(DEFAULTS, rate_hz=500.0, publish_rate_hz=500.0, publish_tf=False,
                              publish_odometry=True, body_frame_id='base_link'))
    assert (config.publish_rate_hz, config.publish_tf, config.publish_odometry,
            config.body_frame_id) == (500.0, False, True, 'base_link')
    defaults = node_config(DEFAULTS)
    assert (defaults.publish_rate_hz, defaults.publish_tf, defaults.publish_odometry,
            defaults.body_frame_id) == (0.0, True, False, 'body')


# The raw path against the messages.

def random_state(rng: random.Random) -> BodyState:
    """Return a state with a unit quaternion and values of many magnitudes and signs."""
    def vector(size):
        return tuple(rng.choice((-1.0, 1.0)) * rng.random() * 10.0 ** rng.randint(-12, 4)
                     for _ in range(size))
    quaternion = vector(4)
    norm = math.sqrt(sum(c * c for c in quaternion))
    return BodyState(vector(3), tuple(c / norm for c in quaternion), vector(3), vector(3))


def random_frame(rng: random.Random) -> str:
    """Return a frame id of 1 to 24 characters, some not ASCII (lengths move the alignment)."""
    alphabet = string.ascii_letters + string.digits + '_/' + 'äöüéø漢字'
    return ''.join(rng.choice(alphabet) for _ in range(rng.randint(1, 24)))


def expected_messages(state: BodyState, stamp_ns: int, frame_id: str, body_frame_id: str):
    """Return the pose, twist and odometry rclpy messages the fill_* functions give."""
    pose, twist, odometry = PoseStamped(), TwistStamped(), Odometry()
    for message, fill in ((pose, fill_pose), (twist, fill_twist), (odometry, fill_odometry)):
        message.header.frame_id = frame_id
        set_stamp(message.header.stamp, stamp_ns)
        fill(message, state)
    odometry.child_frame_id = body_frame_id
    return pose, twist, odometry


def round_trip(message):
    """Return ``message`` as a subscriber of its rclpy serialization receives it."""
    return deserialize_message(serialize_message(message), type(message))


def test_subscribers_receive_what_the_fill_functions_give(ros):
    """
    Random states in random frames: pose, twist and odometry arrive equal to the messages.

    A frame id holding a NUL takes the message path (rclpy cuts the string at the NUL): what
    arrives is then what rclpy sends for the same message.
    """
    rng = random.Random(20240607)
    node = ros.add(Node('publish_path_under_test', context=ros.context))
    publishers = StatePublishers(node, broadcaster_factory=None, unavailable=None,
                                 frame_id='world', body_frame_id='body', publish_tf=False,
                                 publish_odometry=True)
    sent = {'pose': [], 'twist': [], 'odom': []}
    for name, publisher in (('pose', publishers.pose_publisher),
                            ('twist', publishers.twist_publisher),
                            ('odom', publishers.odometry_publisher)):
        publisher.publish = (lambda original, log: lambda data: (
            log.append(type(data)), original(data)))(publisher.publish, sent[name])
    received = {'pose': ros.collect(PoseStamped, 'pose'),
                'twist': ros.collect(TwistStamped, 'twist'),
                'odom': ros.collect(Odometry, 'odom')}
    assert ros.spin_until(lambda: all(
        p.get_subscription_count() > 0 for p in (
            publishers.pose_publisher, publishers.twist_publisher,
            publishers.odometry_publisher)))
    frames = [('world', 'body')] + [(random_frame(rng), random_frame(rng)) for _ in range(12)]
    frames.append(('a\x00b', 'body'))
    expected = {'pose': [], 'twist': [], 'odom': []}
    for frame_id, body_frame_id in frames:
        publishers.configure(frame_id=frame_id, body_frame_id=body_frame_id, publish_tf=False,
                             publish_odometry=True)
        raw = '\x00' not in frame_id
        for name in sent:
            sent[name].clear()
        for _ in range(10):
            state = random_state(rng)
            stamp_ns = rng.randrange(0, 2 ** 31 * NS)
            publishers.publish(stamp_ns, state)
            for name, message in zip(('pose', 'twist', 'odom'), expected_messages(
                    state, stamp_ns, frame_id, body_frame_id)):
                expected[name].append(message if raw else round_trip(message))
        # Bytes go to the middleware, or messages where the layout does not apply.
        assert {name: set(types) for name, types in sent.items()} == {
            name: {bytes if raw else type(expected[name][-1])} for name in sent}
    total = 10 * len(frames)
    assert ros.spin_until(lambda: all(len(r) >= total for r in received.values()))
    for name in received:
        assert len(received[name]) == total
        for got, want in zip(received[name], expected[name]):
            assert got == want, name


def test_the_node_hands_bytes_to_its_publishers(ros):
    """The node's pose and twist go out raw: its publishers are given bytes."""
    node = ros.add(MouseConstraintNode(context=ros.context, parameter_overrides=[
        Parameter('rate_hz', value=200.0)], transform_broadcaster=None))
    given = []
    for publisher in (node._state_publishers.pose_publisher,
                      node._state_publishers.twist_publisher):
        publisher.publish = (lambda original: lambda data: (
            given.append(type(data)), original(data)))(publisher.publish)
    assert ros.spin_until(lambda: len(given) >= 20)
    assert set(given) == {bytes}


# publish_rate_hz on the node, on a simulated clock.

def sim_node(ros, **overrides) -> MouseConstraintNode:
    """Start the node on a simulated clock with ``overrides``, markers and diagnostics off."""
    values = dict(use_sim_time=True, marker_rate_hz=0.0, diagnostics_rate_hz=0.0, **overrides)
    return ros.add(MouseConstraintNode(
        context=ros.context, transform_broadcaster=None,
        parameter_overrides=[Parameter(name, value=value) for name, value in values.items()]))


START = 1_000 * NS


def test_publish_rate_publishes_every_tenth_tick_on_the_grid(ros):
    """
    100 Hz at 1 kHz: the physics steps every tick, pose and twist come every 10th tick.

    The clock advances a tick at a time, 300 ticks: one pose and one twist every 10 ticks,
    stamped exactly 10 ticks apart, the first at the grid's tick 0. (A tick at a time: a clock
    that jumped 10 ms would have one timer callback run 10 ticks, which a busy machine's wall
    time budget may cut short, dropping ticks.)
    """
    rate, publish_rate = 1000.0, 100.0
    node = sim_node(ros, rate_hz=rate, publish_rate_hz=publish_rate)
    poses, twists = ros.collect(PoseStamped, 'pose'), ros.collect(TwistStamped, 'twist')
    clock = SimClock(ros, node)
    period = int(NS / publish_rate)
    ticks_per_publish = int(rate / publish_rate)
    clock.advance_to(START)
    for k in range(1, 30 * ticks_per_publish + 1):
        clock.advance_to(START + k * (period // ticks_per_publish))
    assert node.ticker.record.ticks_run == 30 * ticks_per_publish + 1
    # Tick 0 publishes: the first stamp is the grid's origin.
    origin = stamp_of(poses[0])
    stamps = [stamp_of(m) for m in poses]
    assert stamps == [origin + k * period for k in range(31)]
    assert [stamp_of(m) for m in twists] == stamps


def test_publish_rate_changes_at_run_time_and_a_rate_that_does_not_divide(ros):
    """
    Every tick, then 300 Hz at 1 kHz (gaps of 3 and 4 ticks), then every tick again.

    The stamps published at 300 Hz are exactly the grid ticks ``PublishTicks`` picks.
    """
    rate = 1000.0
    node = sim_node(ros, rate_hz=rate)
    poses = ros.collect(PoseStamped, 'pose')
    clock = SimClock(ros, node)
    tick_ns = int(NS / rate)
    clock.advance_to(START)
    for k in range(1, 11):
        clock.advance_to(START + k * tick_ns)
    origin = stamp_of(poses[0])
    assert [stamp_of(m) for m in poses] == [origin + n * tick_ns for n in range(11)]
    # 300 Hz from tick 11 on.
    assert node.set_parameters([Parameter('publish_rate_hz', value=300.0)])[0].successful
    count = len(poses)
    for k in range(11, 611):  # a tick at a time (see the test above)
        clock.advance_to(START + k * tick_ns)
    expected = [n for n in range(11, 611) if PublishTicks(rate, 300.0).due(n)]
    assert [stamp_of(m) for m in poses[count:]] == [origin + n * tick_ns for n in expected]
    assert node.ticker.record.ticks_run == 611
    # Above rate_hz is refused; 0.0 is every tick again.
    result = node.set_parameters([Parameter('publish_rate_hz', value=2000.0)])[0]
    assert not result.successful and 'publish_rate_hz' in result.reason
    assert node.set_parameters([Parameter('publish_rate_hz', value=0.0)])[0].successful
    count = len(poses)
    clock.advance_to(START + 615 * tick_ns)
    assert [stamp_of(m) for m in poses[count:]] == [origin + n * tick_ns
                                                    for n in range(611, 616)]


def test_a_stepped_node_publishes_on_the_ticks_of_the_publish_rate(simulated_body_factory):
    """
    In lockstep at 1 kHz with 100 Hz publishing: every 10th tick publishes, at its own time.

    The physics steps every tick; 300 Hz then gives the ticks ``PublishTicks`` picks.
    """
    body = simulated_body_factory(rate_hz=1000.0, publish_rate_hz=100.0)
    stamps, last = [], [None]

    def published(b) -> None:
        message = b.pose and b.pose.message
        if message is not None and message is not last[0]:
            last[0] = message
            stamps.append(stamp_of(message))

    body.add_tick_callback(published)
    body.step(100)
    assert stamps == [n * 1_000_000 for n in range(10, 101, 10)]
    assert body.node.ticker.record.ticks_run == 100
    body.set_parameters(publish_rate_hz=300.0)
    del stamps[:]
    body.step(100)
    expected = [n for n in range(101, 201) if PublishTicks(1000.0, 300.0).due(n)]
    assert stamps == [n * 1_000_000 for n in expected]
