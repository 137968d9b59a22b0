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
The closing lines of ``make test``: every tier's outcome, the failed tests of all of them.

``make test`` runs each tier whatever the tiers before it did, and leaves per tier, in one
folder, ``NAME.status`` (pytest's exit status) and ``NAME.xml`` (its JUnit report). ``python -m
test_support.tier_summary FOLDER`` then prints a line per tier in the order they ran (its
totals, as pytest's closing line gives them), the failed tests of every tier, and exits 1
when any tier failed: a failure in the first tier no longer hides the tiers after it. A tier
that a ``-k`` of ``PYTEST_ARGS`` leaves without a test (pytest's exit 5) is no failure.
"""

from pathlib import Path
import sys
from typing import List, Tuple
from xml.etree import ElementTree

# pytest's exit status when no test was selected (e.g. PYTEST_ARGS='-k name' leaves a tier none).
NONE_SELECTED = 5


def tier_report(status_file: Path) -> Tuple[int, str, List[str]]:
    """
    Return a tier's exit status, its totals and its failed tests (``path::name``).

    :param status_file: the tier's ``NAME.status``; its report is ``NAME.xml`` beside it.
    """
    text = status_file.read_text().strip()
    status = int(text) if text.lstrip('-').isdigit() else 1
    report = status_file.with_suffix('.xml')
    try:
        root = ElementTree.parse(report).getroot()
    except (OSError, ElementTree.ParseError):
        return status, f'no report ({report.name} missing or cut short)', []
    suite = root if root.tag == 'testsuite' else root.find('testsuite')
    counts = {k: int(suite.get(k, 0)) for k in ('tests', 'failures', 'errors', 'skipped')}
    passed = counts['tests'] - counts['failures'] - counts['errors'] - counts['skipped']
    totals = ', '.join(f'{n} {word}' for n, word in (
        (counts['failures'], 'failed'), (passed, 'passed'), (counts['skipped'], 'skipped'),
        (counts['errors'], 'errors')) if n) or 'no tests ran'
    failed = []
    for case in suite.iter('testcase'):
        if case.find('failure') is not None or case.find('error') is not None:
            module = case.get('classname', '').replace('.', '/')
            failed.append(f'{module}.py::{case.get("name")}')
    return status, f'{totals} in {float(suite.get("time", 0.0)):.1f} s', failed


def main(argv: List[str]) -> int:
    """Print the summary of the tiers in ``argv[1]``; return 1 if any failed, else 0."""
    if len(argv) != 2:
        print('usage: python -m test_support.tier_summary FOLDER', file=sys.stderr)
        return 2
    statuses = sorted(Path(argv[1]).glob('*.status'))
    if not statuses:
        print(f'make test: no tier ran (nothing in {argv[1]})')
        return 1
    print('make test, every tier:')
    failed_tiers, failed_tests = [], []
    for status_file in statuses:
        status, totals, failed = tier_report(status_file)
        name = status_file.stem.split('-', 1)[-1]
        if status == NONE_SELECTED:
            print(f'  {name}: {totals} (none selected)')
            continue
        print(f'  {name}: {totals}' + (f' (exit {status})' if status else ''))
        if status:
            failed_tiers.append(name)
            failed_tests += failed
    for test in failed_tests:
        print(f'  FAILED {test}')
    if failed_tiers:
        print(f'make test: {len(failed_tiers)} of {len(statuses)} tiers failed: '
              + ', '.join(failed_tiers))
        return 1
    print(f'make test: all {len(statuses)} tiers passed')
    return 0


if __name__ == '__main__':
    sys.exit(main(sys.argv))
