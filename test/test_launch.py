"""
The bring-up files: the launch file and the RViz configuration, as colcon installs them.

One colcon build per module (as in ``test_processes``) gives the install the tests read. What
needs the ROS ``launch`` packages is skipped where they are not importable (the PyPI wheels do
not ship them); the rest reads the installed launch file with small stand-ins for ``launch``
and ``launch_ros`` that record what the file builds.
"""

import importlib.util
import os
from pathlib import Path
import signal
import subprocess
import sys
import types

from geometry_msgs.msg import PoseStamped
import pytest
import yaml

PACKAGE = 'mouse_constraint_ros'
ROOT = Path(__file__).resolve().parent.parent
BIN = Path(sys.executable).parent
LAUNCH_FILE = 'mouse_constraint.launch.py'
RVIZ_FILE = 'mouse_constraint.rviz'
NODE_NAME = 'mouse_constraint'
# The node's topics for an empty namespace: what the RViz configuration must name.
NODE_TOPICS = {'markers': f'/{NODE_NAME}/markers', 'pose': '/pose', 'grab': '/grab',
               'target': '/target'}
LAUNCH_MODULES = ('launch', 'launch.actions', 'launch.conditions', 'launch.substitutions',
                  'launch_ros', 'launch_ros.actions')
SKIP_REASON = ('the ROS launch and launch_ros packages are not importable here (no wheel ships '
               'them; an apt ROS install or their sources provide them)')


@pytest.fixture(scope='module')
def install(tmp_path_factory) -> Path:
    """Build the package with colcon into a temporary install; return the package's prefix."""
    base = tmp_path_factory.mktemp('colcon')
    environment = {'PATH': f'{BIN}:/usr/bin:/bin', 'HOME': str(base),
                   'COLCON_HOME': str(base / 'colcon_home')}
    build = subprocess.run(
        [str(BIN / 'colcon'), '--log-base', str(base / 'log'), 'build', '--base-paths',
         str(ROOT), '--build-base', str(base / 'build'), '--install-base', str(base / 'install'),
         '--event-handlers', 'console_direct-'],
        capture_output=True, text=True, cwd=base, env=environment, timeout=300)
    assert build.returncode == 0, build.stdout + build.stderr
    return base / 'install' / PACKAGE


def share(prefix: Path) -> Path:
    """Return the package's installed share directory under ``prefix``."""
    return prefix / 'share' / PACKAGE


class Recorded:
    """A stand-in for a launch class: keeps its constructor arguments."""

    def __init__(self, *args, **kwargs) -> None:
        """Record the arguments."""
        self.args, self.kwargs = args, kwargs


def stand_in_module(name: str) -> types.ModuleType:
    """Return a module whose every attribute is a ``Recorded`` subclass of that name."""
    module = types.ModuleType(name)
    module.__getattr__ = lambda attribute: type(attribute, (Recorded,), {})
    return module


def describe_with_stand_ins(path: Path, prefix: Path, monkeypatch) -> list:
    """Load the launch file at ``path`` over stand-ins, ament index at ``prefix``; its entities."""
    for name in LAUNCH_MODULES:
        monkeypatch.setitem(sys.modules, name, stand_in_module(name))
    monkeypatch.setenv('AMENT_PREFIX_PATH', str(prefix))
    spec = importlib.util.spec_from_file_location('mouse_constraint_launch', path)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    description = module.generate_launch_description()
    assert type(description).__name__ == 'LaunchDescription'
    (entities,) = description.args
    return entities


def test_colcon_installs_the_launch_and_the_rviz_files(install):
    """share/<pkg>/launch/ and share/<pkg>/rviz/ hold copies of the source tree's files."""
    for folder, name in (('launch', LAUNCH_FILE), ('rviz', RVIZ_FILE)):
        installed = share(install) / folder / name
        assert installed.is_file(), installed
        assert installed.read_bytes() == (ROOT / folder / name).read_bytes()


def test_launch_file_names_the_installed_params_and_rviz_files(install, monkeypatch):
    """The installed launch file defaults to the installed params.yaml and .rviz (ament index)."""
    entities = describe_with_stand_ins(share(install) / 'launch' / LAUNCH_FILE, install,
                                       monkeypatch)
    arguments = {e.args[0]: e.kwargs for e in entities
                 if type(e).__name__ == 'DeclareLaunchArgument'}
    assert list(arguments) == ['namespace', 'params_file', 'use_sim_time', 'rviz']
    params_file = arguments['params_file']['default_value']
    assert params_file == str(share(install) / 'config' / 'params.yaml')
    assert Path(params_file).is_file()
    assert all(argument['description'] for argument in arguments.values())
    nodes = {e.kwargs['package']: e.kwargs for e in entities if type(e).__name__ == 'Node'}
    node = nodes[PACKAGE]
    assert (node['executable'], node['name']) == ('mouse_constraint_node', NODE_NAME)
    assert (share(install).parent.parent / 'lib' / PACKAGE / node['executable']).is_file()
    (params_configuration, overrides) = node['parameters']
    assert params_configuration.args == ('params_file',)
    assert overrides['use_sim_time'].args == ('use_sim_time',)
    rviz = nodes['rviz2']
    rviz_file = rviz['arguments'][rviz['arguments'].index('-d') + 1]
    assert rviz_file == str(share(install) / 'rviz' / RVIZ_FILE)
    assert rviz['condition'].args[0].args == ('rviz',)
    # RViz's absolute topic names follow the launch namespace.
    assert dict(rviz['remappings']) == {
        topic: topic.lstrip('/') for topic in NODE_TOPICS.values()}


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
    assert all(d['Enabled'] is True for d in displays.values())
    points = [t['Topic']['Value'] for t in manager['Tools']
              if t['Class'] == 'rviz_default_plugins/PublishPoint']
    assert points == [NODE_TOPICS['grab'], NODE_TOPICS['target']]


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
    defaults = {a.name: perform_substitutions(LaunchContext(), a.default_value)
                for a in arguments}
    assert defaults == {
        'namespace': '', 'params_file': str(share(install) / 'config' / 'params.yaml'),
        'use_sim_time': 'false', 'rviz': 'false'}
    assert all(a.description and a.description != 'no description given' for a in arguments)


def test_launch_starts_the_node_in_the_namespace(real_launch, ros, install):
    """With the real ``launch``: namespace:=/robot runs /robot/mouse_constraint on /robot/pose."""
    poses = ros.collect(PoseStamped, '/robot/pose')
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
        '    launch_arguments=[("namespace", "/robot")]))\n'
        'sys.exit(service.run())\n')
    process = subprocess.Popen(
        [sys.executable, '-c', script, str(share(install) / 'launch' / LAUNCH_FILE)],
        stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True, env=environment)
    try:
        assert ros.spin_until(lambda: len(poses) > 10, timeout=30.0)
        publishers = ros.probe.get_publishers_info_by_topic('/robot/pose')
        assert [(p.node_namespace, p.node_name) for p in publishers] == [('/robot', NODE_NAME)]
    finally:
        process.send_signal(signal.SIGINT)
        try:
            process.wait(timeout=15.0)
        finally:
            process.kill()
    output, _ = process.communicate()
    assert process.returncode == 0, output
    assert 'process has finished cleanly' in output, output
