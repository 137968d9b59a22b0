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


"""``TargetPath``: a stream's point at a tick's time, by bisection, as a sorted search gives it."""

import bisect

from hypothesis import given, settings, strategies as st

from mouse_constraint_ros.recording.target_path import STREAM_GAP_NS, TargetPath

MS = 1_000_000


class SortedSearch:
    """The plain reading of the rule: sort the stream around the held target, then search."""

    def __init__(self) -> None:
        """Start with no target."""
        self.targets, self.breaks = [], []

    def at(self, time_ns: int, held: int):
        """Return the point at ``time_ns`` between the two targets around it, or the last."""
        after = bisect.bisect_right(self.breaks, held)
        low = self.breaks[after - 1] if after else -1
        high = self.breaks[after] if after < len(self.breaks) else None
        stream = sorted((t for t in self.targets if low < t[0] and (high is None or t[0] < high)),
                        key=lambda t: (t[1], t[0]))
        k = bisect.bisect_left([t[1] for t in stream], time_ns)
        if k == len(stream) and stream:
            return stream[-1][2]
        if k == 0 or k == len(stream) or stream[k][1] - stream[k - 1][1] > STREAM_GAP_NS:
            return None
        (_, t0, p0), (_, t1, p1) = stream[k - 1], stream[k]
        share = (time_ns - t0) / (t1 - t0)
        return tuple(a + share * (b - a) for a, b in zip(p0, p1))


# Each message: a target at a time (ms, going back at times) or a break; then a row at a time.
MESSAGES = st.lists(st.tuples(st.one_of(st.none(), st.integers(0, 400)),
                              st.integers(0, 400)), min_size=1, max_size=60)


@settings(max_examples=300, deadline=None, derandomize=True)
@given(MESSAGES)
def test_bisection_and_the_sorted_search_agree(messages):
    """Targets in and out of time order, breaks between: every row's point is the same."""
    path, reference = TargetPath(), SortedSearch()
    for index, (time_ms, row_ms) in enumerate(messages):
        if time_ms is None:
            path.add_break(index)
            reference.breaks.append(index)
        else:
            point = (float(index), 0.5 * index, -1.0)
            path.add(index, time_ms * MS, point)
            reference.targets.append((index, time_ms * MS, point))
        for held in range(index + 1):
            assert path.at(row_ms * MS + 1, held) == reference.at(row_ms * MS + 1, held)
            assert path.at(row_ms * MS, held) == reference.at(row_ms * MS, held)


def test_forgetting_keeps_what_later_rows_need():
    """Targets two stream gaps before a row's time go; the rows from then on read the same."""
    path, reference = TargetPath(), SortedSearch()
    for index in range(2000):
        time_ns = index * MS + (0 if index % 7 else -3 * MS)  # every seventh stamped earlier
        path.add(index, time_ns, (float(index), 0.0, 0.0))
        reference.targets.append((index, time_ns, (float(index), 0.0, 0.0)))
        row = index * MS - 20 * MS
        if row > 0:
            path.forget_before(row)
            assert path.at(row, index) == reference.at(row, index)
    # Kept: two stream gaps before the latest row (which lags the targets by 20 ms), and one.
    assert len(path._targets) <= 2 * STREAM_GAP_NS // MS + 20 + 2
