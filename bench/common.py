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
Helpers shared by the benchmark modules: timing, medians, machine facts and the results files.

A benchmark module exposes ``run(quick: bool) -> dict`` returning a *section*:

- ``title``: the heading in results.md;
- ``text``: a paragraph saying what was measured and how;
- ``columns``: a list of ``[key, header, format]``, ``format`` a format spec such as ``'.3f'``
  or ``''`` for plain text;
- ``rows``: a list of dicts keyed by the column keys (a missing or None value prints as '-');
- ``notes``: a list of strings printed under the table.

``bench.run_all`` collects the sections under their module names and writes both files.
"""

import datetime
import gc
import importlib
import importlib.metadata
import json
import math
import os
from pathlib import Path
import platform
import statistics
import subprocess
import sys
import time
from typing import Callable, Dict, List, Optional, Sequence

import numpy as np

ROOT = Path(__file__).resolve().parent.parent

# The peers a benchmark may compare with: import name -> distribution name on PyPI.
PEERS = {'pybullet': 'pybullet', 'mujoco': 'mujoco'}

# The body of every scenario: the solid box of the physics tests, and its corner as the anchor.
BOX_MASS = 2.0
BOX_EXTENTS = (0.4, 0.2, 0.1)
CORNER = (0.2, 0.1, 0.05)


def median(values: Sequence[float]) -> float:
    """Return the median of ``values``."""
    return float(statistics.median(values))


def import_peer(name: str):
    """Return the peer's module, or None when it cannot be imported here."""
    try:
        return importlib.import_module(name)
    except Exception:  # A broken install is as good as a missing one here.
        return None


def peer_versions() -> Dict[str, str]:
    """Return each peer's installed version, or why it is not available."""
    versions = {}
    for module, distribution in PEERS.items():
        if import_peer(module) is None:
            versions[module] = 'not installed (skipped)'
            continue
        try:
            versions[module] = importlib.metadata.version(distribution)
        except importlib.metadata.PackageNotFoundError:
            versions[module] = getattr(sys.modules[module], '__version__', 'unknown')
    return versions


def per_call_microseconds(loop: Callable[[int], None], calls: int) -> float:
    """Return the microseconds per call of ``loop(calls)``, which makes ``calls`` calls."""
    enabled = gc.isenabled()
    gc.disable()
    try:
        start = time.perf_counter()
        loop(calls)
        elapsed = time.perf_counter() - start
    finally:
        if enabled:
            gc.enable()
    return 1e6 * elapsed / calls


def time_interleaved(loops: Dict[str, Callable[[int], None]], repeats: int,
                     seconds_per_repeat: float) -> Dict[str, List[float]]:
    """
    Time several loops in turn, ``repeats`` rounds each; return microseconds per call, per round.

    Each ``loops[name](n)`` makes n calls of what is measured. The rounds interleave the loops
    (a, b, c, a, b, c, ...) so that a slow spell of a shared machine hits all of them alike;
    the call count of each loop is set from a warm-up so that one round takes about
    ``seconds_per_repeat``.
    """
    calls = {}
    for name, loop in loops.items():
        loop(50)
        estimate = per_call_microseconds(loop, 500)
        calls[name] = max(200, int(seconds_per_repeat * 1e6 / estimate))
    samples: Dict[str, List[float]] = {name: [] for name in loops}
    for _ in range(repeats):
        for name, loop in loops.items():
            samples[name].append(per_call_microseconds(loop, calls[name]))
    return samples


def paired_ratio(numerator: Sequence[float], denominator: Sequence[float]) -> float:
    """Return the median over rounds of numerator[i] / denominator[i] (same-round ratios)."""
    return median([a / b for a, b in zip(numerator, denominator)])


def rms(values: np.ndarray) -> float:
    """Return the root mean square of the norms of the rows of ``values`` (or of a 1-D array)."""
    values = np.asarray(values, dtype=float)
    if values.ndim == 2:
        values = np.linalg.norm(values, axis=1)
    return float(np.sqrt(np.mean(values * values)))


def _cpu_model() -> str:
    try:
        for line in Path('/proc/cpuinfo').read_text().splitlines():
            if line.lower().startswith('model name'):
                return line.split(':', 1)[1].strip()
    except OSError:
        pass
    return platform.processor() or 'unknown'


def _git_commit() -> Optional[str]:
    try:
        result = subprocess.run(['git', 'describe', '--always', '--dirty'], cwd=ROOT,
                                capture_output=True, text=True, timeout=10)
    except (OSError, subprocess.SubprocessError):
        return None
    return result.stdout.strip() or None


def machine_info() -> dict:
    """Return what the numbers depend on: CPU, cores, Python, numpy, peers, date, commit."""
    try:
        usable = len(os.sched_getaffinity(0))
    except AttributeError:
        usable = os.cpu_count()

    def version(distribution: str) -> str:
        try:
            return importlib.metadata.version(distribution)
        except importlib.metadata.PackageNotFoundError:
            return 'not installed'

    return {
        'cpu': _cpu_model(),
        'cores': os.cpu_count(),
        'cores_usable': usable,
        'platform': platform.platform(),
        'python': platform.python_version(),
        'python_implementation': platform.python_implementation(),
        'numpy': np.__version__,
        'scipy': version('scipy'),
        'rclpy': version('rclpy'),
        'peers': peer_versions(),
        'load_average_at_start': list(os.getloadavg()),
        'openblas_env': {k: os.environ[k] for k in ('OPENBLAS_CORETYPE', 'OPENBLAS_L2_SIZE')
                         if k in os.environ},
        'date': datetime.datetime.now(datetime.timezone.utc).isoformat(timespec='seconds'),
        'commit': _git_commit(),
    }


def _cell(value, spec: str) -> str:
    if value is None:
        return '-'
    if isinstance(value, float):
        if math.isnan(value):
            return 'n/a'
        if math.isinf(value):
            return 'inf'
        return format(value, spec) if spec else repr(value)
    return format(value, spec) if spec and not isinstance(value, str) else str(value)


def measured_line(measured: dict, run: Optional[dict] = None) -> str:
    """
    Return the line under a section that says which run measured it.

    A section kept from an earlier run than ``run`` (the header's date and commit) says so,
    with that run's peers and CPU where it recorded them: its rows are not the header's run.
    """
    when = f'{measured["date"]} (commit {measured["commit"]}'
    peers = measured.get('peers')
    if run is None or (measured['date'], measured['commit']) == (run['date'], run['commit']):
        return f'_Measured on {when})._'
    recorded = ('peers ' + ', '.join(f'{name} {version}' for name, version in peers.items())
                if peers else 'its peers not recorded')
    if measured.get('cpu'):
        recorded += f', CPU {measured["cpu"]}'
    return f"_Kept from an earlier run than the header's: measured on {when}; {recorded})._"


def section_markdown(section: dict, run: Optional[dict] = None) -> str:
    """
    Return one section as markdown: heading, paragraph, table and notes.

    :param run: the date and commit of the run that writes the file, to mark an older section.
    """
    lines = [f'## {section["title"]}', '']
    if section.get('text'):
        lines += [section['text'], '']
    columns = section.get('columns', [])
    rows = section.get('rows', [])
    if columns and rows:
        lines.append('| ' + ' | '.join(header for _, header, _ in columns) + ' |')
        lines.append('|' + '|'.join(
            ' --- ' if spec == '' else ' ---: ' for _, _, spec in columns) + '|')
        for row in rows:
            lines.append('| ' + ' | '.join(
                _cell(row.get(key), spec) for key, _, spec in columns) + ' |')
        lines.append('')
    for note in section.get('notes', []):
        lines.append(f'- {note}')
    if section.get('notes'):
        lines.append('')
    if 'elapsed_s' in section:
        lines += [f'_Section run time: {section["elapsed_s"]:.0f} s._', '']
    if 'measured' in section:
        lines += [measured_line(section['measured'], run), '']
    return '\n'.join(lines)


def results_markdown(results: dict) -> str:
    """Return the whole of results.md for the ``results`` dict that run_all writes as JSON."""
    machine = results['machine']
    peers = ', '.join(f'{name} {version}' for name, version in machine['peers'].items())
    lines = [
        '# Benchmarks',
        '',
        f'Written by `python -m bench.run_all` on {machine["date"]} (commit {machine["commit"]}, '
        '"-dirty": uncommitted changes in the tree); '
        f'the raw numbers are in `results.json`.',
        '',
        f'- CPU: {machine["cpu"]}, {machine["cores"]} cores ({machine["cores_usable"]} usable)',
        f'- {machine["python_implementation"]} {machine["python"]}, numpy {machine["numpy"]}, '
        f'scipy {machine["scipy"]}, rclpy {machine.get("rclpy", "-")}',
        f'- Peers in this run: {peers}; a section kept from an earlier run (`--only`) says so '
        'under it, with its own date, commit and peers',
        f'- Platform: {machine["platform"]}; load average at start (1, 5, 15 min): '
        + ', '.join(f'{x:.2f}' for x in machine['load_average_at_start']),
        f'- Suite run time: {results["elapsed_s"]:.0f} s'
        + (' (quick mode: fewer repeats, shorter runs)' if results.get('quick') else ''),
        '',
    ]
    for name, section in results['sections'].items():
        if 'error' in section:
            lines += [f'## {name}', '', f'Failed: `{section["error"]}`', '']
        else:
            lines.append(section_markdown(section, machine))
    return '\n'.join(lines).rstrip() + '\n'


def _jsonable(value):
    if isinstance(value, dict):
        return {str(k): _jsonable(v) for k, v in value.items()}
    if isinstance(value, (list, tuple)):
        return [_jsonable(v) for v in value]
    if isinstance(value, (np.floating, float)):
        value = float(value)
        return value if math.isfinite(value) else str(value)
    if isinstance(value, np.integer):
        return int(value)
    if isinstance(value, np.bool_):
        return bool(value)
    return value


def write_results(results: dict, directory: Path) -> None:
    """Write ``results.json`` and ``results.md`` into ``directory``."""
    directory.mkdir(parents=True, exist_ok=True)
    (directory / 'results.json').write_text(
        json.dumps(_jsonable(results), indent=2) + '\n')
    (directory / 'results.md').write_text(results_markdown(results))
