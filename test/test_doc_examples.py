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
The code blocks of README.md and docs/*.md run as written, so that none drifts from the code.

Every ``python`` block runs, in a namespace of its own, unless an HTML comment on the line
before it says what it is instead: ``<!-- example: test/NAME.py -->``, a test module shown as
it is below its licence header (pytest runs it), or ``<!-- example: not run, WHY -->``. The
example in ``mouse_constraint_ros.testing``'s docstring runs too. The command lines of the
shell blocks that run ``mouse_target``, ``mouse_wrench``, ``mouse_record`` or ``mouse_ctl``
parse with the command's own parser, and each ``-p name:=value`` they give names a parameter of
the node.
"""

from pathlib import Path
import re
import shlex
from typing import Iterator, NamedTuple

import pytest
from rclpy.utilities import remove_ros_args

from mouse_constraint_ros.cli import ctl, record, target, wrench
from mouse_constraint_ros.node.parameters import PARAMETERS
import mouse_constraint_ros.testing

ROOT = Path(__file__).resolve().parent.parent
PAGES = [ROOT / 'README.md', *sorted((ROOT / 'docs').glob('*.md'))]
MARK = re.compile(r'<!-- example: (.+?) -->')
PARSERS = {'mouse_target': target.build_parser, 'mouse_wrench': wrench.build_parser,
           'mouse_record': record.build_parser, 'mouse_ctl': ctl.build_parser}
# Parameters any ROS node takes besides the node's own.
ROS_PARAMETERS = {'use_sim_time'}


class Block(NamedTuple):
    """A fenced code block: its page, the line of its fence, its language, mark and code."""

    page: Path
    line: int
    language: str
    mark: str
    code: str

    def name(self) -> str:
        """Return where it is, as ``page:line``."""
        return f'{self.page.relative_to(ROOT)}:{self.line}'


def blocks() -> Iterator[Block]:
    """Yield every fenced block of the pages, with the mark on the line before it, if any."""
    for page in PAGES:
        lines = page.read_text().splitlines()
        index = 0
        while index < len(lines):
            fence = re.match(r'^```(\w*)\s*$', lines[index])
            if not fence:
                index += 1
                continue
            end = lines.index('```', index + 1)
            mark = MARK.fullmatch(lines[index - 1].strip()) if index else None
            yield Block(page, index + 1, fence.group(1), mark.group(1) if mark else '',
                        '\n'.join(lines[index + 1:end]) + '\n')
            index = end + 1


PYTHON = [block for block in blocks() if block.language == 'python']
SHELL = [block for block in blocks() if block.language in ('bash', 'console', 'sh')]


def test_the_pages_have_python_blocks_and_each_is_run_or_marked():
    """Each python block runs, is a test module, or says why it is not run."""
    assert len(PYTHON) >= 2
    for block in PYTHON:
        assert block.mark == '' or block.mark.startswith(('test/', 'not run, ')), block.name()


def docstring_example() -> str:
    """Return the example of ``mouse_constraint_ros.testing``'s docstring, dedented."""
    text = mouse_constraint_ros.testing.__doc__.split('::\n\n', 1)[1]
    lines = []
    for line in text.splitlines():
        if line and not line.startswith('    '):
            break
        lines.append(line[4:])
    return '\n'.join(lines).strip() + '\n'


RUNNABLE = [pytest.param(block.code, id=block.name()) for block in PYTHON if not block.mark]
RUNNABLE.append(pytest.param(docstring_example(), id='mouse_constraint_ros.testing'))


@pytest.mark.ros
@pytest.mark.parametrize('code', RUNNABLE)
def test_each_python_example_runs_as_written(code):
    """The example runs to its end: its assertions hold."""
    exec(compile(code, 'example', 'exec'), {'__name__': 'example'})


@pytest.mark.parametrize('block', [b for b in PYTHON if b.mark.startswith('test/')],
                         ids=Block.name)
def test_a_block_marked_as_a_test_module_is_that_module(block):
    """The block is the module below its licence header, which pytest runs."""
    source = (ROOT / block.mark).read_text()
    body = source.split('# limitations under the License.\n\n', 1)[1]
    assert block.code == body


# The package's executables (setup.py's console scripts), as ``ros2 run`` names them.
SCRIPTS = (ROOT / 'setup.py').read_text().split("'console_scripts': [", 1)[1].split(']', 1)[0]
EXECUTABLES = set(re.findall(r"'(\w+) = ", SCRIPTS))
PACKAGE_RUN = ['ros2', 'run', 'mouse_constraint_ros']


def command_lines() -> Iterator[tuple]:
    """
    Yield (block, command, arguments) for each shell line that runs one of the commands.

    A command is named by its path (``.venv/bin/mouse_target``) or run by ``ros2 run
    mouse_constraint_ros NAME``, whatever ``NAME`` is: the test of the line checks it.
    """
    for block in SHELL:
        for line in block.code.replace('\\\n', ' ').splitlines():
            line = line.removeprefix('$ ').split(' #')[0].split('&')[0].strip()
            words = shlex.split(line) if line else []
            for index, word in enumerate(words):
                command = Path(word).name
                if words[index:index + 3] == PACKAGE_RUN and len(words) > index + 3:
                    yield block, words[index + 3], words[index + 4:]
                    break
                if command in PARSERS or command == 'mouse_constraint_node':
                    yield block, command, words[index + 1:]
                    break


def test_the_shell_blocks_run_the_commands():
    """The pages show each command at least once."""
    shown = {command for _, command, _ in command_lines()}
    assert set(PARSERS) | {'mouse_constraint_node'} <= shown


@pytest.mark.parametrize('line', [pytest.param((command, words), id=f'{block.name()} {command}')
                                  for block, command, words in command_lines()])
def test_each_command_line_shown_parses(line):
    """The command is the package's, its arguments parse; -p names a parameter of the node."""
    command, words = line
    assert command in EXECUTABLES, command
    names = {p.name for p in PARAMETERS} | ROS_PARAMETERS
    given = [words[i + 1].split(':=')[0] for i, word in enumerate(words[:-1]) if word == '-p']
    assert set(given) <= names, given
    if command in PARSERS:
        PARSERS[command]().parse_args(remove_ros_args(['command', *words])[1:])


@pytest.mark.parametrize('page, commands', [
    ('README.md', {'mouse_target', 'mouse_wrench', 'mouse_record', 'mouse_ctl'}),
    ('docs/haptics.md', {'mouse_constraint_node'})])
def test_readme_and_the_haptics_page_show_commands_whose_lines_are_parsed(page, commands):
    """The worked example's commands, and the node started for a haptic device, are checked."""
    shown = {command for block, command, _ in command_lines() if block.page == ROOT / page}
    assert commands <= shown
