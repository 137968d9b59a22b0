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

"""``bench.run_all --only``: the sections it runs replace theirs; the others stay, dated."""

import json

from bench import common
from bench.run_all import kept_sections, SUITE


def test_a_partial_run_keeps_the_other_sections_in_suite_order_with_their_date(tmp_path):
    """Fresh sections replace theirs; kept ones take the old file's date unless they have one."""
    names = [name for name, _ in SUITE]
    first, second, third = names[0], names[1], names[2]
    old = {'machine': {'date': '2026-01-01', 'commit': 'abc'},
           'sections': {third: {'title': 'old third'}, first: {'title': 'old first'},
                        second: {'title': 'old second',
                                 'measured': {'date': '2025-12-31', 'commit': 'def'}}}}
    path = tmp_path / 'results.json'
    path.write_text(json.dumps(old))
    fresh = {second: {'title': 'new second', 'measured': {'date': 'now', 'commit': 'ghi'}}}
    merged = kept_sections(path, fresh)
    assert list(merged) == [first, second, third]
    assert merged[second] == fresh[second]
    assert merged[first] == {'title': 'old first',
                             'measured': {'date': '2026-01-01', 'commit': 'abc'}}
    assert kept_sections(tmp_path / 'absent.json', fresh) == fresh


def test_each_section_says_when_it_was_measured():
    """results.md carries a section's date and commit under it."""
    text = common.section_markdown({'title': 'T', 'text': '', 'rows': [], 'notes': [],
                                    'measured': {'date': '2026-12-06', 'commit': '1234567'}})
    assert '_Measured on 2026-12-06 (commit 1234567)._' in text
