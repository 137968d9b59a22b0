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

"""README's parameter table and documentation table, and the modules docs/architecture.md names."""

import math
from pathlib import Path
import re

from mouse_constraint_ros.node.parameters import PARAMETERS

ROOT = Path(__file__).resolve().parent.parent
README = ROOT / 'README.md'
ARCHITECTURE = ROOT / 'docs' / 'architecture.md'
PACKAGE = 'mouse_constraint_ros'


def yaml_literal(value) -> str:
    """Return a default as config/params.yaml and README write it."""
    if isinstance(value, bool):
        return str(value).lower()
    if isinstance(value, float) and math.isinf(value):
        return '.inf'
    if value == '':
        return "''"
    return str(value)


def test_readme_parameter_table_matches_the_declarations():
    """One row per parameter, and the default in the row is the declared one."""
    section = README.read_text().split('### Parameters', 1)[1].split('\n## ', 1)[0]
    rows = dict(re.findall(r'^\| `(\w+)` \| `([^`]*)` \|', section, re.MULTILINE))
    assert set(rows) == {p.name for p in PARAMETERS}
    for parameter in PARAMETERS:
        assert rows[parameter.name] == yaml_literal(parameter.default), parameter.name


def test_readme_closed_ranges_are_the_declared_ones():
    """
    A range README writes [low, high] is the declared one: ``ros2 param describe`` shows it.

    A value outside it is refused at start and at run time in the node's words, which name the
    same bounds (``test_startup``).
    """
    section = README.read_text().split('### Parameters', 1)[1].split('\n## ', 1)[0]
    rows = re.findall(r'^\| `(\w+)` \| `[^`]*` \| \[([^,\]]+), ([^\])]+)\] \|', section,
                      re.MULTILINE)
    declared = {p.name: p.bounds for p in PARAMETERS}
    assert len(rows) >= 10
    for name, low, high in rows:
        assert declared[name] == (float(low), float(high)), name


def architecture_module_paths():
    """
    Yield (line, path) for every module docs/architecture.md names.

    A path starting with the package's name (or test/, test_support/, bench/) is from the
    repository's root; a bare name in the bullet of a folder is in that folder; any other is in
    the package.
    """
    folder = PACKAGE
    for line in ARCHITECTURE.read_text().splitlines():
        bullet = re.match(rf'- `({PACKAGE}/[\w/]*)`:', line)
        if bullet:
            folder = bullet.group(1).rstrip('/')
        elif not line.startswith('  '):
            folder = PACKAGE
        for name in re.findall(r'`([\w/]+\.py)`', line):
            if name.split('/')[0] in (PACKAGE, 'test', 'test_support', 'bench'):
                yield line, ROOT / name
            else:
                yield line, ROOT / folder / name


def test_architecture_names_only_modules_that_exist():
    """Every module path in docs/architecture.md is a file of the package."""
    paths = list(architecture_module_paths())
    assert len(paths) > 40
    missing = [f'{path.relative_to(ROOT)} ({line.strip()})' for line, path in paths
               if not path.is_file()]
    assert not missing, missing


def test_architecture_names_what_its_modules_define():
    """A name followed by its module, as `TickGrid.due` (`.../tick_grid.py`), is defined there."""
    text = ' '.join(ARCHITECTURE.read_text().split())
    pairs = re.findall(rf'`(\w+(?:\.\w+)?)` \(`({PACKAGE}/[\w/]+\.py)`', text)
    assert len(pairs) > 15
    for symbol, module in pairs:
        source = (ROOT / module).read_text()
        for part in symbol.split('.'):
            definition = rf'^\s*(?:class|def) {part}\b'
            assert re.search(definition, source, re.MULTILINE), (symbol, module)


def test_readme_links_every_docs_page():
    """The documentation table links each page of docs/, the architecture included."""
    section = README.read_text().split('## Documentation', 1)[1]
    linked = set(re.findall(r'\]\((docs/[\w.]+\.md)\)', section))
    assert linked == {f'docs/{page.name}' for page in (ROOT / 'docs').glob('*.md')}


def _section(title: str) -> str:
    return README.read_text().split(f'## {title}', 1)[1].split('\n## ', 1)[0]


def test_the_ros_native_route_installs_what_it_needs_before_building():
    """Install with rosdep before colcon; viser at its pin for mouse_view; rviz2 for RViz."""
    section = (ROOT / 'docs' / 'launch.md').read_text()
    commands = re.search(r'```bash\n(.*?)```', section, re.S).group(1).splitlines()
    rosdep = next(i for i, line in enumerate(commands)
                  if line.startswith('rosdep install --from-paths src'))
    build = next(i for i, line in enumerate(commands) if line.startswith('colcon build'))
    assert rosdep < build
    [pin] = re.findall(r'^viser==\S+$', (ROOT / 'requirements' / 'view.txt').read_text(), re.M)
    assert f'pip install {pin}' in section
    assert 'ros-jazzy-rviz2' in section and 'rviz:=true' in section


def test_the_worked_example_gives_each_terminal_one_role():
    """Terminals are introduced in order, each once: the node, the view, commands, recorder."""
    numbers = [int(n) for n in re.findall(r'[Tt]erminal (\d+)', _section('A worked example'))]
    assert numbers == list(range(1, len(numbers) + 1)) and len(numbers) >= 4


def _anchors(page: Path) -> set:
    """Return the anchors of ``page``'s headings, as GitHub makes them."""
    titles = re.findall(r'^#+ (.+)$', page.read_text(), re.M)
    return {re.sub(r'[^\w\- ]', '', t.strip().lower()).replace(' ', '-') for t in titles}


def test_every_link_between_the_pages_resolves():
    """A link from README or docs/ to a file of the repository finds it, and its heading."""
    broken = []
    for page in [README, ROOT / 'CONTRIBUTING.md', *sorted((ROOT / 'docs').glob('*.md'))]:
        for target, anchor in re.findall(r'\]\(([\w./-]*?)(?:#([\w-]+))?\)', page.read_text()):
            if target.startswith(('http', 'mailto')):
                continue
            path = (page.parent / target) if target else page
            if not path.exists() or (anchor and anchor not in _anchors(path)):
                broken.append(f'{page.name}: {target}#{anchor}')
    assert not broken


# The pages that say what a command does and guarantees; measured figures live in
# bench/results.md (make bench writes it) and in the tests' assertions.
PROSE = [ROOT / 'Makefile', README, ROOT / 'CONTRIBUTING.md', ROOT / 'bench' / 'README.md',
         *sorted((ROOT / 'docs').glob('*.md'))]
# A command or step whose wall-clock time depends on the machine and the day.
RUN_SUBJECT = re.compile(r'make (?:test|venv|bench|lint)|\.ci/run|test-(?:unit|loaded|browser)'
                         r'|\btest (?:run|suite|tiers?)\b|\bthe suite\b|\btests (?:each|passed)\b'
                         r'|\bmaking (?:the )?venv\b|\bfresh.clone\b|\bpip install(?:s|ed)?\b'
                         r'|\buv\b', re.IGNORECASE)
DURATION = re.compile(r'\b\d+(?:\.\d+)? ?(?:min|minutes?|s|seconds?|h|hours?)\b')
MACHINE = re.compile(r'\b(?:Xeon|EPYC|Opteron|Ryzen|Threadripper|Intel|AMD|Graviton)\b'
                     r'|\b(?:\d+|two|four|eight)[- ]cores?\b', re.IGNORECASE)
COUNT = r'(?:two|three|four|five|six|seven|eight|nine|ten|(?<![.\d])[1-9]\d*)'
RUN_COUNT = re.compile(
    rf'\b{COUNT} (?:(?:loaded|fresh-clone|full|test|bench|benchmark|suite|CI|clean|more) )?runs\b'
    r'|\b(?:first|second|third|fourth|fifth|latest|last|previous|earlier) (?:[\w-]+ )?runs?\b'
    r'|\bruns? of the day\b|\bfresh-clone runs?\b|\bthe (?:bench |`make bench` )?run '
    r'(?:above|below|before)\b|\bthis run\b|\bin the bench run\b', re.IGNORECASE)


def sentences(page: Path):
    """Yield the sentences of ``page``, a Makefile's comment or a page's paragraph joined up."""
    text = page.read_text()
    if page.name == 'Makefile':
        text = '\n'.join(line.lstrip('#') if line.startswith('#') else '\n'
                         for line in text.splitlines())
    for paragraph in re.split(r'\n\s*\n', text):
        yield from re.split(r'(?<=[.;:!?])\s+(?=[A-Z`(])|\n(?=\s*[-|#]|\s*\d+\. )',
                            ' '.join(paragraph.split('\n ')).replace('\n', ' \n'))


def test_no_page_quotes_a_run_time_a_machine_or_a_run_count():
    """
    No page carries how long a test run or an install took, the machine, or which run it was.

    Those are readings of one run on one machine that go stale with the next; the pages say
    what a command does and guarantees, and link to bench/results.md for measured values.
    """
    found = []
    for page in PROSE:
        for sentence in sentences(page):
            sentence = ' '.join(sentence.split())
            hits = MACHINE.findall(sentence) + RUN_COUNT.findall(sentence)
            if RUN_SUBJECT.search(sentence):
                hits += DURATION.findall(sentence)
            if hits:
                found.append(f'{page.relative_to(ROOT)}: {hits}: {sentence[:160]}')
    assert not found, '\n'.join(found)


def test_readme_is_an_entry_point_of_at_most_250_lines():
    """README: what it is, set-up, a worked example, the interface and links; the rest in docs/."""
    assert len(README.read_text().splitlines()) <= 250


def test_no_module_is_over_500_lines():
    """
    The package's, the test support's, the benchmarks' and the launch files' modules.

    The rule is one concern per module (CONTRIBUTING.md); 500 lines flags a module that has
    likely grown a second one, to be split along the two, never squeezed to fit.
    """
    folders = ('mouse_constraint_ros', 'test_support', 'bench', 'launch', 'demo')
    modules = [path for folder in folders for path in sorted((ROOT / folder).rglob('*.py'))]
    assert len(modules) > 100
    long = {str(path.relative_to(ROOT)): count for path in modules
            if (count := len(path.read_text().splitlines())) > 500}
    assert not long


def test_every_benchmark_the_pages_name_is_in_make_bench():
    """Each ``python -m bench.NAME`` of a page is a section of the suite: make bench writes it."""
    from bench.run_all import SUITE
    suite = {name for name, _ in SUITE} | {'run_all'}
    named = {(page.relative_to(ROOT), name) for page in PROSE
             for name in re.findall(r'python -m bench\.(\w+)', page.read_text())}
    assert len(named) > 10
    assert not {(str(page), name) for page, name in named if name not in suite}


def test_readme_places_anchor_initial_position_and_pose_in_the_link_frame_of_a_urdf():
    """
    With a URDF, anchor, initial_position and pose are of the link frame (docs/bodies.md).

    README's table and conventions say so: the body frame is the box's COM, a URDF's link frame.
    """
    text = README.read_text()
    section = text.split('### Parameters', 1)[1].split('\n## ', 1)[0]
    rows = {row.split('|')[1].strip(' `'): row for row in section.splitlines()
            if row.startswith('| `')}
    for name in ('anchor', 'initial_position'):
        assert "a URDF's link frame" in rows[name] and 'COM position' not in rows[name], name
    conventions = ' '.join(text.split('Conventions: ', 1)[1].split('`twist`', 1)[0].split())
    assert '`pose` is the position and orientation' in conventions
    assert "a URDF's link frame" in conventions and 'whose origin is the COM' not in conventions
