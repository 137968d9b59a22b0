"""
The ``mouse_record`` command: record target, pose and twist, then draw the motion.

``mouse_record --duration 10 --output run`` records the relative topics ``target``, ``pose`` and
``twist`` for 10 s of the node's clock from the first pose, with a progress bar, then writes

- ``run.csv``: one row per tick (pose and twist of the same stamp), with the anchor's world
  position, the latest target received before that pose, the anchor error, speed and angular
  speed;
- ``run.png``: anchor and target paths from above and from the side, the anchor error, speed and
  angular speed over time;
- ``run.mcap`` with ``--mcap``: the three topics as received (CDR, ``ros2`` profile), which
  Foxglove and ``ros2 bag info/play`` open.

The anchor (body frame) is read from the ``anchor`` parameter of the node being recorded
(``--node``, default ``mouse_constraint`` in the recorder's namespace) through its parameter
service, so the figure always matches the node; ``--anchor X Y Z`` gives it instead and needs
no node. Ctrl-C ends the recording early and still writes the files. The files are checked
for writing before the recording starts: an unwritable ``--output`` fails at once.
"""

import argparse
import csv
import datetime
import importlib
import math
from pathlib import Path
import re
import sys
import time
from typing import Callable, Dict, List, NamedTuple, Optional, Sequence, TextIO, Tuple

from geometry_msgs.msg import PointStamped, PoseStamped, TwistStamped
import numpy as np
from rcl_interfaces.msg import ParameterType
from rcl_interfaces.srv import GetParameters
import rclpy
from rclpy.executors import ExternalShutdownException
from rclpy.experimental import EventsExecutor
from rclpy.node import Node
from rclpy.qos import HistoryPolicy, QoSProfile, ReliabilityPolicy
from rclpy.serialization import deserialize_message
from rclpy.signals import SignalHandlerOptions
from rclpy.utilities import remove_ros_args
import yaml

from ..interface import NODE_NAME, POSE_TOPIC, TARGET_TOPIC, TWIST_TOPIC
from ..messages import point_from_message, stamp_nanoseconds, state_from_messages
from ..physics.algebra import multiply, rotation_matrix, Vector3
from ..spin import StopRequest

# The recorded topics (relative: namespaces and remaps apply) and their types, in CSV order.
TOPICS = {TARGET_TOPIC: PointStamped, POSE_TOPIC: PoseStamped, TWIST_TOPIC: TwistStamped}
# Deep RELIABLE queues: a burst of caught-up ticks must not overwrite unread messages.
RECORD_QOS = QoSProfile(history=HistoryPolicy.KEEP_LAST, depth=1000,
                        reliability=ReliabilityPolicy.RELIABLE)
COLUMNS = ('time', 'stamp_ns', 'x', 'y', 'z', 'qx', 'qy', 'qz', 'qw', 'vx', 'vy', 'vz', 'wx', 'wy',
           'wz', 'anchor_x', 'anchor_y', 'anchor_z', 'target_x', 'target_y', 'target_z',
           'anchor_error', 'speed', 'angular_speed')
# The figure: FIGURE_INCHES at FIGURE_DPI, i.e. 1500 x 1000 pixels.
FIGURE_INCHES = (15.0, 10.0)
FIGURE_DPI = 100
# Anchor errors below this are drawn at it on the logarithmic axis (m).
ERROR_FLOOR = 1e-9


class Received(NamedTuple):
    """One message as received: topic key, receive time (ns, node clock), serialized CDR."""

    topic: str
    log_time: int
    data: bytes


class Row(NamedTuple):
    """One tick of the CSV, see ``COLUMNS``; the target fields are None before any target."""

    time: float
    stamp_ns: int
    position: Vector3
    orientation: Tuple[float, float, float, float]
    linear_velocity: Vector3
    angular_velocity: Vector3
    anchor: Vector3
    target: Optional[Vector3]
    anchor_error: Optional[float]
    speed: float
    angular_speed: float

    def fields(self) -> list:
        """Return the row's values in ``COLUMNS`` order; '' where there is no target."""
        target = self.target if self.target is not None else ('', '', '')
        error = '' if self.anchor_error is None else self.anchor_error
        return [self.time, self.stamp_ns, *self.position, *self.orientation,
                *self.linear_velocity, *self.angular_velocity, *self.anchor, *target, error,
                self.speed, self.angular_speed]


def _finite(name: str, minimum: Optional[float] = None):
    def parse(text: str) -> float:
        value = float(text)
        if not math.isfinite(value) or (minimum is not None and not value > minimum):
            raise argparse.ArgumentTypeError(
                f'{name} must be finite' + ('' if minimum is None else f' and > {minimum:g}')
                + f', got {text}')
        return value
    return parse


def plain_text(text: str) -> str:
    """Return docstring text for a terminal: without reST literals' backticks, one line."""
    return ' '.join(text.replace('``', '').split())


def build_parser() -> argparse.ArgumentParser:
    """Return the command's argument parser; every option's help names its default."""
    parser = argparse.ArgumentParser(
        prog='mouse_record', description=plain_text(__doc__.split('\n\n')[0]),
        epilog='examples: mouse_record -d 10 -o run --mcap | mouse_record --anchor 0.2 0.1 0.05'
               ' | add --ros-args -r __ns:=/robot for a namespaced node')
    parser.add_argument('-d', '--duration', type=_finite('--duration', 0.0), default=10.0,
                        help='seconds to record from the first pose (default: %(default)g)')
    parser.add_argument('-o', '--output', type=Path, default=None,
                        help='path prefix of the files (default: mouse_record_<date>_<time>)')
    parser.add_argument('--mcap', action='store_true',
                        help='also write PREFIX.mcap (Foxglove, ros2 bag; default: off)')
    parser.add_argument('--anchor', nargs=3, type=_finite('--anchor'), metavar=('X', 'Y', 'Z'),
                        help="the anchor in the body frame (m; default: the node's parameter)")
    parser.add_argument('--node', default=NODE_NAME,
                        help='the node whose anchor parameter to read '
                             '(default: %(default)s, in this namespace)')
    parser.add_argument('--timeout', type=_finite('--timeout', 0.0), default=10.0,
                        help='seconds to wait for the parameter service and the first pose '
                             '(default: %(default)g)')
    return parser


def parse_arguments(argv: List[str]) -> argparse.Namespace:
    """Return the command's options from ``argv`` (ROS arguments already removed)."""
    parser = build_parser()
    options = parser.parse_args(argv)
    if options.output is None:
        options.output = Path(datetime.datetime.now().strftime('mouse_record_%Y%m%d_%H%M%S'))
    if not options.output.name or options.output.name == '..':
        parser.error(f'--output needs a file name prefix, got {str(options.output)!r}')
    return options


def output_paths(prefix: Path, mcap: bool) -> List[Path]:
    """Return the files a recording writes: PREFIX.csv, PREFIX.png and with ``mcap`` .mcap."""
    suffixes = ('.csv', '.png', '.mcap') if mcap else ('.csv', '.png')
    return [prefix.with_name(prefix.name + suffix) for suffix in suffixes]


def check_writable(paths: Sequence[Path]) -> None:
    """
    Make sure each of ``paths`` can be written, leaving the file system as it was.

    It does what writing does: creates the missing directories and opens each file for
    appending (creating it, truncating nothing), then removes what it created. Trying is the
    only reliable test: permissions say nothing for root, nor about /proc or a read-only mount.

    :raises OSError: the first failure, its ``filename`` the path that failed.
    """
    created: List[Path] = []
    try:
        for path in paths:
            missing = [d for d in (path.parent, *path.parent.parents) if not d.exists()]
            for directory in reversed(missing):
                directory.mkdir()
                created.append(directory)
            existed = path.exists()
            with open(path, 'ab'):
                pass
            if not existed:
                created.append(path)
    finally:
        for path in reversed(created):
            try:
                path.rmdir() if path.is_dir() else path.unlink()
            except OSError:
                pass


def describe_os_error(error: OSError) -> str:
    """Return 'PATH: reason' for an error of the file system, on one line."""
    reason = error.strerror or str(error)
    return f'{error.filename}: {reason}' if error.filename else reason


class Recorder(Node):
    """Subscribes to the recorded topics and keeps every message, serialized, as it arrives."""

    def __init__(self, **kwargs) -> None:
        """Create the node ``mouse_record`` and its subscriptions."""
        super().__init__('mouse_record', **kwargs)
        self.received: List[Received] = []
        self.counts = dict.fromkeys(TOPICS, 0)
        self.offered_qos: Dict[str, str] = {}
        self.first_pose_ns: Optional[int] = None
        self.recording = True
        self.subscriptions_by_topic = {
            key: self.create_subscription(message_type, key, self._receiver(key), RECORD_QOS,
                                          raw=True)
            for key, message_type in TOPICS.items()}

    def topic_name(self, key: str) -> str:
        """Return the resolved (namespaced, remapped) name of a recorded topic."""
        return self.subscriptions_by_topic[key].topic_name

    def _receiver(self, key: str):
        # Serialized messages (raw=True) and no message info: the EventsExecutor of this rclpy
        # (7.1.6) fails on callbacks that take one.
        def receive(data: bytes) -> None:
            if not self.recording:
                return
            now = self.get_clock().now().nanoseconds
            self.received.append(Received(key, now, data))
            self.counts[key] += 1
            # With use_sim_time the clock reads 0 until /clock arrives: start once it runs.
            if key == 'pose' and self.first_pose_ns is None and now > 0:
                self.first_pose_ns = now
            if key not in self.offered_qos:
                self.offered_qos[key] = offered_qos_yaml(
                    [e.qos_profile for e in self.get_publishers_info_by_topic(
                        self.topic_name(key))])
        return receive

    def elapsed(self) -> float:
        """Return the seconds recorded since the first pose (0 before it)."""
        if self.first_pose_ns is None:
            return 0.0
        return max(0.0, (self.get_clock().now().nanoseconds - self.first_pose_ns) * 1e-9)


def offered_qos_yaml(profiles: Sequence[QoSProfile]) -> str:
    """Return the publishers' QoS profiles as rosbag2 (Jazzy, metadata version 9) writes them."""
    def duration(value) -> dict:
        sec, nsec = divmod(value.nanoseconds, 1_000_000_000)
        return {'sec': sec, 'nsec': nsec}
    return yaml.safe_dump([{
        'history': p.history.name.lower(), 'depth': p.depth,
        'reliability': p.reliability.name.lower(), 'durability': p.durability.name.lower(),
        'deadline': duration(p.deadline), 'lifespan': duration(p.lifespan),
        'liveliness': p.liveliness.name.lower(),
        'liveliness_lease_duration': duration(p.liveliness_lease_duration),
        'avoid_ros_namespace_conventions': p.avoid_ros_namespace_conventions,
    } for p in profiles], sort_keys=False) if profiles else ''


class Interrupted(Exception):
    """Ctrl-C or SIGTERM came while waiting."""


def spin_until(executor, condition: Callable[[], bool], timeout: float, stop,
               failure: str) -> None:
    """
    Spin until ``condition()`` holds.

    :raises RuntimeError: with ``failure`` after ``timeout`` seconds.
    :raises Interrupted: when ``stop`` (a ``StopRequest``) turns true first.
    """
    deadline = time.monotonic() + timeout
    while not condition():
        if stop:
            raise Interrupted()
        if time.monotonic() > deadline:
            raise RuntimeError(failure)
        executor.spin_once(timeout_sec=0.05)


def fetch_anchor(node: Node, executor, target_node: str, timeout: float, stop) -> Vector3:
    """Return ``target_node``'s ``anchor`` parameter; raise RuntimeError saying why it failed."""
    client = node.create_client(GetParameters, f'{target_node}/get_parameters')
    try:
        spin_until(executor, client.service_is_ready, timeout, stop,
                   f'no parameter service {client.srv_name} after {timeout:g} s')
        future = client.call_async(GetParameters.Request(names=['anchor']))
        spin_until(executor, future.done, timeout, stop,
                   f'{client.srv_name} did not answer in {timeout:g} s')
        values = future.result().values
        if len(values) != 1 or values[0].type != ParameterType.PARAMETER_DOUBLE_ARRAY \
                or len(values[0].double_array_value) != 3:
            raise RuntimeError(f'{target_node} has no anchor parameter of 3 numbers')
        return tuple(float(v) for v in values[0].double_array_value)
    finally:
        node.destroy_client(client)


def progress_bar(elapsed: float, duration: float, counts: Dict[str, int],
                 width: int = 30) -> str:
    """Return the progress line: a bar, the seconds recorded and the messages per topic."""
    share = min(1.0, elapsed / duration)
    filled = round(width * share)
    return (f'recording [{"#" * filled}{"." * (width - filled)}] {elapsed:5.1f}/{duration:g} s  '
            + '  '.join(f'{topic} {count}' for topic, count in counts.items()))


class Progress:
    """Draws the bar in place on a terminal, and a line per tenth of the duration otherwise."""

    def __init__(self, duration: float, stream: TextIO = sys.stderr) -> None:
        """Draw on ``stream``."""
        self._duration, self._stream = duration, stream
        self._terminal = stream.isatty()
        self._drawn_at = -math.inf
        self._tenth = -1

    def update(self, elapsed: float, counts: Dict[str, int], final: bool = False) -> None:
        """Redraw for ``elapsed`` seconds (at most 10 times a second on a terminal)."""
        line = progress_bar(elapsed, self._duration, counts)
        if self._terminal:
            now = time.monotonic()
            if final or now - self._drawn_at >= 0.1:
                self._stream.write('\r' + line + ('\n' if final else ''))
                self._stream.flush()
                self._drawn_at = now
        else:
            tenth = int(10.0 * min(1.0, elapsed / self._duration))
            if final or tenth > self._tenth:
                self._stream.write(line + '\n')
                self._stream.flush()
                self._tenth = tenth


def anchor_position(position: Vector3, orientation, anchor: Vector3) -> Vector3:
    """Return the world position x + R(q) r of the body-frame ``anchor``."""
    r = multiply(anchor, rotation_matrix(orientation))
    return (position[0] + r[0], position[1] + r[1], position[2] + r[2])


def tick_rows(received: Sequence[Received], anchor: Vector3) -> List[Row]:
    """
    Return one row per stamp that has both a pose and a twist, in the order the poses came.

    The target of a row is the latest target received before its pose; there is none (None)
    until the first target, e.g. while the node holds its initial anchor.
    """
    target: Optional[Vector3] = None
    poses: Dict[int, Tuple[PoseStamped, Optional[Vector3]]] = {}
    twists: Dict[int, TwistStamped] = {}
    for message in received:
        decoded = deserialize_message(message.data, TOPICS[message.topic])
        if message.topic == 'target':
            target = point_from_message(decoded)
        elif message.topic == 'pose':
            poses.setdefault(stamp_nanoseconds(decoded.header.stamp), (decoded, target))
        else:
            twists.setdefault(stamp_nanoseconds(decoded.header.stamp), decoded)
    rows: List[Row] = []
    for stamp, (pose, pose_target) in poses.items():
        twist = twists.get(stamp)
        if twist is None:
            continue
        state = state_from_messages(pose, twist)
        world_anchor = anchor_position(state.position, state.orientation, anchor)
        error = None if pose_target is None else math.dist(world_anchor, pose_target)
        start = rows[0].stamp_ns if rows else stamp
        rows.append(Row((stamp - start) * 1e-9, stamp, state.position, state.orientation,
                        state.linear_velocity, state.angular_velocity, world_anchor,
                        pose_target, error, math.hypot(*state.linear_velocity),
                        math.hypot(*state.angular_velocity)))
    return rows


def write_csv(path: Path, rows: Sequence[Row]) -> None:
    """Write ``rows`` under a ``COLUMNS`` header; floats keep every digit (repr)."""
    with open(path, 'w', newline='') as stream:
        writer = csv.writer(stream)
        writer.writerow(COLUMNS)
        writer.writerows(row.fields() for row in rows)


def write_figure(path: Path, rows: Sequence[Row], anchor: Vector3, frame_id: str,
                 title: str = 'mouse_constraint') -> None:
    """
    Draw the recording into a PNG of ``FIGURE_INCHES`` at ``FIGURE_DPI`` (Agg, no display).

    Top left the paths seen from above (x, y), top right from the side (x, z); bottom left the
    anchor error on a log scale, bottom right speed and angular speed.
    """
    from matplotlib.figure import Figure

    if not rows:
        raise ValueError('no ticks to draw')
    t = np.array([row.time for row in rows])
    anchors = np.array([row.anchor for row in rows])
    targets = np.array([row.target if row.target is not None else (np.nan,) * 3
                        for row in rows])
    errors = np.array([np.nan if row.anchor_error is None else row.anchor_error
                       for row in rows])
    figure = Figure(figsize=FIGURE_INCHES, dpi=FIGURE_DPI, layout='constrained')
    (top, side), (error_axes, speed_axes) = figure.subplots(2, 2)
    for axes, (i, j), view in ((top, (0, 1), 'top view'), (side, (0, 2), 'side view')):
        axes.plot(anchors[:, i], anchors[:, j], color='tab:orange', linewidth=1.2,
                  label='anchor')
        axes.plot(targets[:, i], targets[:, j], color='tab:purple', linestyle='--',
                  linewidth=1.0, label='target')
        axes.plot(anchors[0, i], anchors[0, j], 'o', color='tab:orange', label='anchor start')
        axes.plot(anchors[-1, i], anchors[-1, j], 's', color='tab:orange', label='anchor end')
        axes.set_aspect('equal', adjustable='datalim')
        axes.set_xlabel(f'{"xyz"[i]} (m, {frame_id})')
        axes.set_ylabel(f'{"xyz"[j]} (m, {frame_id})')
        axes.set_title(f'Anchor and target paths, {view}')
        axes.grid(True, alpha=0.3)
        axes.legend(loc='best', fontsize='small')
    error_axes.semilogy(t, np.maximum(errors, ERROR_FLOOR), color='tab:red', linewidth=0.8)
    error_axes.set_xlim(0.0, max(t[-1], 1e-3))
    error_axes.set_xlabel('time (s)')
    error_axes.set_ylabel('anchor error |anchor - target| (m)')
    error_axes.set_title('Anchor error')
    error_axes.grid(True, which='both', alpha=0.3)
    speed_axes.plot(t, [row.speed for row in rows], color='tab:blue', label='speed |v| (m/s)')
    speed_axes.set_xlim(0.0, max(t[-1], 1e-3))
    speed_axes.set_xlabel('time (s)')
    speed_axes.set_ylabel('speed of the COM (m/s)', color='tab:blue')
    spin_axes = speed_axes.twinx()
    spin_axes.plot(t, [row.angular_speed for row in rows], color='tab:green', linewidth=1.0,
                   label='angular speed |w| (rad/s)')
    spin_axes.set_ylabel('angular speed (rad/s)', color='tab:green')
    speed_axes.set_title('Speed and angular speed')
    speed_axes.grid(True, alpha=0.3)
    lines = speed_axes.get_lines() + spin_axes.get_lines()
    speed_axes.legend(lines, [line.get_label() for line in lines], loc='upper right',
                      fontsize='small')
    figure.suptitle(f'{title}: {t[-1]:.1f} s, {len(rows)} ticks, anchor '
                    f'({", ".join(f"{c:g}" for c in anchor)}) m in the body frame')
    figure.savefig(path, dpi=FIGURE_DPI)


def schema_name(message_type) -> str:
    """Return the ROS 2 type name of a message class, e.g. ``geometry_msgs/msg/PointStamped``."""
    return f'{message_type.__module__.split(".")[0]}/msg/{message_type.__name__}'


_BASIC_TYPES = {'double': 'float64', 'float': 'float32', 'boolean': 'bool', 'octet': 'byte'}


def _field_type(idl_type: str, nested: List[str]) -> str:
    sequence = re.fullmatch(r'sequence<(.+?)(?:, (\d+))?>', idl_type)
    if sequence:
        base = _field_type(sequence.group(1), nested)
        return f'{base}[<={sequence.group(2)}]' if sequence.group(2) else f'{base}[]'
    array = re.fullmatch(r'(.+)\[(\d+)\]', idl_type)
    if array:
        return f'{_field_type(array.group(1), nested)}[{array.group(2)}]'
    bounded = re.fullmatch(r'(w?string)<(\d+)>', idl_type)
    if bounded:
        return f'{bounded.group(1)}<={bounded.group(2)}'
    if '/' in idl_type:
        nested.append(idl_type)
    return _BASIC_TYPES.get(idl_type, idl_type)


def message_definition(message_type) -> str:
    """
    Return the ``ros2msg`` schema of a message class: its fields, then each nested type once.

    It is built from the class's own field list, so it needs no ``.msg`` files; it has the
    fields (all that decoding needs) but not the comments or constants of the ``.msg`` files.
    """
    sections, done, queue = [], set(), [None]
    while queue:
        name = queue.pop(0)
        if name is None:
            current = message_type
        else:
            if name in done:
                continue
            done.add(name)
            package, type_name = name.split('/')
            current = getattr(importlib.import_module(f'{package}.msg'), type_name)
        nested: List[str] = []
        lines = [f'{_field_type(kind, nested)} {field}'
                 for field, kind in current.get_fields_and_field_types().items()]
        header = '' if name is None else '=' * 80 + f'\nMSG: {name}\n'
        sections.append(header + '\n'.join(lines) + '\n')
        queue.extend(nested)
    return ''.join(sections)


def write_mcap(path: Path, recorder: Recorder) -> None:
    """Write the messages as received into an MCAP file with the ``ros2`` profile."""
    from mcap.writer import Writer

    with open(path, 'wb') as stream:
        writer = Writer(stream)
        writer.start(profile='ros2', library='mouse_constraint_ros mouse_record')
        channels = {}
        for key, message_type in TOPICS.items():
            schema = writer.register_schema(name=schema_name(message_type), encoding='ros2msg',
                                            data=message_definition(message_type).encode())
            channels[key] = writer.register_channel(
                topic=recorder.topic_name(key), message_encoding='cdr', schema_id=schema,
                metadata={'offered_qos_profiles': recorder.offered_qos.get(key, '')})
        for sequence, message in enumerate(recorder.received):
            writer.add_message(channel_id=channels[message.topic], log_time=message.log_time,
                               publish_time=message.log_time, data=message.data,
                               sequence=sequence)
        writer.finish()


def frame_of(received: Sequence[Received]) -> str:
    """Return the frame_id of the first pose, or '' without one."""
    for message in received:
        if message.topic == 'pose':
            return deserialize_message(message.data, PoseStamped).header.frame_id
    return ''


def main(args: Optional[List[str]] = None) -> int:
    """Record, then write the files; 0 on success, 1 if there was nothing to record."""
    argv = sys.argv if args is None else args
    options = parse_arguments(remove_ros_args(argv)[1:])
    try:
        check_writable(output_paths(options.output, options.mcap))
    except OSError as error:
        print(f'mouse_record: cannot write {describe_os_error(error)}: nothing recorded',
              file=sys.stderr)
        return 1
    rclpy.init(args=argv, signal_handler_options=SignalHandlerOptions.NO)
    node = Recorder()
    logger = node.get_logger()
    executor = EventsExecutor(context=node.context)
    executor.add_node(node)
    try:
        with StopRequest() as stop:
            anchor = options.anchor
            if anchor is None:
                try:
                    anchor = fetch_anchor(node, executor, options.node, options.timeout, stop)
                except RuntimeError as error:
                    logger.error(f'{error}: is the node running (same ROS_DOMAIN_ID and '
                                 'namespace, --node)? Or give --anchor X Y Z')
                    return 1
                logger.info(f'anchor {anchor} m (body frame) from {options.node}')
            anchor = tuple(anchor)
            try:
                spin_until(executor, lambda: node.first_pose_ns is not None, options.timeout,
                           stop, f'no pose on {node.topic_name("pose")} after '
                           f'{options.timeout:g} s')
            except RuntimeError as error:
                logger.error(str(error))
                return 1
            progress = Progress(options.duration)
            while not stop and node.elapsed() < options.duration:
                executor.spin_once(timeout_sec=0.05)
                progress.update(node.elapsed(), node.counts)
            node.recording = False
            progress.update(min(node.elapsed(), options.duration), node.counts, final=True)
        return write_outputs(node, options, anchor)
    except Interrupted:
        logger.warning('interrupted before the first pose: nothing recorded')
        return 130
    except ExternalShutdownException:
        return 1
    finally:
        node.destroy_node()
        rclpy.try_shutdown()


def write_outputs(node: Recorder, options: argparse.Namespace, anchor: Vector3) -> int:
    """Write the CSV, the figure and, with ``--mcap``, the MCAP file; log where they went."""
    logger = node.get_logger()
    rows = tick_rows(node.received, anchor)
    if not rows:
        logger.error('no tick with both pose and twist was recorded')
        return 1
    written = output_paths(options.output, options.mcap)
    try:
        options.output.parent.mkdir(parents=True, exist_ok=True)
        write_csv(written[0], rows)
        write_figure(written[1], rows, anchor, frame_of(node.received) or '?')
        if options.mcap:
            write_mcap(written[2], node)
    except OSError as error:
        # Checked before recording, but the file system may have changed since.
        logger.error(f'cannot write {describe_os_error(error)}')
        return 1
    logger.info(f'{len(rows)} ticks, {rows[-1].time:.2f} s: wrote '
                + ', '.join(str(path) for path in written))
    return 0


if __name__ == '__main__':
    sys.exit(main())
