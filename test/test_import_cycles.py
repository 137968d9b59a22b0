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
No module imports itself back: the import graph of the package, the benches and their support.

The graph is read from the source (``ast``), not from an import: every ``import`` and ``from
... import`` of a module, a function's own too, is an edge to the module of the repository it
names (``from a import b`` is ``a.b`` when that is a module, else ``a``). Two modules in one
circle hold one concern between them, or each holds a piece of the other's: the piece goes
where it belongs. A circle found is named, module by module.
"""

import ast
from pathlib import Path
from typing import Dict, Iterator, List, Optional, Set

ROOT = Path(__file__).resolve().parent.parent

# The folders whose modules the graph holds: the package, the benches and what they share.
PACKAGES = ('mouse_constraint_ros', 'bench', 'test_support')


def module_name(path: Path, root: Path = ROOT) -> str:
    """Return the dotted name of the module at ``path``: a package's is its folder's."""
    parts = list(path.relative_to(root).with_suffix('').parts)
    return '.'.join(parts[:-1] if parts[-1] == '__init__' else parts)


def repository_modules() -> Dict[str, Path]:
    """Return every module of PACKAGES by its dotted name."""
    return {module_name(path): path
            for package in PACKAGES for path in sorted((ROOT / package).rglob('*.py'))}


def innermost(name: str, modules: Dict[str, Path]) -> Optional[str]:
    """Return the module of ``modules`` that ``name`` is or lies in; None for another's."""
    parts = name.split('.')
    while parts and '.'.join(parts) not in modules:
        parts.pop()
    return '.'.join(parts) if parts else None


def imports(name: str, modules: Dict[str, Path]) -> Iterator[str]:
    """Yield each module of ``modules`` that the module ``name`` imports, anywhere in it."""
    path = modules[name]
    package = name.split('.') if path.name == '__init__.py' else name.split('.')[:-1]
    for node in ast.walk(ast.parse(path.read_text(), str(path))):
        if isinstance(node, ast.Import):
            names = [alias.name for alias in node.names]
        elif isinstance(node, ast.ImportFrom):
            base = package[:len(package) - node.level + 1] if node.level else []
            source = '.'.join(base + (node.module.split('.') if node.module else []))
            # ``from a import b``: the module ``a.b`` if there is one, else a name of ``a``.
            names = [f'{source}.{alias.name}' if f'{source}.{alias.name}' in modules
                     else source for alias in node.names]
        else:
            continue
        for imported in names:
            target = innermost(imported, modules)
            if target is not None:
                yield target


def import_graph(modules: Dict[str, Path]) -> Dict[str, Set[str]]:
    """Return module -> the modules of ``modules`` it imports (itself left out)."""
    return {name: set(imports(name, modules)) - {name} for name in modules}


def cycles(graph: Dict[str, Set[str]]) -> List[List[str]]:
    """Return one circle through each strongly connected set of modules (Tarjan), first first."""
    index: Dict[str, int] = {}
    low: Dict[str, int] = {}
    stack: List[str] = []
    on_stack: Set[str] = set()
    found = []

    def visit(node: str) -> None:
        index[node] = low[node] = len(index)
        stack.append(node)
        on_stack.add(node)
        for target in sorted(graph[node]):
            if target not in index:
                visit(target)
                low[node] = min(low[node], low[target])
            elif target in on_stack:
                low[node] = min(low[node], index[target])
        if low[node] == index[node]:
            members = set()
            while True:
                member = stack.pop()
                on_stack.discard(member)
                members.add(member)
                if member == node:
                    break
            if len(members) > 1:
                found.append(circle(graph, members))

    for node in sorted(graph):
        if node not in index:
            visit(node)
    return sorted(found)


def circle(graph: Dict[str, Set[str]], members: Set[str]) -> List[str]:
    """Return a shortest circle from the first of ``members`` back to it, inside them."""
    start = min(members)
    paths = {start: [start]}
    frontier = [start]
    while frontier:
        following = []
        for node in frontier:
            for target in sorted(graph[node] & members):
                if target == start:
                    return paths[node] + [start]
                if target not in paths:
                    paths[target] = paths[node] + [target]
                    following.append(target)
        frontier = following
    raise AssertionError(f'no circle through {sorted(members)}')


def test_the_graph_sees_imports_inside_functions_and_relative_ones(tmp_path):
    """A function's own import and a relative one are edges; a name imported is its module's."""
    package = tmp_path / 'pkg'
    package.mkdir()
    (package / '__init__.py').write_text('')
    (package / 'one.py').write_text('from . import two\nVALUE = 1\n')
    (package / 'two.py').write_text('def late():\n    from .three import run\n')
    (package / 'three.py').write_text('from pkg.one import VALUE\n\ndef run():\n    pass\n')
    modules = {module_name(path, tmp_path): path for path in sorted(package.rglob('*.py'))}
    graph = import_graph(modules)
    assert graph['pkg.one'] == {'pkg.two'}
    assert graph['pkg.two'] == {'pkg.three'}
    assert graph['pkg.three'] == {'pkg.one'}
    assert cycles(graph) == [['pkg.one', 'pkg.two', 'pkg.three', 'pkg.one']]


def test_no_module_imports_itself_back():
    """No circle of imports among the package's, the benches' and their support's modules."""
    graph = import_graph(repository_modules())
    assert len(graph) > 200 and sum(len(targets) for targets in graph.values()) > 500
    # A function's own import is an edge: the console script imports its command late.
    assert 'mouse_constraint_ros.cli.ctl' in graph['mouse_constraint_ros.cli.console']
    found = cycles(graph)
    assert not found, 'import circles:\n' + '\n'.join(' -> '.join(c) for c in found)
