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
What the node says when it starts: its refusals as one line each, its warnings, its summary.

Start-up refuses what it cannot run with one FATAL line tagged with the node's real name and
exit 1: a parameter of the wrong type or out of its declared range (``refusal_reason``, also
the reason of such a change refused at run time, which rclpy refuses before the node sees it), a
configuration that is not valid as a whole (``node_config``'s reason), both ``publish_clock``
and ``use_sim_time`` (``CLOCK_LOOP``), a params file rcl cannot read (``rcl_reason``, under
the name ``requested_logger_name`` finds in the command line, as rcl cannot say it then), or a
``-p name:=value`` that rcl cannot take (``override_refusal``, said before rcl says it at
length: a URDF's text, whose comments hold ``: ``).
Unknown keys in the parameters given to the node are not an error (one file may serve several
nodes) but are warned about, with the nearest known name (``unknown_parameter_warnings``).

Plain Python only: parameter types are named as rclpy's ``Parameter.Type`` names them
('DOUBLE', 'INTEGER_ARRAY', ...), so that every text here is tested without rclpy.
"""

import difflib
import math
import re
from typing import Any, Iterable, List, Mapping, Optional, Sequence, Tuple

from .parameters import DEFAULTS, node_config, NodeConfig, ParameterSpec
from ..physics.settings import force_bound

# Why publish_clock and use_sim_time cannot both be true.
CLOCK_LOOP = ('publish_clock: true with use_sim_time: true: a node cannot follow the clock it '
              'publishes itself (set use_sim_time false, or publish_clock false to follow '
              'another /clock)')
# rcl's words for a ``-p name:=value`` it cannot take.
OVERRIDE_PARSE_ERROR = "Couldn't parse parameter override rule"
# Parameters rclpy declares or reads by itself; not unknown keys.
RCLPY_PARAMETER_PREFIXES = ('use_sim_time', 'start_type_description_service', 'qos_overrides.')
# How the refusals name each rclpy parameter type (by its ``Parameter.Type`` name).
TYPE_NAMES = {
    'BOOL': 'a bool',
    'INTEGER': 'an integer',
    'DOUBLE': 'a double',
    'STRING': 'a string',
    'BYTE_ARRAY': 'a list of bytes',
    'BOOL_ARRAY': 'a list of bools',
    'INTEGER_ARRAY': 'a list of integers',
    'DOUBLE_ARRAY': 'a list of doubles',
    'STRING_ARRAY': 'a list of strings',
}


class StartupRefusal(ValueError):
    """
    The node cannot start with what it was given; the message says what and why.

    :param logger_name: the logger of the node that refuses, with its real (remapped) name.
    :param reason: one line naming the parameter and the reason.
    """

    def __init__(self, logger_name: str, reason: str) -> None:
        """Keep the logger name next to the reason."""
        super().__init__(reason)
        self.logger_name = logger_name


def clock_loop(publish_clock: bool, use_sim_time: bool) -> Optional[str]:
    """Return ``CLOCK_LOOP`` when the node would follow the clock it publishes, else None."""
    return CLOCK_LOOP if publish_clock and use_sim_time else None


def value_type(value: Any) -> str:
    """
    Return the rclpy parameter type of ``value`` by name, as ``Parameter.Type`` finds it.

    The type a declaration takes is its default's: bool before int (a bool is an int in
    Python), a sequence by the type all its items share ('NOT_SET' for None).

    :raises TypeError: for a value no parameter type holds.
    """
    if value is None:
        return 'NOT_SET'
    for python_type, name in ((bool, 'BOOL'), (int, 'INTEGER'), (float, 'DOUBLE'),
                              (str, 'STRING')):
        if isinstance(value, python_type):
            return name
    if isinstance(value, (list, tuple)) or type(value).__name__ == 'array':
        for python_type, name in ((bytes, 'BYTE_ARRAY'), (bool, 'BOOL_ARRAY'),
                                  (int, 'INTEGER_ARRAY'), (float, 'DOUBLE_ARRAY'),
                                  (str, 'STRING_ARRAY')):
            if all(isinstance(v, python_type) for v in value):
                return name
    raise TypeError(f'no parameter type holds {value!r}')


def yaml_text(value: Any) -> str:
    """Return ``value`` as YAML writes it (true, 2.0, [1.0, 2.0], .nan)."""
    if isinstance(value, bool):
        return 'true' if value else 'false'
    if isinstance(value, float) and not math.isfinite(value):
        return '.nan' if math.isnan(value) else ('-.inf' if value < 0 else '.inf')
    if isinstance(value, (list, tuple)) or type(value).__name__ == 'array':
        return '[' + ', '.join(yaml_text(v) for v in value) + ']'
    return repr(value)


def type_hint(value: Any, expected: str) -> Optional[str]:
    """Return how to write ``value`` as the ``expected`` type (by name), where that is plain."""
    if expected == 'DOUBLE' and type(value) is int:
        return yaml_text(float(value))
    if expected == 'DOUBLE_ARRAY' and isinstance(value, Sequence):
        if all(type(v) in (int, float) for v in value):
            return yaml_text([float(v) for v in value])
    if expected == 'INTEGER' and isinstance(value, float) and value.is_integer():
        return str(int(value))
    if expected == 'BOOL' and type(value) is int and value in (0, 1):
        return yaml_text(bool(value))
    return None


def refusal_reason(declaration: ParameterSpec, error: object,
                   given: Optional[Tuple[Any, str]] = None,
                   values: Optional[Mapping[str, Any]] = None) -> str:
    """
    Return one line saying why the ``given`` value cannot be ``declaration``'s.

    rclpy refuses an override or a change of another type than the default's (a YAML ``2`` is
    an integer, never a double: ``ros2 param set`` refuses it the same way, so the node does not
    convert it at start either) or outside the declared range; its texts name neither the
    parameter first nor the fix, and differ between start-up and run time. A value of another
    type is said so here, with how to write it; one out of range in the words the node refuses
    any invalid value with (``node_config``'s, the other parameters at ``values``), so that a
    value reads the same whichever check meets it first.

    :param declaration: the parameter as the node declares it.
    :param error: what rclpy raised (its text is the reason when nothing plainer is known).
    :param given: the value given, as (value, rclpy type name), or None.
    :param values: the node's other parameters (the defaults where not given).
    """
    name = declaration.name
    if given is None:
        return f'{name}: {error}'
    value, given_type = given
    expected = value_type(declaration.default)
    if given_type != expected:
        reason = (f'{name}: {yaml_text(value)} is {TYPE_NAMES.get(given_type, given_type)}, '
                  f'{name} takes {TYPE_NAMES.get(expected, expected)}')
        hint = type_hint(value, expected)
        return reason + (f': write {hint}' if hint else '')
    if declaration.bounds is not None:
        try:
            # The box as the body: a range is worded alike for any, and no URDF is read again.
            node_config({**DEFAULTS, **(values or {}), name: value, 'robot_description': '',
                         'body_link': ''})
        except ValueError as refusal:
            return str(refusal)
        low, high = declaration.bounds
        # The largest float as the top: every finite value from low, not .inf.
        top = 'finite' if high == math.nextafter(math.inf, 0.0) else yaml_text(high)
        bounds = f'its range [{yaml_text(low)}, {top}]'
        if isinstance(value, float) and math.isnan(value):
            return f'{name}: .nan is not a number, so not within {bounds}'
        return f'{name}: {yaml_text(value)} is outside {bounds}'
    return f'{name}: {error}'


def unknown_parameter_warnings(given: Iterable[str], declared: Iterable[str],
                               known: Sequence[str]) -> List[str]:
    """
    Return one warning for each given parameter the node does not have, with the nearest name.

    :param given: the names of the parameters the node was started with.
    :param declared: the names the node has (its own and rclpy's).
    :param known: the node's own names, to suggest from.
    """
    warnings = []
    for name in sorted(set(given) - set(declared)):
        if name.startswith(RCLPY_PARAMETER_PREFIXES):
            continue
        nearest = difflib.get_close_matches(name, known, n=1)
        warnings.append(f'ignoring unknown parameter {name!r}'
                        + (f': did you mean {nearest[0]!r}?' if nearest else ''))
    return warnings


def describe(config: NodeConfig) -> str:
    """Return the line the node logs at start and after each change: rate, body, constraint."""
    c = config
    s = c.settings
    constraint = s.constraint
    if constraint.rigid:
        mode = f'rigid, baumgarte {constraint.baumgarte:g}'
    else:
        omega, mass = 2.0 * math.pi * constraint.frequency_hz, s.body.mass
        mode = (f'soft, {constraint.frequency_hz:g} Hz, '
                f'damping ratio {constraint.damping_ratio:g} (at the COM '
                f'{mass * omega * omega:g} N/m, '
                f'{2.0 * mass * constraint.damping_ratio * omega:g} N s/m)')
    motion = s.target_motion
    return (f'{c.rate_hz:g} Hz x {s.substeps} substeps in frame {c.frame_id!r}: '
            f'{_body(c)}mass {s.body.mass:g} kg, inertia {s.body.inertia}, anchor {c.anchor},'
            f' {mode}, force bound {force_bound(s):g} N, angular friction '
            f'{constraint.angular_friction:g}, guide {motion.max_speed:g} m/s '
            f'{motion.max_acceleration:g} m/s^2, gravity {s.gravity}, damping '
            f'{s.linear_damping:g}/{s.angular_damping:g} 1/s, target timeout '
            f'{c.target_timeout:g} s' + _floor(s.floor) + (
                f', publishing at {c.publish_rate_hz:g} Hz' if c.publish_rate_hz else '') + (
                f', publishing /clock at real time factor {c.real_time_factor:g}'
                if c.publish_clock else ''))


def hold_here(config: NodeConfig) -> str:
    """
    Return where a device is to be held at the start: the anchor's world point, and the device's.

    A device held elsewhere pulls the anchor to it at the coupling's force, up to the bound.
    Both points are shown to a tenth of a millimetre (of a device unit).
    """
    anchor = config.initial_anchor()
    device = config.device
    at = ', '.join(f'{round(c, 4) + 0.0:g}' for c in anchor)
    held = ', '.join(f'{round(c, 4) + 0.0:g}' for c in device.mapping.from_world(anchor))
    return (f'the anchor starts at ({at}) m in {config.frame_id!r}: hold the device there, at '
            f'({held}) in {device.pose_frame(config.frame_id)!r}, before its poses come on '
            'target_pose')


def _body(config: NodeConfig) -> str:
    """Return the URDF link's part of ``describe``: its name and COM, or nothing for the box."""
    if config.body_frame.at_com:
        return ''
    return f'link {config.geometry.link!r} (COM {config.body_frame.com} m in it), '


def _floor(floor) -> str:
    """Return the floor's part of ``describe``: where it is and how it holds, or none."""
    if not floor.enabled:
        return ', no floor'
    return (f', floor at z {floor.height:g} m (friction {floor.friction:g}, restitution '
            f'{floor.restitution:g})')


def requested_logger_name(args: Sequence[str], node_name: str) -> str:
    """
    Return the logger name of ``node_name`` as the command line's remaps make it, without rcl.

    For the one case where rcl cannot start (an unreadable params file) and so cannot say:
    ``-r __node:=other`` (or ``__name``) and ``-r __ns:=/a/b`` give ``a.b.other``.
    """
    name, namespace = node_name, ''
    for argument in args:
        match = re.fullmatch(r'(?:[^:=]+:)?__(node|name|ns):=(.+)', argument)
        if match and match.group(1) == 'ns':
            namespace = match.group(2)
        elif match:
            name = match.group(2)
    return '.'.join(part for part in namespace.split('/') + [name] if part)


def override_reason(name: str, problem: str) -> str:
    """
    Return why rcl cannot take ``-p name:=value`` (``problem``), and the way round.

    A URDF's text given as ``-p robot_description:="$(cat f.urdf)"`` is such a value: rcl reads
    every override as YAML, and a ``: `` in the text (an XML comment's) makes it no string.
    """
    line = (f"{OVERRIDE_PARSE_ERROR}: -p {name}:=... ({problem}; rcl reads an override's value "
            "as YAML, where ': ' and ' #' are not text)")
    if name.rpartition(':')[2] == 'robot_description':
        return (line + '; give the URDF as a file: make run URDF=path/to.urdf, or python -m '
                'mouse_constraint_ros.cli.urdf_params path/to.urdf out.yaml and --params-file '
                'out.yaml')
    return line + f'; quote the value as YAML text (-p "{name}:=\'...\'") or use --params-file'


def override_refusal(args: Sequence[str]) -> Optional[str]:
    """
    Return why rcl would refuse a ``-p name:=value`` of ``args``, before rcl prints it; or None.

    rcl takes a scalar or a list as an override; a value YAML reads as a mapping, or cannot
    read, it refuses with a message that holds the whole value (cut at 1024 characters).

    :param args: the command line (``sys.argv``).
    """
    import yaml

    arguments = list(args)
    for flag, rule in zip(arguments, arguments[1:]):
        name, assigned, value = rule.partition(':=')
        if flag not in ('-p', '--param') or not assigned:
            continue
        try:
            parsed = yaml.safe_load(value)
        except (yaml.scanner.ScannerError, yaml.parser.ParserError) as error:
            return override_reason(name, f'not YAML: {error.problem}')
        except yaml.YAMLError:  # a tag PyYAML does not build: rcl decides
            continue
        if isinstance(parsed, dict):
            return override_reason(name, 'a mapping, not a value')
    return None


def rcl_reason(error: object) -> str:
    """Return rcl's start-up error as one line: its sentence, without rcl's source locations."""
    text = re.sub(r', at \S+:\d+', '', str(error)).strip()
    text = re.sub(r'^failed to initialize rcl: ', '', text)
    override = re.match(re.escape(OVERRIDE_PARSE_ERROR) + r": '-p ([^=\s]+):=", text)
    if override:
        return override_reason(override.group(1), 'rcl cannot parse it')
    if 'Sequence should be of same type' in text:
        text += (' (a list holds one type: write every number of a list of doubles with a '
                 'decimal point, e.g. [0.2, 0.0, 0.05])')
    elif 'Error opening YAML file' in text:
        text += ' (no such file, or not readable)'
    return text
