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
``mouse_constraint_ros.testing``: the harness itself, its lockstep, isolation and refusals.

What it promises a downstream package: the same poses bit for bit on every run, in any process
and however loaded the machine; a node's ROS-time timers at exact simulated times; a command
sent in response to tick k acting from tick k + 1; its traffic kept to itself; loud failures
(never a hang) when an endpoint does not match or a drain never goes idle; and a pytest plugin
that costs pytest nothing at start.
"""

import importlib.metadata
from pathlib import Path
import subprocess
import sys
import textwrap

from geometry_msgs.msg import PointStamped, PoseStamped
import numpy as np
import pytest
from rclpy.executors import SingleThreadedExecutor
from rclpy.node import Node
from rclpy.parameter import Parameter
from rclpy.qos import QoSProfile, ReliabilityPolicy

from mouse_constraint_ros.node.mouse_constraint_node import MouseConstraintNode
from mouse_constraint_ros.testing import (DrainTimeout, InputRefused, MatchTimeout, NeverHeld,
                                          SimulatedBody)
from mouse_constraint_ros.testing.lockstep import isolated_context
from mouse_constraint_ros.wire.messages import point_message, stamp_nanoseconds

# A run whose poses are hashed: the worked example's controller for 1200 ticks.
RUN = """
import hashlib
import numpy as np
from mouse_constraint_ros.testing import SimulatedBody
from test_worked_example import AnchorController, GOAL


def run_digest():
    digest = hashlib.sha256()
    with SimulatedBody(target_feed_forward=False, floor=True) as body:
        body.add_node(AnchorController(context=body.context, goal=GOAL))
        body.add_tick_callback(lambda b: digest.update(
            b.pose.position.tobytes() + b.pose.orientation.tobytes() + b.twist.linear.tobytes()
            + b.twist.angular.tobytes() + np.float64(b.pose.time).tobytes()))
        body.step(1200)
    return digest.hexdigest()
"""
# The same code runs here and in a child interpreter.
namespace = {}
exec(RUN, namespace)  # noqa: S102
run_digest = namespace['run_digest']


@pytest.mark.system
def test_the_same_poses_bit_for_bit_in_this_process_and_another():
    """Two runs here and one in a fresh interpreter hash every pose and twist alike."""
    # The child runs while this process makes its two: each run keeps to its own context.
    child = subprocess.Popen(
        [sys.executable, '-c', RUN + '\nprint(run_digest())'], stdout=subprocess.PIPE,
        stderr=subprocess.PIPE, text=True, cwd=str(Path(__file__).parent))
    try:
        here = [run_digest(), run_digest()]
        stdout, stderr = child.communicate(timeout=120)
    finally:
        if child.poll() is None:
            child.kill()
            child.wait()
    assert child.returncode == 0, stderr
    assert here[0] == here[1] == stdout.split()[-1]


def test_a_ros_time_timer_fires_at_exact_simulated_times(simulated_body_factory):
    """A node on use_sim_time with a 7 ms timer: called at 7, 14, ... ms of the body's clock."""
    body = simulated_body_factory(rate_hz=1000.0)
    node = Node('timed', context=body.context,
                parameter_overrides=[Parameter('use_sim_time', value=True)])
    calls = []
    node.create_timer(0.007, lambda: calls.append(node.get_clock().now().nanoseconds))
    body.add_node(node)
    body.step(100)
    assert calls == [k * 7_000_000 for k in range(1, 15)]


def test_a_command_sent_in_response_to_tick_k_acts_from_tick_k_plus_1(simulated_body_factory):
    """
    A node answers the pose of tick 10 with a target: the node has it before tick 11 runs.

    Tick 10's state is the one of a run without the command, bit for bit; tick 11's is not.
    """
    def run(command: bool) -> list:
        body = simulated_body_factory(rate_hz=1000.0)
        responder = Node('responder', context=body.context)
        publisher = responder.create_publisher(PointStamped, 'target', 10)

        def on_pose(message):
            if command and stamp_nanoseconds(message.header.stamp) == 10_000_000:
                publisher.publish(point_message((0.5, 0.2, 1.0), 'world', 0))
        responder.create_subscription(PoseStamped, 'pose', on_pose, 10)
        body.add_node(responder)
        rows = []
        body.add_tick_callback(lambda b: rows.append(
            (b.node.simulation.state, b.node.simulation.target)))
        body.step(12)
        return rows

    quiet, commanded = run(False), run(True)
    assert commanded[9][1] == (0.5, 0.2, 1.0) != quiet[9][1]
    assert commanded[9][0] == quiet[9][0]
    assert commanded[10][0] != quiet[10][0]


def test_its_traffic_stays_in_its_context(ros):
    """A node of another context in this process, or another process, sees none of it."""
    other = subprocess.Popen([sys.executable, '-c', textwrap.dedent("""
        import sys
        from mouse_constraint_ros.testing import SimulatedBody
        with SimulatedBody() as body:
            print('ready', flush=True)
            while sys.stdin.readline():
                body.step(50)
        """)], stdin=subprocess.PIPE, stdout=subprocess.PIPE, text=True)
    try:
        assert other.stdout.readline().strip() == 'ready'
        with SimulatedBody() as body:
            seen = []
            watcher = Node('watcher', context=body.context)
            watcher.create_subscription(PoseStamped, 'pose', seen.append, 100)
            body.add_node(watcher)
            for _ in range(5):
                other.stdin.write('\n')
                other.stdin.flush()
                body.step(10)
                ros.spin_for(0.05)
            # Only its own node publishes pose and /clock; it ticked 50 times, the other 250.
            assert body.node.count_publishers('/clock') == 1
            assert body.node.count_publishers('pose') == 1
            assert len(seen) == 50
            assert ros.probe.count_publishers('/clock') == 0
            assert ros.probe.count_publishers('pose') == 0
    finally:
        other.stdin.close()
        other.wait(timeout=30)


@pytest.mark.ros
def test_it_takes_the_callers_context_and_executor():
    """Given a context and an executor, it uses them and leaves them running at close."""
    context = isolated_context()
    executor = SingleThreadedExecutor(context=context)
    try:
        with SimulatedBody(context=context, executor=executor) as body:
            assert body.context is context and body.executor is executor
            body.step(3)
            assert body.time == pytest.approx(0.003, abs=1e-12)
        assert context.ok()
    finally:
        executor.shutdown()
        context.try_shutdown()


def test_before_the_first_tick_there_is_no_pose(simulated_body):
    """Time 0, no pose or twist yet; each tick calls the tick callback once."""
    assert simulated_body.time == 0.0
    assert simulated_body.pose is None and simulated_body.twist is None
    calls = []
    simulated_body.add_tick_callback(lambda b: calls.append(b.time))
    simulated_body.step(3)
    assert calls == pytest.approx([0.001, 0.002, 0.003], abs=1e-12)
    assert simulated_body.pose.time == pytest.approx(0.003, abs=1e-12)


@pytest.mark.parametrize('simulated_body', [{'mass': 5, 'gravity': (0, 0, -1)}],
                         indirect=True)
def test_parameters_come_as_keywords_and_whole_numbers_are_doubles(simulated_body):
    """mass=5 and an int tuple are taken as the doubles the node declares."""
    assert simulated_body.node.get_parameter('mass').value == 5.0
    assert simulated_body.node.simulation.settings.gravity == (0.0, 0.0, -1.0)


def test_what_would_take_the_clock_from_it_or_is_no_parameter_is_refused(simulated_body):
    """publish_clock false, use_sim_time, an unknown name; the node's refusals, with reasons."""
    for keywords in ({'publish_clock': False}, {'use_sim_time': True}):
        with pytest.raises(ValueError, match='would take the clock from the harness'):
            SimulatedBody(**keywords)
        with pytest.raises(ValueError, match='would take the clock from the harness'):
            simulated_body.set_parameters(**keywords)
    with pytest.raises(TypeError, match="unknown parameter 'mas': did you mean 'mass'"):
        simulated_body.set_parameters(mas=3.0)
    with pytest.raises(ValueError, match='triangle'):
        simulated_body.set_parameters(inertia=[1.0, 0.0, 0.0, 1.0, 0.0, 3.0])
    with pytest.raises(InputRefused, match='not finite') as refused:
        simulated_body.target((float('nan'), 0.0, 1.0))
    assert refused.value.key == 'finite'


def test_step_until_says_the_time_it_reached(simulated_body):
    """A predicate that never holds: NeverHeld with the ticks and the simulated time."""
    with pytest.raises(NeverHeld, match=r'did not hold within 25 ticks: simulated time '
                                        r'0\.025000 s'):
        simulated_body.step_until(lambda: simulated_body.time > 1.0, max_ticks=25)
    assert simulated_body.step_until(lambda: True, max_ticks=0) == 0


@pytest.mark.ros
def test_an_endpoint_that_cannot_match_fails_add_node_naming_it():
    """A best-effort target publisher does not match the reliable subscription: said, and why."""
    with SimulatedBody(match_timeout=0.3) as body:
        node = Node('sloppy', context=body.context)
        node.create_publisher(PointStamped, 'target',
                              QoSProfile(depth=1, reliability=ReliabilityPolicy.BEST_EFFORT))
        with pytest.raises(MatchTimeout, match=r'publisher on /target \(ERROR: Best effort '
                                               r'publisher and reliable subscription'):
            body.add_node(node)
        with pytest.raises(ValueError, match='another context'):
            body.add_node(Node('elsewhere', context=isolated_context()))


@pytest.mark.ros
def test_its_node_has_no_qos_event_handlers_and_the_node_alone_has_them():
    """
    The harness names an endpoint that cannot match itself (above): its node has no handlers.

    The node built as an application builds it has rclpy's two per topic, which warn of a peer
    of incompatible QoS or type.
    """
    with SimulatedBody() as body:
        assert list(body.node.waitables) == []
        alone = MouseConstraintNode(context=body.context, namespace='alone', stepped=True,
                                    parameter_overrides=[Parameter('publish_clock', value=True)])
        try:
            topics = len(list(alone.publishers)) + len(list(alone.subscriptions))
            assert len(list(alone.waitables)) == 2 * topics == 22
        finally:
            alone.destroy_node()


@pytest.mark.ros
def test_a_drain_that_never_goes_idle_fails_loudly():
    """A node whose timer is always due: DrainTimeout, naming the timer, instead of a hang."""
    with SimulatedBody(drain_timeout=0.3) as body:
        busy = Node('busy', context=body.context)
        busy.create_timer(0.0, lambda: None)
        body.executor.add_node(busy)
        with pytest.raises(DrainTimeout, match=r'did not go idle in 0\.3 s.*timer of 0 s'):
            body.step()


@pytest.mark.system
def test_the_plugin_costs_pytest_no_ros_import_and_is_registered():
    """Importing the plugin loads neither rclpy nor a message package; the entry point names it."""
    probe = subprocess.run([sys.executable, '-c', textwrap.dedent("""
        import sys
        import mouse_constraint_ros.testing.pytest_plugin
        loaded = [name for name in sys.modules
                  if name.split('.')[0] == 'rclpy' or name.split('.')[0].endswith('_msgs')]
        print(loaded)
        """)], capture_output=True, text=True, timeout=60)
    assert probe.returncode == 0 and probe.stdout.strip() == '[]', probe.stdout + probe.stderr
    plugins = {e.name: e.value for e in importlib.metadata.entry_points(group='pytest11')}
    assert plugins['mouse_constraint_ros'] == 'mouse_constraint_ros.testing.pytest_plugin'


@pytest.mark.system
def test_a_downstream_package_gets_the_fixture_by_installing_this_one(tmp_path):
    """A pytest run in a folder with no conftest: ``simulated_body`` comes from the plugin."""
    (tmp_path / 'test_downstream.py').write_text(textwrap.dedent("""
        def test_it_falls(simulated_body):
            simulated_body.release()
            simulated_body.step(100)
            assert simulated_body.twist.linear[2] < -0.9
        """))
    result = subprocess.run([sys.executable, '-m', 'pytest', '-q', '-p', 'no:cacheprovider',
                             str(tmp_path)], capture_output=True, text=True, cwd=tmp_path,
                            timeout=120)
    assert result.returncode == 0, result.stdout + result.stderr
    assert '1 passed' in result.stdout


def test_the_worked_example_is_the_one_docs_testing_shows():
    """docs/testing.md shows test_worked_example.py as it is, below its licence header."""
    root = Path(__file__).resolve().parent.parent
    source = (root / 'test' / 'test_worked_example.py').read_text()
    example = source[source.index('"""A downstream'):]
    page = (root / 'docs' / 'testing.md').read_text()
    assert '```python\n' + example + '```' in page


def test_anchor_is_the_dragged_point_in_the_world(simulated_body):
    """The body-frame anchor placed by the latest pose; a grab at the COM makes it the COM."""
    from scipy.spatial.transform import Rotation

    body = simulated_body
    assert body.anchor is None
    body.step(20)
    local = np.array(body.node.get_parameter('anchor').value)
    rotation = Rotation.from_quat(body.pose.orientation)
    assert np.allclose(body.anchor, body.pose.position + rotation.apply(local), atol=1e-12)
    assert np.allclose(body.anchor, (0.2, 0.1, 1.05), atol=1e-6)  # held where it started
    body.grab(tuple(body.pose.position))
    body.step(1)
    assert np.allclose(body.anchor, body.pose.position, atol=1e-9)
