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
The ``mouse_record`` command: record target, pose, twist, grabs and pushes, and draw the motion.

``mouse_record --duration 10 --output run`` records the relative topics ``target``, ``pose``,
``twist``, ``grab`` and ``wrench``, and a robot's ``joint_states``, for 10 s of the node's clock
from the first pose, with a progress bar, into

- ``run.csv``: one row per tick (pose and twist of the same stamp), with the anchor's world
  position, the target path at the tick's time (within a stream of targets the point between
  the two around it; else the node's target: the latest received, a grab it took, what
  ``~/reset`` and ``~/release`` leave), the anchor error to it, speed and angular speed, the
  body-frame anchor in effect, the grabs, taken or ignored, and the wrench the node applied;
  for a robot, each joint's position, velocity and effort of the tick (``joint.<name>.*``);
- ``run.mcap`` with ``--mcap``: the topics as received (CDR, ``ros2`` profile), with the
  recorded node's changes from ``/parameter_events`` and its reset and release service events,
  which Foxglove and ``ros2 bag info/play`` open;
- ``run.png`` at the end: anchor and target paths from above and from the side, the anchor
  error, speed and angular speed over time, grabs marked; pushes as spans, the anchor's path
  while pushed in red, and the applied force over time; a URDF body's hull outlined; a robot's
  joint positions over time.

The CSV and the MCAP file are written while recording (``RecordingFiles``): a recorder killed
outright leaves all but its last half second. The anchor (body frame), ``hold_initial_anchor``,
the initial pose and the rates are read at the start from the node being recorded (``--node``,
default ``mouse_constraint`` in the recorder's namespace) through its parameter service, then
followed on ``/parameter_events`` (a ``grab`` makes the grabbed point the node's anchor), so the
figure always matches the node; ``--anchor X Y Z`` gives the starting anchor instead and needs
no node's answer (without one, the target after a reset and the node's tick grid are not
known). Ctrl-C ends the recording early and still writes the files. The files are checked for
writing before the recording starts: an unwritable ``--output`` fails at once.

This module is the command (its options and ``main``); the recording, the rows, the files and
the figure are in the ``recording`` package.
"""

import argparse
import datetime
import math
from pathlib import Path
import sys
import time
from typing import Dict, List, Optional

import rclpy
from rclpy.executors import ExternalShutdownException
from rclpy.experimental import EventsExecutor
from rclpy.signals import SignalHandlerOptions
from rclpy.utilities import remove_ros_args

from .exit_status import INTERRUPTED_STATUS
from .help_text import plain_text
from ..recording.body_outline import body_hull
from ..recording.capture import capture, Progress, Recorder, start_request
from ..recording.figure import write_figure
from ..recording.outputs import check_writable, describe_os_error, output_paths
from ..recording.recording_files import RecordingFiles
from ..timing.spin import Interrupted, SpinEnd, StopRequest, wait_until
from ..wire.interface import NODE_NAME, POSE_TOPIC

# With --anchor, how long the recorded node's parameters are waited for once poses come (s).
ANCHOR_FETCH_SECONDS = 2.0
# The longest recording (s): the stamps' seconds are an int32, no node's clock runs longer.
MAX_DURATION = float(2 ** 31 - 1)


def _finite(name: str, minimum: Optional[float] = None, maximum: Optional[float] = None):
    def parse(text: str) -> float:
        value = float(text)
        if not math.isfinite(value) or (minimum is not None and not value > minimum) or (
                maximum is not None and value > maximum):
            raise argparse.ArgumentTypeError(
                f'{name} must be finite' + ('' if minimum is None else f' and > {minimum:g}')
                + ('' if maximum is None else f' and <= {maximum:.10g}') + f', got {text}')
        return value
    return parse


def build_parser() -> argparse.ArgumentParser:
    """Return the command's argument parser; every option's help names its default."""
    parser = argparse.ArgumentParser(
        prog='mouse_record', description=plain_text(__doc__.split('\n\n')[0]),
        epilog='examples: mouse_record -d 10 -o run --mcap | mouse_record --anchor 0.2 0.1 0.05'
               ' | add --ros-args -r __ns:=/robot for a namespaced node')
    parser.add_argument('-d', '--duration', type=_finite('--duration', 0.0, MAX_DURATION),
                        default=10.0,
                        help='seconds to record from the first pose (default: %(default)g)')
    parser.add_argument('-o', '--output', type=Path, default=None,
                        help='path prefix of the files (default: mouse_record_<date>_<time>)')
    parser.add_argument('--mcap', action='store_true',
                        help='also write PREFIX.mcap (Foxglove, ros2 bag; default: off)')
    parser.add_argument('--anchor', nargs=3, type=_finite('--anchor'), metavar=('X', 'Y', 'Z'),
                        help="the anchor in the body frame at the start (m; default: the node's "
                             "parameter); changes of the node's anchor are followed")
    parser.add_argument('--node', default=NODE_NAME,
                        help='the node whose anchor parameter to read and follow '
                             '(default: %(default)s, in this namespace)')
    parser.add_argument('--timeout', type=_finite('--timeout', 0.0), default=10.0,
                        help='seconds to wait for the parameter service and the first pose, '
                             'and for each pose while recording (default: %(default)g)')
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


def main(args: Optional[List[str]] = None) -> int:
    """
    Record, writing the files as it goes.

    :returns: 0 on success (also when Ctrl-C ended the recording early); 1 when there was
        nothing to record or the files cannot be written; ``INTERRUPTED_STATUS`` when a stop
        came before the first pose.
    """
    argv = sys.argv if args is None else args
    options = parse_arguments(remove_ros_args(argv)[1:])
    paths = output_paths(options.output, options.mcap)
    try:
        check_writable(paths)
    except OSError as error:
        print(f'mouse_record: cannot write {describe_os_error(error)}: nothing recorded',
              file=sys.stderr)
        return 1
    rclpy.init(args=argv, signal_handler_options=SignalHandlerOptions.NO)
    files = RecordingFiles(paths[0], paths[2] if options.mcap else None)
    node = Recorder(target_node=options.node, sink=files.add, keep=False)
    logger = node.get_logger()
    executor = EventsExecutor(context=node.context)
    executor.add_node(node)
    try:
        # Set before the first pose: what comes while the node is asked is held to it too.
        node.duration_ns = round(options.duration * 1e9)
        with StopRequest() as stop:
            start = _wait_for_start(node, executor, stop, options)
            if start is None:
                return 1
            try:
                options.output.parent.mkdir(parents=True, exist_ok=True)
                files.start(start, topic_names=node.topic_names(),
                            offered_qos=node.offered_qos,
                            metadata=[f'mouse_record of {node.target_name}'])
            except OSError as error:
                # Checked before recording, but the file system may have changed since.
                logger.error(f'cannot write {describe_os_error(error)}')
                return 1
            end = capture(node, executor, stop, duration=options.duration,
                          idle_timeout=options.timeout, progress=Progress(options.duration),
                          each_turn=files.flush_due)
            if end is SpinEnd.SHUTDOWN:
                files.close()  # what came is kept; the context is gone
                return 1
            if end is SpinEnd.DEADLINE:
                logger.warning(f'no pose for {options.timeout:g} s (the node paused or gone): '
                               f'the recording ends at {node.elapsed():.3f} s')
        return finish_outputs(node, files, options, start)
    except Interrupted:
        logger.warning('interrupted before the first pose: nothing recorded')
        return INTERRUPTED_STATUS
    except ExternalShutdownException:
        return 1
    finally:
        node.destroy_node()
        rclpy.try_shutdown()


def _wait_for_start(node: Recorder, executor, stop: StopRequest,
                    options: argparse.Namespace) -> Optional[Dict[str, object]]:
    """
    Return the recorded node's parameters once they and the first pose came; None, logged, else.

    The parameters are asked for from the start, alongside the wait for the first pose
    (``start_request``), and asked again when it comes: the node has matched the recorder by
    then, and its answer comes back at once. ``--anchor`` gives the anchor and needs no answer:
    once the poses come, the node that publishes them, if it is one, is being discovered, and
    its answer is waited for ``ANCHOR_FETCH_SECONDS`` at most; without it (poses from a bag, a
    node of another name) its rates and initial pose are not known, and the grid is taken from
    the rows (``missing_ticks``).
    """
    logger = node.get_logger()
    request = start_request(node, options.node)
    posed = False

    def ready() -> bool:
        nonlocal posed
        if not posed and node.first_pose_ns is not None:
            posed = True
            request.ask_again()
        answered = request.poll()
        return posed and (answered or options.anchor is not None)

    came = wait_until(executor, stop, ready, deadline=time.monotonic() + options.timeout)
    if options.anchor is None and request.values is None:
        logger.error(f'{request.unanswered(options.timeout)}: is the node running (same '
                     'ROS_DOMAIN_ID and namespace, --node)? Or give --anchor X Y Z')
        return None
    if not came:
        logger.error(f'no pose on {node.topic_name(POSE_TOPIC)} after {options.timeout:g} s')
        return None
    if options.anchor is None:
        logger.info(f'anchor {request.values["anchor"]} m (body frame) from {options.node}')
        return request.values
    seconds = min(options.timeout, ANCHOR_FETCH_SECONDS)
    wait_until(executor, stop, request.poll, deadline=time.monotonic() + seconds)
    anchor = {'anchor': tuple(options.anchor)}
    if request.values is None:
        logger.info(f"{request.unanswered(seconds)}: the node's rates and initial pose are not "
                    'known')
        return anchor
    return {**request.values, **anchor}


def finish_outputs(node: Recorder, files: RecordingFiles, options: argparse.Namespace,
                   start: Dict[str, object]) -> int:
    """
    Write the last rows, the CSV's trailer, the MCAP's summary and the figure; log them.

    :param start: the recorded node's parameters at the start (``rows.NodeView``).
    """
    logger = node.get_logger()
    written = output_paths(options.output, options.mcap)
    try:
        files.close()
        if not files.figure_rows.count:
            logger.error('no tick with both pose and twist was recorded')
            for path in files.paths():
                path.unlink(missing_ok=True)
            return 1
        # A robot's links are not one body: no outline (its joints have a panel).
        write_figure(written[1], files.rows(), anchor=start['anchor'],
                     frame_id=files.frame_id or '?', ticks=files.figure_rows.count,
                     hull=None if files.joint_names else body_hull(start, logger.warning))
    except OSError as error:
        logger.error(f'cannot write {describe_os_error(error)}')
        return 1
    last, lacking = files.rows()[-1], files.missing()
    logger.info(f'{files.figure_rows.count} ticks, {last.time:.2f} s: wrote '
                + ', '.join(str(path) for path in written))
    if lacking.missing:
        logger.warning(
            f'{lacking.missing} of {lacking.expected} ticks missing from the recording '
            f'(longest gap {lacking.longest_gap:.6g} s at {lacking.gap_at:.6g} s, grid '
            f'{lacking.grid}): the node dropped them or was paused, or this recorder did not '
            f'keep up; the CSV says so in its last lines too')
    else:
        logger.info(f'no tick missing on the grid ({lacking.grid})')
    return 0


if __name__ == '__main__':
    sys.exit(main())
