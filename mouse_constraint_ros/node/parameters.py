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
The node's parameters as plain data, and the core objects they make (no ROS here).

``PARAMETERS`` is the one table of names, defaults, units and ranges: the node declares it,
``config/params.yaml`` lists it (a test checks they match), and ``node_config`` turns values
into validated core objects, or raises ValueError: one line naming the parameter.

The ranges of the physical parameters are those of ``physics.limits``, where the step's float
arithmetic stays finite and well conditioned at every step the node can take,
h = 1 / (rate_hz substeps) from 1e-7 s to 1 s (within the core's MIN_STEP..MAX_STEP).
"""

import math
from typing import Any, Mapping, NamedTuple, Optional, Tuple

from .body_parameters import body_from, BODY_PARAMETERS, BodyFrame, BodyLoader
from .device_parameters import device_from, DEVICE_PARAMETERS, DeviceConfig
from .floor_parameters import floor_from, FLOOR_PARAMETERS
from .frame_parameters import frames_from
from .haptic_parameters import HAPTIC_PARAMETERS, soft_mode
from .robot_parameters import robot_from, ROBOT_PARAMETERS, RobotConfig, stand_in_body
from .timer_limits import FINITE_MAX, MIN_REAL_TIME_FACTOR, MIN_TIMER_RATE, off_or_at_least
from ..description import BodyGeometry
from ..physics import BodyState, MouseConstraint, Settings
from ..physics.algebra import Vector3
from ..physics.limits import (MAX_ACCELERATION, MAX_CONDITION, MAX_DISTANCE, MAX_MASS, MAX_MOMENT,
                              MIN_MASS, MIN_MOMENT)
from ..physics.settings import check_lever
from ..physics.target_motion import TargetMotion
from ..physics.validation import finite_vector, scalar, shown

# The largest real_time_factor: a million simulated seconds per wall second is beyond what the
# step can run (some 1e5 ticks per second), so a larger factor means "as fast as it can": 0.
MAX_REAL_TIME_FACTOR = 1e6


class ParameterSpec(NamedTuple):
    """One parameter: its default, what it means, and its range (for numbers) if any."""

    name: str
    default: Any
    description: str
    bounds: Optional[Tuple[float, float]] = None


PARAMETERS = (
    ParameterSpec('rate_hz', 1000.0,
                  'Physics rate (Hz), and publishing rate unless publish_rate_hz; dt = 1 / '
                  'rate_hz.',
                  (1.0, 10000.0)),
    ParameterSpec('substeps', 2, 'Equal solver substeps per tick.', (1, 1000)),
    ParameterSpec('frame_id', 'world',
                  'Frame of targets (empty frame_id is taken as this) and of pose and twist; no '
                  'leading slash (tf2 refuses it).'),
    ParameterSpec('mass', 2.0,
                  f'Body mass (kg), {MIN_MASS:g} .. {MAX_MASS:g}: beyond, the effective mass '
                  '(1 / m) or the impulses and energies (m) of the step overflow.',
                  (MIN_MASS, MAX_MASS)),
    ParameterSpec('box_size', [0.4, 0.2, 0.1],
                  f'Edge lengths of the body box (m), each in (0, {MAX_DISTANCE:g}]; gives the '
                  'inertia when inertia is all zeros, which must then be valid as below.'),
    ParameterSpec('inertia', [0.0, 0.0, 0.0, 0.0, 0.0, 0.0],
                  'Inertia about the COM, body frame, URDF order ixx ixy ixz iyy iyz izz '
                  '(kg m^2); '
                  'all zeros: a solid box of box_size and mass. Physical (positive definite, '
                  f'I1 + I2 >= I3), principal moments {MIN_MOMENT:g} .. {MAX_MOMENT:g} (the '
                  'gyroscopic step multiplies three of them), the largest at most '
                  f'{MAX_CONDITION:g} times the smallest.'),
    ParameterSpec('anchor', [0.2, 0.1, 0.05],
                  'Dragged point in the body frame (the link frame with robot_description, '
                  f"else from the box's COM) (m), at most {MAX_DISTANCE:g} m from the COM and "
                  f'with 1 + mass |r|^2 / I_min <= {MAX_CONDITION:g} for r from the COM, the '
                  'condition number of the effective mass the step solves.'),
    ParameterSpec('initial_position', [0.0, 0.0, 1.0],
                  "Body frame position (the box's COM, or the link frame) at start and after "
                  '~/reset (m, frame_id), at most '
                  f'{MAX_DISTANCE:g} m from the origin.'),
    ParameterSpec('initial_orientation', [0.0, 0.0, 0.0, 1.0],
                  'Orientation at start and after ~/reset, unit quaternion x y z w.'),
    ParameterSpec('hold_initial_anchor', True,
                  'At start and after ~/reset, hold the anchor where it starts until a target '
                  'arrives; false: start as a free body.'),
    ParameterSpec('gravity', [0.0, 0.0, -9.80665],
                  'Gravitational acceleration (m/s^2, frame_id), norm at most '
                  f'{MAX_ACCELERATION:g} (about the surface gravity of a neutron star).'),
    ParameterSpec('baumgarte', 0.2,
                  'Rigid mode: fraction of the anchor error removed per substep.',
                  (0.0, 1.0)),
    ParameterSpec('frequency_hz', 0.0,
                  'Soft mode: natural frequency of the anchor (Hz); 0 = rigid.',
                  (0.0, 1e6)),
    ParameterSpec('damping_ratio', 1.0, 'Soft mode: damping ratio (1 = critical).', (0.0, 1e6)),
    ParameterSpec('max_force', math.inf, 'Bound on the constraint force (N); .inf = unlimited.',
                  (0.0, math.inf)),
    ParameterSpec('linear_damping', 0.0, 'Linear velocity decay rate (1/s).', (0.0, FINITE_MAX)),
    ParameterSpec('angular_damping', 0.0, 'Angular velocity decay rate (1/s).', (0.0, FINITE_MAX)),
    ParameterSpec('workspace_radius', 10000.0,
                  'Targets farther than this from the origin of frame_id are ignored, like '
                  'non-finite ones (m): beyond it a drag would wreck the precision of the state.',
                  (0.0, MAX_DISTANCE)),
    ParameterSpec('target_timeout', 0.0,
                  'Release the body when no target arrived for this long (s); 0 = hold forever.',
                  (0.0, FINITE_MAX)),
    ParameterSpec('marker_rate_hz', 30.0,
                  'Rate of the RViz markers on ~/markers (Hz), on their own timer; 0 = none.',
                  (0.0, 100.0)),
    ParameterSpec('diagnostics_rate_hz', 1.0,
                  'Rate of /diagnostics (Hz), on its own timer; the achieved tick rate is '
                  'measured '
                  f'over one period. 0 = none, else at least {MIN_TIMER_RATE:g}.', (0.0, 100.0)),
    ParameterSpec('diagnostics_anchor_warn', 0.05,
                  'Anchor error (m) from which /diagnostics reports WARN.', (0.0, FINITE_MAX)),
    ParameterSpec('diagnostics_anchor_error', 0.5,
                  'Anchor error (m) from which /diagnostics reports ERROR, >= '
                  'diagnostics_anchor_warn.', (0.0, FINITE_MAX)),
    ParameterSpec('grab_margin', 0.01,
                  'A grab within this distance (m) of the body (its collision pieces, or the '
                  'box_size box, at the pose) is taken, for clicks on markers that trail the '
                  'body; farther ones are ignored.',
                  (0.0, MAX_DISTANCE)),
    ParameterSpec('publish_rate_hz', 0.0,
                  'Rate of pose, twist, TF and odometry (Hz); 0 = every tick, else at most '
                  'rate_hz. The physics still steps every tick; the publishing ticks are those '
                  'where floor(n publish_rate_hz / rate_hz) changes, n the tick number: every '
                  '(rate_hz / publish_rate_hz)-th tick when that divides, else gaps of the two '
                  'nearest whole ticks, so the mean rate is exact and stamps lie on the grid.',
                  (0.0, 10000.0)),
    ParameterSpec('publish_tf', True,
                  'Broadcast the transform frame_id -> body_frame_id on /tf at the publish '
                  'rate. Needs tf2_ros; without it TF is off, said at start and in /diagnostics.'),
    ParameterSpec('publish_odometry', False,
                  'Publish nav_msgs/Odometry on odom at the publish rate: pose in frame_id, '
                  'twist in body_frame_id (the body frame), zero covariances.'),
    ParameterSpec('body_frame_id', '',
                  "Frame of the body, the child of TF and of odometry: empty = body_link's name "
                  "with robot_description (RViz's RobotModel draws the link on it), else "
                  '"body", at the box\'s COM. No leading slash, not frame_id.'),
    ParameterSpec('publish_clock', False,
                  'Be the time source: publish /clock at every tick and stamp everything with '
                  'the simulated time (from 0), paced by real_time_factor; refused with '
                  'use_sim_time (a node cannot follow its own clock).'),
    ParameterSpec('real_time_factor', 1.0,
                  'With publish_clock: simulated seconds per wall second; 0 = as fast as the '
                  f'machine allows, else >= {MIN_REAL_TIME_FACTOR:g}; a change goes on from now.',
                  (0.0, MAX_REAL_TIME_FACTOR)),
    ParameterSpec('wrench_timeout', 0.5,
                  'Stop applying the wrench when no new one came for this long (s, of the '
                  "node's time); 0 = hold it until one replaces it.", (0.0, FINITE_MAX)),
    ParameterSpec('max_wrench_force', 1000.0,
                  'Wrenches whose force exceeds this (N) are ignored, like non-finite ones.',
                  (0.0, FINITE_MAX)),
    ParameterSpec('max_wrench_torque', 100.0,
                  'Wrenches whose torque exceeds this (N m) are ignored, like non-finite ones.',
                  (0.0, FINITE_MAX)),
    ParameterSpec('max_force_per_weight', 20.0,
                  'Bound on the constraint force in body weights, mass |gravity| (standard '
                  'gravity when gravity is zero); .inf = none. Applies with max_force.',
                  (0.0, math.inf)),
    ParameterSpec('angular_friction', 0.25,
                  'Angular friction while a target is held: the spin about the line from the '
                  'anchor to the COM is stopped by a torque of at most this times mass '
                  '|gravity| sqrt(I_mean / mass) (N m); the swing is left alone. 0 = none.',
                  (0.0, FINITE_MAX)),
    ParameterSpec('gravity_feed_forward', True,
                  'Soft mode: the joint carries the weight outright, so the spring does not sag '
                  'by |gravity| / (2 pi frequency_hz)^2.'),
    ParameterSpec('max_target_speed', 2.0,
                  'The point the joint pulls to moves toward the target at most this fast '
                  '(m/s); a click carries the body over instead of flinging it. .inf with '
                  'max_target_acceleration .inf: the joint pulls at the target itself.',
                  (0.0, math.inf)),
    ParameterSpec('max_target_acceleration', 20.0,
                  'Acceleration bound of that point (m/s^2); .inf = none.', (0.0, math.inf)),
    ParameterSpec('target_feed_forward', True,
                  'Estimate the velocity of a stream of targets (a drag) from their stamps or '
                  'arrival times and let the joint follow it, so a drag does not lag.'),
) + tuple(ParameterSpec(*spec) for spec in
          BODY_PARAMETERS + ROBOT_PARAMETERS + FLOOR_PARAMETERS + HAPTIC_PARAMETERS
          + DEVICE_PARAMETERS)

DEFAULTS = {p.name: p.default for p in PARAMETERS}


class NodeConfig(NamedTuple):
    """What the node runs with, built from its parameters and valid as a whole."""

    settings: Settings
    initial_state: BodyState
    rate_hz: float
    frame_id: str
    box_size: Vector3
    hold_initial_anchor: bool
    workspace_radius: float
    target_timeout: float
    marker_rate_hz: float
    diagnostics_rate_hz: float
    diagnostics_anchor_warn: float
    diagnostics_anchor_error: float
    grab_margin: float
    publish_rate_hz: float = 0.0
    publish_tf: bool = True
    publish_odometry: bool = False
    publish_force: bool = False
    body_frame_id: str = 'body'
    publish_clock: bool = False
    real_time_factor: float = 1.0
    wrench_timeout: float = 0.5
    max_wrench_force: float = 1000.0
    max_wrench_torque: float = 100.0
    geometry: BodyGeometry = BodyGeometry.box((0.4, 0.2, 0.1))
    body_frame: BodyFrame = BodyFrame()
    device: DeviceConfig = DeviceConfig()
    robot: Optional[RobotConfig] = None

    @property
    def anchor(self) -> Vector3:
        """Return the anchor as the ``anchor`` parameter gives it: in the body (link) frame."""
        return self.body_frame.link_point(self.settings.constraint.anchor)

    def initial_anchor(self) -> Vector3:
        """Return the anchor's world position in the initial state."""
        return self.initial_state.world_point(self.settings.constraint.anchor)


def node_config(values: Mapping[str, Any], *, load: Optional[BodyLoader] = None) -> NodeConfig:
    """
    Return the configuration for parameter ``values``; raise ValueError naming what is wrong.

    The message is one line (the node returns it as the reason of a refused ``ros2 param set``
    and logs it at start-up) and names the parameter as the user set it. ``load``: see
    ``body_parameters.body_from``.
    """
    try:
        return _configuration_from(values, load)
    except ValueError as error:
        raise ValueError(' '.join(str(error).splitlines())) from None


def _configuration_from(values: Mapping[str, Any], load: Optional[BodyLoader]) -> NodeConfig:
    rate_hz = _bounded('rate_hz', values['rate_hz'])
    substeps = values['substeps']
    # Settings checks that substeps is an integer >= 1; the node also bounds it above.
    most = BOUNDS['substeps'][1]
    if isinstance(substeps, int) and substeps > most:
        raise ValueError(f'substeps must be <= {most}, got {substeps}')
    box_size = finite_vector('box_size', values['box_size'])
    if not isinstance(values['robot_description_file'], str):
        raise ValueError('robot_description_file must be a path, got '
                         f"{shown(values['robot_description_file'])}")
    robot = robot_from(values)
    if robot is None:
        body, geometry, frame, body_name = body_from(values, load)
    else:
        if values['floor']:
            raise ValueError('floor is not served for a robot (a robot_description of several '
                             'links): set floor false, or body_link to drag one link')
        body, frame = stand_in_body(robot), BodyFrame()
        geometry = robot.links.geometry(robot.tracked_link)
        body_name = f'robot {robot.robot.structure.name!r} of mass'
    frequency_hz, damping_ratio = soft_mode(values)
    anchor = finite_vector('anchor', values['anchor'])
    constraint = MouseConstraint(
        anchor=frame.physics_point(anchor), baumgarte=values['baumgarte'],
        frequency_hz=frequency_hz, damping_ratio=damping_ratio,
        max_force=values['max_force'], max_force_per_weight=values['max_force_per_weight'],
        angular_friction=values['angular_friction'],
        gravity_feed_forward=_flag(values, 'gravity_feed_forward'))
    motion = TargetMotion(max_speed=values['max_target_speed'],
                          max_acceleration=values['max_target_acceleration'],
                          feed_forward=_flag(values, 'target_feed_forward'))
    check_lever(body, constraint.anchor, body_name=body_name)
    settings = Settings(body, constraint, gravity=values['gravity'],
                        linear_damping=values['linear_damping'],
                        angular_damping=values['angular_damping'], substeps=substeps,
                        target_motion=motion, floor=floor_from(
                            values, box_size, geometry.collision_shape()
                            if values['robot_description'] else None))
    initial_state = frame.physics_state(BodyState(
        values['initial_position'], values['initial_orientation']).validated(prefix='initial_'))
    settings.floor.check_state(initial_state.position, initial_state.orientation)
    frame_id, body_frame_id = frames_from(values, geometry.link)
    # A robot starts free: its anchor's first world point is its own, not the box's.
    hold = _flag(values, 'hold_initial_anchor') and robot is None
    anchor_warn = scalar('diagnostics_anchor_warn', values['diagnostics_anchor_warn'], above=0.0)
    anchor_error = scalar('diagnostics_anchor_error', values['diagnostics_anchor_error'],
                          at_least=anchor_warn)
    return NodeConfig(
        settings=settings,
        initial_state=initial_state,
        rate_hz=rate_hz,
        frame_id=frame_id,
        box_size=box_size,
        hold_initial_anchor=hold,
        workspace_radius=scalar('workspace_radius', values['workspace_radius'], above=0.0,
                                at_most=MAX_DISTANCE),
        target_timeout=scalar('target_timeout', values['target_timeout'], at_least=0.0),
        marker_rate_hz=_bounded('marker_rate_hz', values['marker_rate_hz'], MIN_TIMER_RATE),
        diagnostics_rate_hz=_bounded('diagnostics_rate_hz', values['diagnostics_rate_hz'],
                                     MIN_TIMER_RATE),
        diagnostics_anchor_warn=anchor_warn,
        diagnostics_anchor_error=anchor_error,
        grab_margin=scalar('grab_margin', values['grab_margin'], at_least=0.0,
                           at_most=MAX_DISTANCE),
        body_frame_id=body_frame_id,
        **_publishing(values, rate_hz),
        **_simulator_controls(values),
        geometry=geometry,
        body_frame=frame,
        device=device_from(values),
        robot=robot,
    )


def _publishing(values: Mapping[str, Any], rate_hz: float) -> dict:
    """Return the checked publish_rate_hz and the publishing switches."""
    publish_rate = scalar('publish_rate_hz', values['publish_rate_hz'], at_least=0.0)
    if publish_rate > rate_hz:
        raise ValueError(f'publish_rate_hz must be 0.0 (every tick) or within (0, rate_hz] = '
                         f'(0, {rate_hz!r}], got {publish_rate!r}')
    switches = {name: _flag(values, name)
                for name in ('publish_tf', 'publish_odometry', 'publish_force')}
    return {'publish_rate_hz': publish_rate, **switches}


def _simulator_controls(values: Mapping[str, Any]) -> dict:
    """Return the validated clock and wrench fields of NodeConfig."""
    publish_clock = _flag(values, 'publish_clock')
    return {
        'publish_clock': publish_clock,
        'real_time_factor': _bounded('real_time_factor', values['real_time_factor'],
                                     MIN_REAL_TIME_FACTOR),
        'wrench_timeout': scalar('wrench_timeout', values['wrench_timeout'], at_least=0.0),
        'max_wrench_force': scalar('max_wrench_force', values['max_wrench_force'],
                                   at_least=0.0),
        'max_wrench_torque': scalar('max_wrench_torque', values['max_wrench_torque'],
                                    at_least=0.0),
    }


def _flag(values: Mapping[str, Any], name: str) -> bool:
    """Return the boolean parameter ``name``, or raise ValueError naming it."""
    value = values[name]
    if not isinstance(value, bool):
        raise ValueError(f'{name} must be true or false, got {shown(value)}')
    return value


def _bounded(name: str, value: Any, off_below: float = 0.0) -> float:
    """Return ``value`` checked against the range of ``name``: 0 or >= ``off_below`` too."""
    low, high = BOUNDS[name]
    return off_or_at_least(name, scalar(name, value, at_least=low, at_most=high), off_below)


BOUNDS = {p.name: p.bounds for p in PARAMETERS if p.bounds is not None}
