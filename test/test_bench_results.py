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


def test_a_section_kept_from_an_earlier_run_is_marked_with_that_run_s_peers():
    """
    The header's peers are its run's; a section of another run says so, with its own peers.

    A run without the peers (``--only``, outside ``make bench``) keeps a section whose PyBullet
    rows an earlier run measured: that section is marked as kept, not passed off as this run's.
    """
    peers = {'pybullet': '3.2.7', 'mujoco': '4.0.0'}
    missing = {'pybullet': 'not installed (skipped)', 'mujoco': 'not installed (skipped)'}
    results = {
        'machine': {'cpu': 'c', 'cores': 2, 'cores_usable': 2, 'platform': 'p', 'python': '3',
                    'python_implementation': 'CPython', 'numpy': '2', 'scipy': '1',
                    'rclpy': '7', 'peers': missing, 'load_average_at_start': [0.0] * 3,
                    'date': '2026-12-07', 'commit': 'new'},
        'elapsed_s': 1.0,
        'sections': {
            'core_cost': {'title': 'Peers', 'columns': [('engine', 'engine', '')],
                          'rows': [{'engine': 'PyBullet multibody'}],
                          'measured': {'date': '2026-12-06', 'commit': 'old', 'peers': peers}},
            'soak': {'title': 'Older', 'measured': {'date': '2026-12-05', 'commit': 'older'}},
            'device_stream': {'title': 'Fresh',
                              'measured': {'date': '2026-12-07', 'commit': 'new',
                                           'peers': missing}}}}
    text = common.results_markdown(results)
    assert '- Peers in this run: pybullet not installed (skipped), mujoco not installed ' \
           '(skipped); a section kept from an earlier run' in text
    kept = text.split('## Peers', 1)[1].split('## Older', 1)[0]
    assert "_Kept from an earlier run than the header's: measured on 2026-12-06 (commit old; " \
           'peers pybullet 3.2.7, mujoco 4.0.0)._' in kept
    assert '(commit older; its peers not recorded)._' in text.split('## Older', 1)[1]
    fresh = text.split('## Fresh', 1)[1]
    assert '_Measured on 2026-12-07 (commit new)._' in fresh and 'Kept' not in fresh


def test_the_shipped_results_mark_every_section_not_of_the_header_s_run():
    """bench/results.md: each section is of the header's run, or marked as kept from another."""
    results = json.loads((common.ROOT / 'bench' / 'results.json').read_text())
    machine = results['machine']
    text = (common.ROOT / 'bench' / 'results.md').read_text()
    assert text == common.results_markdown(results)
    for name, section in results['sections'].items():
        measured = section['measured']
        own = (measured['date'], measured['commit']) == (machine['date'], machine['commit'])
        assert own or "_Kept from an earlier run than the header's: measured on " \
            f"{measured['date']} (commit {measured['commit']};" in text, name


def test_a_kept_section_of_the_old_header_s_run_takes_its_peers_and_cpu(tmp_path):
    """The old file's header says the peers and CPU of the sections measured with it."""
    names = [name for name, _ in SUITE]
    old = {'machine': {'date': 'd1', 'commit': 'c1', 'cpu': 'Xeon',
                       'peers': {'pybullet': 'not installed (skipped)'}},
           'sections': {names[0]: {'title': 'of d1', 'measured': {'date': 'd1', 'commit': 'c1'}},
                        names[1]: {'title': 'of d0', 'measured': {'date': 'd0', 'commit': 'c0'}}}}
    path = tmp_path / 'results.json'
    path.write_text(json.dumps(old))
    merged = kept_sections(path, {})
    assert merged[names[0]]['measured'] == {'date': 'd1', 'commit': 'c1', 'cpu': 'Xeon',
                                            'peers': {'pybullet': 'not installed (skipped)'}}
    assert merged[names[1]]['measured'] == {'date': 'd0', 'commit': 'c0'}
    line = common.measured_line(merged[names[0]]['measured'], {'date': 'd2', 'commit': 'c2'})
    assert line == ("_Kept from an earlier run than the header's: measured on d1 (commit c1; "
                    'peers pybullet not installed (skipped), CPU Xeon)._')
