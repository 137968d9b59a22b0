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
The bring-up files: the launch file and the RViz configuration, as colcon installs them.

One colcon build per session (``conftest.py``, shared with ``test_processes``) gives the install
the tests read. What needs the ROS ``launch`` packages is skipped where they are not importable
(the PyPI wheels do not ship them, and nothing stands in for them); the rest reads the installed
launch file's source and checks what it names against the colcon install.
"""

import ast
import os
from pathlib import Path
import signal
import subprocess
import sys

from geometry_msgs.msg import PoseStamped
import pytest
import yaml

from test_support import qt_window_state

PACKAGE = 'mouse_constraint_ros'
ROOT = Path(__file__).resolve().parent.parent
BIN = Path(sys.executable).parent
LAUNCH_FILE = 'mouse_constraint.launch.py'
RVIZ_FILE = 'mouse_constraint.rviz'
NODE_NAME = 'mouse_constraint'
# The node's topics for an empty namespace: what the RViz configuration must name.
NODE_TOPICS = {'markers': f'/{NODE_NAME}/markers', 'pose': '/pose', 'grab': '/grab',
               'target': '/target', 'marker_update': '/mouse_marker/update',
               'marker_feedback': '/mouse_marker/feedback',
               'marker_service': '/mouse_marker/get_interactive_markers',
               'robot_description': '/robot_description'}
SKIP_REASON = ('the ROS launch and launch_ros packages are not importable here (no wheel ships '
               'them; an apt ROS install or their sources provide them)')


@pytest.fixture(scope='module')
def install(colcon_install) -> Path:
    """Return the package's prefix in the session's colcon build (see ``conftest.py``)."""
    return colcon_install


def share(prefix: Path) -> Path:
    """Return the package's installed share directory under ``prefix``."""
    return prefix / 'share' / PACKAGE


def launch_calls(path: Path, name: str) -> list:
    """Return the calls of ``name`` (``DeclareLaunchArgument``, ``Node``) in a launch file."""
    tree = ast.parse(path.read_text())
    return [node for node in ast.walk(tree) if isinstance(node, ast.Call)
            and getattr(node.func, 'id', getattr(node.func, 'attr', None)) == name]


def keywords(call: ast.Call) -> dict:
    """Return a call's keyword arguments as AST nodes."""
    return {keyword.arg: keyword.value for keyword in call.keywords}


def share_path(expression: ast.AST, share_directory: Path) -> Path:
    """
    Return the path an ``os.path.join(share, 'a', 'b')`` expression of the launch file names.

    ``share`` is the package's share directory, which the launch file asks the ament index for
    (``get_package_share_directory``) and the test resolves with the same index.
    """
    assert isinstance(expression, ast.Call) and ast.unparse(expression.func) == 'os.path.join'
    first, *parts = expression.args
    assert ast.unparse(first) == 'share'
    return share_directory.joinpath(*(ast.literal_eval(part) for part in parts))


def test_colcon_installs_the_launch_rviz_and_config_files(install):
    """share/<pkg>/ launch/, rviz/ and config/ hold copies of the source tree's files."""
    examples = [('config', path.name) for path in sorted((ROOT / 'config').glob('*'))]
    assert {'tool.urdf', 'mug.urdf', 'mug.stl', 'tool.yaml', 'mug.yaml'} <= {
        name for _, name in examples}
    for folder, name in (('launch', LAUNCH_FILE), ('rviz', RVIZ_FILE), *examples):
        installed = share(install) / folder / name
        assert installed.is_file(), installed
        assert installed.read_bytes() == (ROOT / folder / name).read_bytes()


def test_the_installed_mug_finds_its_package_mesh(install, monkeypatch):
    """With the install's ament index, package://mouse_constraint_ros/config/mug.stl resolves."""
    from mouse_constraint_ros.description.urdf_link import body_model
    monkeypatch.setenv('AMENT_PREFIX_PATH', str(install))
    text = (share(install) / 'config' / 'mug.urdf').read_text()
    model = body_model(text, density=2400.0)
    assert model.geometry.collisions[0].kind == 'mesh' and model.mass > 0.3


def test_launch_file_names_the_installed_params_and_rviz_files(install, monkeypatch):
    """
    The installed launch file's defaults are the installed params.yaml and .rviz (ament index).

    Read from its source (``launch`` itself is not importable here): the share directory it asks
    the ament index for is resolved with the same index over the colcon install, and the files it
    names there exist; the node it starts is the installed executable.
    """
    path = share(install) / 'launch' / LAUNCH_FILE
    source = path.read_text()
    assert f"PACKAGE = '{PACKAGE}'" in source
    assert 'share = get_package_share_directory(PACKAGE)' in source
    monkeypatch.setenv('AMENT_PREFIX_PATH', str(install))
    from ament_index_python.packages import get_package_share_directory
    share_directory = Path(get_package_share_directory(PACKAGE))
    assert share_directory == share(install)
    arguments = {ast.literal_eval(call.args[0]): keywords(call)
                 for call in launch_calls(path, 'DeclareLaunchArgument')}
    assert list(arguments) == ['namespace', 'params_file', 'use_sim_time', 'rviz', 'urdf',
                               'body_link', 'body_frame_id', 'marker']
    # The marker server goes with RViz unless told otherwise.
    assert ast.unparse(arguments['marker']['default_value']) == "LaunchConfiguration('rviz')"
    assert all(ast.literal_eval(argument['description']) for argument in arguments.values())
    params_file = share_path(arguments['params_file']['default_value'], share_directory)
    assert params_file == share(install) / 'config' / 'params.yaml'
    assert params_file.is_file()
    calls = [keywords(call) for call in launch_calls(path, 'Node')]
    nodes = {ast.literal_eval(call['executable']): call for call in calls}
    assert list(nodes) == ['rviz2', 'mouse_constraint_node', 'mouse_marker']
    node = nodes['mouse_constraint_node']
    executable = ast.literal_eval(node['executable'])
    assert ast.unparse(node['package']) == 'PACKAGE'
    assert ast.unparse(node['name']) == 'NODE_NAME' and f"NODE_NAME = '{NODE_NAME}'" in source
    assert (install / 'lib' / PACKAGE / executable).is_file()
    assert ast.unparse(node['parameters']).startswith("[LaunchConfiguration('params_file'), {")
    parameters = ast.unparse(node['parameters'])
    assert "'body_frame_id': LaunchConfiguration('body_frame_id')" in parameters
    # The URDF file's text as a string (never YAML-parsed), read only when urdf:= is given.
    assert "'robot_description': ParameterValue(urdf_text, value_type=str)" in parameters
    assert ("urdf_text = IfElseSubstitution(NotEqualsSubstitution(urdf, ''), FileContent(urdf), "
            "'')") in source
    assert "'body_link': LaunchConfiguration('body_link')" in parameters
    assert all(ast.literal_eval(n['output']) == 'screen' for n in nodes.values())
    marker = nodes['mouse_marker']
    assert ast.unparse(marker['package']) == 'PACKAGE' and ast.unparse(marker['name']) == \
        'MARKER_NAME' and "MARKER_NAME = 'mouse_marker'" in source
    assert (install / 'lib' / PACKAGE / 'mouse_marker').is_file()
    assert ast.unparse(marker['condition']) == "IfCondition(LaunchConfiguration('marker'))"
    rviz = nodes['rviz2']
    rviz_arguments = rviz['arguments']
    assert ast.literal_eval(rviz_arguments.elts[0]) == '-d'
    rviz_file = share_path(rviz_arguments.elts[1], share_directory)
    assert rviz_file == share(install) / 'rviz' / RVIZ_FILE and rviz_file.is_file()
    assert ast.unparse(rviz['condition']) == "IfCondition(LaunchConfiguration('rviz'))"
    # RViz's absolute topic names follow the launch namespace: each is remapped to its relative
    # name, and they are the node's topics.
    assert ast.unparse(rviz['remappings']) == "[('/' + topic, topic) for topic in RVIZ_TOPICS]"
    (assignment,) = [node for node in ast.walk(ast.parse(source)) if isinstance(node, ast.Assign)
                     and ast.unparse(node.targets[0]) == 'RVIZ_TOPICS']
    topics = eval(compile(ast.Expression(assignment.value), str(path), 'eval'),
                  {'NODE_NAME': NODE_NAME, 'MARKER_NAME': 'mouse_marker'})
    assert sorted('/' + topic for topic in topics) == sorted(NODE_TOPICS.values())


def test_rviz_configuration_names_the_node_topics_and_the_world_frame():
    """The .rviz file is YAML with fixed frame world, the node's displays and two point tools."""
    configuration = yaml.safe_load((ROOT / 'rviz' / RVIZ_FILE).read_text())
    assert {'Panels', 'Visualization Manager', 'Window Geometry'} <= set(configuration)
    manager = configuration['Visualization Manager']
    assert manager['Global Options']['Fixed Frame'] == 'world'
    displays = {d['Class']: d for d in manager['Displays']}
    assert displays['rviz_default_plugins/MarkerArray']['Topic']['Value'] == \
        NODE_TOPICS['markers']
    assert displays['rviz_default_plugins/Pose']['Topic']['Value'] == NODE_TOPICS['pose']
    assert displays['rviz_default_plugins/TF']['Enabled'] is True
    robot = displays['rviz_default_plugins/RobotModel']
    assert (robot['Description Source'], robot['Description Topic']['Value'],
            robot['Description Topic']['Durability Policy']) == (
        'Topic', NODE_TOPICS['robot_description'], 'Transient Local')
    assert all(d['Enabled'] is True for d in displays.values())
    points = [t['Topic']['Value'] for t in manager['Tools']
              if t['Class'] == 'rviz_default_plugins/PublishPoint']
    assert points == [NODE_TOPICS['grab'], NODE_TOPICS['target']]
    # The interactive marker's namespace: its update topic less '/update'; and the Interact
    # tool first, the one rviz2 selects at start.
    namespace = displays['rviz_default_plugins/InteractiveMarkers'][
        'Interactive Markers Namespace']
    assert namespace + '/update' == NODE_TOPICS['marker_update']
    assert manager['Tools'][0]['Class'] == 'rviz_default_plugins/Interact'


# What rviz2 (Jazzy) reads from a .rviz, per place and per plugin class: the keys its load()
# functions ask for and the names of the properties each class creates (whose children load
# under the same names, and whose own value is the special key 'Value'). ANY: read whole, by
# names the file chooses (TF frames, marker namespaces). A key outside these is ignored.
ANY = object()
XYZ = {'X': None, 'Y': None, 'Z': None}
TREE = {'Expanded': None, 'Splitter Ratio': None}   # PropertyTreeWidget::load
# RosTopicProperty with its QosProfileProperty children (displays resubscribe when they change).
TOPIC = {'Value': None, 'Depth': None, 'History Policy': None, 'Reliability Policy': None,
         'Durability Policy': None}
PANELS = {
    'rviz_common/Displays': {'Property Tree Widget': TREE, 'Tree Height': None,
                             'Help Height': None},
    'rviz_common/Selection': {},
    'rviz_common/Tool Properties': TREE,
    'rviz_common/Views': TREE,
}
DISPLAY = {'Class': None, 'Name': None, 'Enabled': None, 'Value': None}
DISPLAYS = {
    'rviz_default_plugins/Grid': {
        'Alpha': None, 'Cell Size': None, 'Color': None,
        'Line Style': {'Value': None, 'Line Width': None}, 'Normal Cell Count': None,
        'Offset': XYZ, 'Plane': None, 'Plane Cell Count': None, 'Reference Frame': None},
    'rviz_default_plugins/MarkerArray': {'Topic': TOPIC, 'Namespaces': ANY},
    'rviz_default_plugins/Pose': {
        'Alpha': None, 'Axes Length': None, 'Axes Radius': None, 'Color': None,
        'Head Length': None, 'Head Radius': None, 'Shaft Length': None, 'Shaft Radius': None,
        'Shape': None, 'Topic': dict(TOPIC, **{'Filter size': None})},
    'rviz_default_plugins/InteractiveMarkers': {
        'Interactive Markers Namespace': None, 'Show Descriptions': None, 'Show Axes': None,
        'Show Visual Aids': None, 'Enable Transparency': None},
    'rviz_default_plugins/RobotModel': {
        'Visual Enabled': None, 'Collision Enabled': None,
        'Mass Properties': {'Mass': None, 'Inertia': None}, 'Update Interval': None,
        'Alpha': None, 'Description Source': None, 'Description File': None,
        'Description Topic': TOPIC, 'TF Prefix': None, 'Links': ANY},
    'rviz_default_plugins/TF': {
        'Frame Timeout': None, 'Frames': ANY, 'Marker Scale': None, 'Show Arrows': None,
        'Show Axes': None, 'Show Names': None, 'Tree': ANY, 'Update Interval': None,
        'Filter (blacklist)': None, 'Filter (whitelist)': None},
}
# Tool::load reads only the tool's properties: no name, no shortcut. The Publish Point tool's
# Topic has QoS children too, but its publisher is made before they are read: none is listed.
TOOLS = {
    'rviz_default_plugins/Interact': {'Hide Inactive Objects': None},
    'rviz_default_plugins/MoveCamera': {},
    'rviz_default_plugins/Select': {},
    'rviz_default_plugins/FocusCamera': {},
    'rviz_default_plugins/Measure': {'Line color': None},
    'rviz_default_plugins/PublishPoint': {'Single click': None, 'Topic': {'Value': None}},
}
VIEWS = {
    'rviz_default_plugins/Orbit': {
        'Class': None, 'Name': None, 'Value': None, 'Distance': None, 'Focal Point': XYZ,
        'Focal Shape Fixed Size': None, 'Focal Shape Size': None, 'Pitch': None, 'Yaw': None,
        'Target Frame': None, 'Invert Z Axis': None, 'Near Clip Distance': None,
        'Enable Stereo Rendering': {'Value': None, 'Stereo Eye Separation': None,
                                    'Stereo Focal Distance': None, 'Swap Stereo Eyes': None}},
}
WINDOW = {'X': None, 'Y': None, 'Width': None, 'Height': None, 'QMainWindow State': None,
          'Hide Left Dock': None, 'Hide Right Dock': None}


def unread_keys(value, schema, path: str) -> list:
    """Return the paths of the keys in ``value`` that ``schema`` does not list."""
    if schema is ANY:
        return []
    if schema is None:
        return [] if not isinstance(value, dict) else [f'{path} (a map where rviz2 reads a value)']
    if not isinstance(value, dict):
        return [f'{path} (a value where rviz2 reads a map)']
    unread = []
    for key, child in value.items():
        if key not in schema:
            unread.append(f'{path}/{key}')
        else:
            unread += unread_keys(child, schema[key], f'{path}/{key}')
    return unread


def by_class(items: list, classes: dict, base: dict, path: str) -> list:
    """Return the unread keys of a list of plugin configurations, each read by its Class."""
    unread = []
    for index, item in enumerate(items):
        name = item.get('Class')
        if name not in classes:
            unread.append(f'{path}[{index}] (class {name!r} not listed)')
        else:
            unread += unread_keys(item, {**base, 'Class': None, **classes[name]},
                                  f'{path}[{index}]')
    return unread


def test_rviz_configuration_has_only_keys_rviz2_reads():
    """
    Every key of the .rviz is one rviz2 reads (its sources, Jazzy): none is silently ignored.

    Panels, displays, tools and views by their class; the window geometry with one map per panel
    (its dock's 'collapsed'); the visualization manager's own keys.
    """
    configuration = yaml.safe_load((ROOT / 'rviz' / RVIZ_FILE).read_text())
    assert set(configuration) == {'Panels', 'Visualization Manager', 'Window Geometry'}
    panels = configuration['Panels']
    unread = by_class(panels, PANELS, {'Name': None}, '/Panels')
    geometry = dict(WINDOW, **{panel['Name']: {'collapsed': None} for panel in panels})
    unread += unread_keys(configuration['Window Geometry'], geometry, '/Window Geometry')
    manager = dict(configuration['Visualization Manager'])
    path = '/Visualization Manager'
    unread += by_class(manager.pop('Displays'), DISPLAYS, DISPLAY, path + '/Displays')
    unread += by_class(manager.pop('Tools'), TOOLS, {}, path + '/Tools')
    views = manager.pop('Views')
    unread += unread_keys(views, {'Current': ANY, 'Saved': None}, path + '/Views')
    unread += by_class([views['Current']], VIEWS, {}, path + '/Views/Current')
    unread += unread_keys(manager, {
        'Enabled': None, 'Name': None, 'Value': None,
        'Global Options': {'Background Color': None, 'Fixed Frame': None, 'Frame Rate': None},
        'Transformation': {'Current': {'Class': None}}}, path)
    assert unread == []


def test_rviz_window_state_docks_every_panel():
    """
    The QMainWindow State docks each panel by its name (rviz2 floats any it does not name).

    Displays, Views and Tool Properties are docked and shown; no panel floats; the state is the
    one docked_layout writes (read back byte for byte).
    """
    configuration = yaml.safe_load((ROOT / 'rviz' / RVIZ_FILE).read_text())
    names = [panel['Name'] for panel in configuration['Panels']]
    data = bytes.fromhex(configuration['Window Geometry']['QMainWindow State'])
    state = qt_window_state.decode(data)
    assert qt_window_state.encode(state) == data
    widgets = {widget.name: widget for widget in state.dock_widgets()}
    assert len(widgets) == len(state.dock_widgets())
    assert sorted(widgets) == sorted(names)
    assert all(not widget.flags & qt_window_state.FLOATING for widget in widgets.values())
    for name in ('Displays', 'Views', 'Tool Properties'):
        assert widgets[name].flags & qt_window_state.VISIBLE, name
    [(_, [toolbar])] = state.toolbars
    assert toolbar.name == 'Tools'   # rviz2's toolbar of tools


def test_rviz_window_state_restores_in_qt(monkeypatch):
    """
    Qt itself, where PyQt5 is importable: the state docks rviz2's floating panels as intended.

    As rviz2 does: every panel a floating dock widget named after it, then ``restoreState``;
    Qt's own ``saveState`` afterwards reads back with the decoder.
    """
    reason = 'PyQt5 is not installed (Qt: python3-pyqt5 on apt, where RViz is)'
    widgets = pytest.importorskip('PyQt5.QtWidgets', reason=reason)
    QtCore = pytest.importorskip('PyQt5.QtCore', reason=reason)
    monkeypatch.setenv('QT_QPA_PLATFORM', 'offscreen')
    configuration = yaml.safe_load((ROOT / 'rviz' / RVIZ_FILE).read_text())
    application = widgets.QApplication.instance() or widgets.QApplication(['rviz_state'])
    window = widgets.QMainWindow()
    window.setCentralWidget(widgets.QWidget())
    window.addToolBar('Tools').setObjectName('Tools')
    docks = {}
    for panel in configuration['Panels']:
        dock = docks[panel['Name']] = widgets.QDockWidget(panel['Name'])
        dock.setObjectName(panel['Name'])
        dock.setFloating(True)
        window.addDockWidget(QtCore.Qt.LeftDockWidgetArea, dock)
    geometry = configuration['Window Geometry']
    window.resize(geometry['Width'], geometry['Height'])
    assert window.restoreState(QtCore.QByteArray.fromHex(
        geometry['QMainWindow State'].encode()))
    window.show()
    application.processEvents()
    areas = {name: window.dockWidgetArea(dock) for name, dock in docks.items()}
    assert areas == {'Displays': QtCore.Qt.LeftDockWidgetArea,
                     'Selection': QtCore.Qt.RightDockWidgetArea,
                     'Tool Properties': QtCore.Qt.RightDockWidgetArea,
                     'Views': QtCore.Qt.RightDockWidgetArea}
    assert not any(dock.isFloating() for dock in docks.values())
    assert [name for name, dock in docks.items() if not dock.isVisible()] == ['Selection']
    saved = qt_window_state.decode(bytes(window.saveState()))
    assert sorted(w.name for w in saved.dock_widgets()) == sorted(docks)
    window.close()


def test_qt_window_state_reads_what_qt_writes():
    """The decoder on a state with every kind of item: tabs, nested, floating, placeholders."""
    state = qt_window_state.WindowState(
        docks={qt_window_state.LEFT: ((200, 500), qt_window_state.Sequence(
            qt_window_state.VERTICAL, [
                qt_window_state.DockWidget('a', qt_window_state.VISIBLE, (65, 250, 0, 99)),
                qt_window_state.Nested((315, 250, 0, 0), qt_window_state.Sequence(
                    qt_window_state.HORIZONTAL, [
                        qt_window_state.DockWidget('b', 0, (0, 100, 0, 0)),
                        qt_window_state.DockWidget('c', 3, (10, 20, 300, 400))], tab=1))]))},
        central_size=(800, 500), corners=qt_window_state.DEFAULT_CORNERS)
    data = qt_window_state.encode(state)
    assert qt_window_state.decode(data) == state
    assert [w.name for w in qt_window_state.decode(data).dock_widgets()] == ['a', 'b', 'c']
    with pytest.raises(ValueError):
        qt_window_state.decode(data + b'\0')
    with pytest.raises(ValueError):
        qt_window_state.decode(b'\0' * 8 + data[8:])


@pytest.fixture
def real_launch():
    """Skip the test, saying why, unless ``launch`` and ``launch_ros`` are importable."""
    pytest.importorskip('launch.actions', reason=SKIP_REASON)
    pytest.importorskip('launch_ros.actions', reason=SKIP_REASON)


def test_launch_file_parses_and_describes_its_arguments(real_launch, install, monkeypatch):
    """With the real ``launch``: the arguments ``ros2 launch -s`` lists, with their defaults."""
    from launch import LaunchContext
    from launch.launch_description_sources import get_launch_description_from_python_launch_file
    from launch.utilities import perform_substitutions

    monkeypatch.setenv('AMENT_PREFIX_PATH', str(install))
    description = get_launch_description_from_python_launch_file(
        str(share(install) / 'launch' / LAUNCH_FILE))
    arguments = description.get_launch_arguments()
    assert all(a.description and a.description != 'no description given' for a in arguments)
    for namespace, body_frame in (('', ''), ('/robot', 'robot/body'),
                                  ('/a/b/', 'a/b/body')):
        context = LaunchContext()
        context.launch_configurations['namespace'] = namespace
        defaults = {a.name: perform_substitutions(context, a.default_value) for a in arguments}
        assert defaults == {
            'namespace': '', 'params_file': str(share(install) / 'config' / 'params.yaml'),
            'use_sim_time': 'false', 'rviz': 'false', 'urdf': '', 'body_link': '',
            'body_frame_id': body_frame, 'marker': 'false'}
    choices = {a.name: a.choices for a in arguments}
    assert choices['rviz'] == choices['use_sim_time'] and {'True', 'true'} <= set(
        choices['rviz'])


def launch_process(install: Path, arguments: list) -> subprocess.Popen:
    """Start the installed launch file with the real ``launch`` in a process, output piped."""
    site_packages = next(install.glob('lib/python3*/site-packages'))
    python_path = os.pathsep.join(filter(None, [str(site_packages),
                                                os.environ.get('PYTHONPATH')]))
    environment = dict(os.environ, AMENT_PREFIX_PATH=str(install), PYTHONPATH=python_path)
    script = (
        # A handler, not SIG_IGN, so that the launched node gets SIGINT too (handlers reset
        # on exec, an ignored signal stays ignored).
        'import signal, sys; signal.signal(signal.SIGINT, signal.default_int_handler)\n'
        'from launch import LaunchService\n'
        'from launch.actions import IncludeLaunchDescription\n'
        'from launch.launch_description_sources import PythonLaunchDescriptionSource\n'
        'service = LaunchService()\n'
        'service.include_launch_description(IncludeLaunchDescription(\n'
        '    PythonLaunchDescriptionSource(sys.argv[1]),\n'
        '    launch_arguments=[a.split(":=", 1) for a in sys.argv[2:]]))\n'
        'sys.exit(service.run())\n')
    return subprocess.Popen(
        [sys.executable, '-c', script, str(share(install) / 'launch' / LAUNCH_FILE),
         *arguments], stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True,
        env=environment)


def stop(process: subprocess.Popen) -> str:
    """SIGINT the launch process, wait for it; return its output."""
    process.send_signal(signal.SIGINT)
    try:
        process.wait(timeout=15.0)
    finally:
        process.kill()
    output, _ = process.communicate()
    return output


def node_parameters(ros, node: str, names: list) -> list:
    """Return the values of ``names`` from ``node``'s parameter service (Python values)."""
    from rcl_interfaces.srv import GetParameters
    from rclpy.parameter import parameter_value_to_python

    client = ros.probe.create_client(GetParameters, f'{node}/get_parameters')
    assert ros.spin_until(client.service_is_ready, timeout=30.0)
    future = client.call_async(GetParameters.Request(names=names))
    assert ros.spin_until(future.done, timeout=10.0)
    return [parameter_value_to_python(value) for value in future.result().values]


def test_launch_starts_the_node_in_the_namespace(real_launch, ros, install):
    """
    With the real ``launch``: namespace:=/robot runs /robot/mouse_constraint on /robot/pose.

    Its body frame on /tf is robot/body, so a second instance in another namespace publishes
    another child frame.
    """
    poses = ros.collect(PoseStamped, '/robot/pose')
    process = launch_process(install, ['namespace:=/robot'])
    try:
        assert ros.spin_until(lambda: len(poses) > 10, timeout=30.0)

        def publishers() -> list:
            return [(p.node_namespace, p.node_name)
                    for p in ros.probe.get_publishers_info_by_topic('/robot/pose')]
        # The publisher's node name comes with discovery, a little after its first messages.
        assert ros.spin_until(lambda: publishers() == [('/robot', NODE_NAME)], timeout=10.0), \
            publishers()
        assert node_parameters(ros, f'/robot/{NODE_NAME}', ['body_frame_id', 'frame_id']) == [
            'robot/body', 'world']
    finally:
        output = stop(process)
    assert process.returncode == 0, output
    assert 'process has finished cleanly' in output, output


def test_launch_takes_capitalised_booleans(real_launch, ros, install):
    """use_sim_time:=True and rviz:=False are taken: the node follows /clock, no RViz."""
    process = launch_process(install, ['namespace:=/caps', 'use_sim_time:=True', 'rviz:=False',
                                       'body_frame_id:=caps_body'])
    try:
        assert node_parameters(ros, f'/caps/{NODE_NAME}', ['use_sim_time', 'body_frame_id']) == [
            True, 'caps_body']
    finally:
        output = stop(process)
    assert process.returncode == 0, output
    assert 'rviz2' not in output, output


def test_rviz_true_without_rviz2_fails_before_the_node_starts(real_launch, install):
    """
    Where rviz2 is not installed, rviz:=true exits 1 naming it, and no node was started.

    The launch process's ament index is the colcon install alone, so rviz2 is not in it.
    """
    process = launch_process(install, ['namespace:=/no_rviz', 'rviz:=true'])
    try:
        output, _ = process.communicate(timeout=60.0)
    finally:
        process.kill()
    assert process.returncode == 1, output
    assert "package 'rviz2' not found" in output, output
    assert 'mouse_constraint_node' not in output, output
