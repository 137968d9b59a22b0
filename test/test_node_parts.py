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
Each part of the node is made of a few things: at most MAX_ARGUMENTS.

A part that needs more holds more than one concern, or takes apart what belongs together: the
concern goes to a part of its own, or what belongs together into one record. Read from the
source (``ast``): the arguments of each class's ``__init__`` in ``node/``, ``self`` left out.
"""

import ast
from pathlib import Path

NODE = Path(__file__).resolve().parent.parent / 'mouse_constraint_ros' / 'node'

MAX_ARGUMENTS = 7


def part_arguments():
    """Yield (module, class, the names its ``__init__`` takes) for every class of ``node/``."""
    for path in sorted(NODE.glob('*.py')):
        for node in ast.walk(ast.parse(path.read_text(), str(path))):
            if not isinstance(node, ast.ClassDef):
                continue
            for function in node.body:
                if isinstance(function, ast.FunctionDef) and function.name == '__init__':
                    arguments = function.args
                    names = [a.arg for a in (*arguments.posonlyargs, *arguments.args,
                                             *arguments.kwonlyargs)][1:]
                    yield path.name, node.name, names


def test_no_part_of_the_node_takes_more_than_seven_things():
    """Every class of node/ is made with at most MAX_ARGUMENTS arguments."""
    parts = list(part_arguments())
    assert len(parts) > 10
    many = [f'{module}: {name}({", ".join(names)})' for module, name, names in parts
            if len(names) > MAX_ARGUMENTS]
    assert not many, '\n'.join(many)
