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
The MCAP file of a recording: the messages as received (CDR) on ``ros2msg`` schemas.

``McapStream`` writes it as the messages come, a chunk at a time; ``write_mcap`` a whole
recording at once.

Foxglove and ``ros2 bag info/play`` open it: the ``ros2`` profile, one channel per recorded topic
(target, pose, twist, grab, wrench, ``/parameter_events`` with the recorded node's changes, the
service events of its ``~/reset`` and ``~/release``, and a robot's ``joint_states``)
with the publishers' QoS as rosbag2 writes it (``offered_qos_profiles``), and schemas generated
from the message classes (``message_definition``), so that no ``.msg`` files are needed.
"""

import importlib
from pathlib import Path
import pickle
import re
import tempfile
from typing import Dict, Iterator, List, Mapping, Sequence

from rclpy.qos import QoSProfile
import yaml

from .received import MESSAGE_TYPES, Received, ROBOT_TOPICS


def schema_name(message_type) -> str:
    """
    Return the ROS 2 type name of a message class, e.g. ``geometry_msgs/msg/PointStamped``.

    A service event is named after its service: ``std_srvs/srv/Trigger_Event``.
    """
    package, kind = message_type.__module__.split('.')[:2]
    return f'{package}/{kind}/{message_type.__name__}'


def _message_class(name: str):
    """Return the class of a nested type ``package/Name``: a message, or a service's part."""
    package, type_name = name.split('/')
    for kind in ('msg', 'srv'):
        try:
            module = importlib.import_module(f'{package}.{kind}')
        except ImportError:
            continue
        if hasattr(module, type_name):
            return getattr(module, type_name)
        service, _, part = type_name.rpartition('_')
        if kind == 'srv' and hasattr(module, service):
            return getattr(getattr(module, service), part)
    raise ImportError(f'no message type {name}')


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
            current = _message_class(name)
        nested: List[str] = []
        lines = [f'{_field_type(kind, nested)} {field}'
                 for field, kind in current.get_fields_and_field_types().items()]
        header = '' if name is None else '=' * 80 + f'\nMSG: {name}\n'
        sections.append(header + '\n'.join(lines) + '\n')
        queue.extend(nested)
    return ''.join(sections)


class SpilledChunkIndexes:
    """
    The chunk indexes of an MCAP writer, kept in a temporary file instead of memory.

    The writer keeps one per chunk for the summary it writes at the end (some 700 bytes each in
    memory; a recording flushes a chunk four times a second: 10 MB an hour); here each is
    pickled to the file as it comes and read back, in order, when the summary is written.
    """

    def __init__(self) -> None:
        """Open the temporary file (deleted when closed)."""
        self._file = tempfile.TemporaryFile()
        self._count = 0

    def append(self, index) -> None:
        """Keep one chunk index, at the end."""
        self._file.seek(0, 2)
        pickle.dump(index, self._file, protocol=pickle.HIGHEST_PROTOCOL)
        self._count += 1

    def __iter__(self) -> Iterator:
        """Yield the chunk indexes, in the order they came."""
        self._file.seek(0)
        for _ in range(self._count):
            yield pickle.load(self._file)

    def __len__(self) -> int:
        """Return how many chunk indexes are kept."""
        return self._count

    def close(self) -> None:
        """Close and delete the temporary file."""
        self._file.close()


class McapStream:
    """
    A recording's MCAP file, written as the messages come, a chunk at a time.

    The schemas are written first, each channel with its first message (the publishers' QoS is
    known then), the channels without a message at the end, so that each recorded topic is in
    the file; a robot's topics (``ROBOT_TOPICS``), schema and channel, come with their first
    message only, so that a single body's file has none. ``flush`` closes the chunk in
    progress and hands it to the operating system: a killed recorder leaves a file whose chunks
    up to its last flush are read back (``mcap recover``, a streaming reader); ``close`` writes
    the summary that seeking readers use.

    :param path: the file (created or truncated).
    :param topic_names: the resolved topic name of each key of ``MESSAGE_TYPES``.
    """

    def __init__(self, path: Path, *, topic_names: Mapping[str, str]) -> None:
        """Open the file and write the header and the schemas."""
        from mcap.writer import Writer

        self._stream = open(path, 'wb')
        self._writer = Writer(self._stream)
        # The writer's list of chunk indexes (mcap 1.6), spilled to a file: flat memory.
        self._chunk_indexes = SpilledChunkIndexes()
        if isinstance(getattr(self._writer, '_Writer__chunk_indices', None), list):
            self._writer._Writer__chunk_indices = self._chunk_indexes
        self._writer.start(profile='ros2', library='mouse_constraint_ros mouse_record')
        self._topic_names = topic_names
        self._schemas: Dict[str, int] = {}
        for key in MESSAGE_TYPES:
            if key not in ROBOT_TOPICS:
                self._schema(key)
        self._channels: Dict[str, int] = {}
        self._sequence = 0

    def _schema(self, key: str) -> int:
        if key not in self._schemas:
            message_type = MESSAGE_TYPES[key]
            self._schemas[key] = self._writer.register_schema(
                name=schema_name(message_type), encoding='ros2msg',
                data=message_definition(message_type).encode())
        return self._schemas[key]

    def _channel(self, key: str, offered_qos: str) -> int:
        if key not in self._channels:
            self._channels[key] = self._writer.register_channel(
                topic=self._topic_names[key], message_encoding='cdr',
                schema_id=self._schema(key), metadata={'offered_qos_profiles': offered_qos})
        return self._channels[key]

    def add(self, message: Received, offered_qos: str = '') -> None:
        """
        Write one message as received; each message its own sequence number, in order.

        :param offered_qos: the publishers' QoS of its topic (``offered_qos_yaml``), used with
            the first message of the topic.
        """
        self._writer.add_message(channel_id=self._channel(message.topic, offered_qos),
                                 log_time=message.log_time, publish_time=message.log_time,
                                 data=message.data, sequence=self._sequence)
        self._sequence += 1

    def flush(self) -> None:
        """Close the chunk in progress and hand the file's bytes to the operating system."""
        self._writer.flush()

    def close(self, offered_qos: Mapping[str, str]) -> None:
        """Write the channels without a message, the summary and the footer; close the file."""
        for key in MESSAGE_TYPES:
            if key not in ROBOT_TOPICS:
                self._channel(key, offered_qos.get(key, ''))
        self._writer.finish()
        self._stream.close()
        self._chunk_indexes.close()


def write_mcap(path: Path, received: Sequence[Received], *, topic_names: Mapping[str, str],
               offered_qos: Mapping[str, str]) -> None:
    """
    Write a whole recording's messages, as received, into an MCAP file (``McapStream``).

    :param received: the messages, in the order they came.
    :param offered_qos: the publishers' QoS of each key (``offered_qos_yaml``), '' if unknown.
    """
    stream = McapStream(path, topic_names=topic_names)
    for message in received:
        stream.add(message, offered_qos.get(message.topic, ''))
    stream.close(offered_qos)


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
