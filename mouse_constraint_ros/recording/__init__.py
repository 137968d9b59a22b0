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
The parts of ``mouse_record``, one idea a module, below the thin command ``cli/record.py``.

- ``received``: the recorded topics and one message as received (serialized CDR);
- ``capture``: the recording node, the anchor read from the recorded node, the progress line;
- ``node_view``: the recorded node's target and anchor as the messages make them;
- ``target_path``: where a stream of targets is at a tick's time;
- ``applied_wrench``: the wrench the node applied at a tick, and the pushes of a recording;
- ``rows``: messages to CSV rows (one per tick), made as the messages come; ``joints`` a
  robot's ``joint_states`` on them and their CSV columns;
- ``recording_files``: the files written while recording; ``csv_file`` and ``mcap_file`` the
  CSV and the MCAP file (and the ``ros2msg`` schemas it carries);
- ``figure``: the PNG figure (matplotlib, no display); ``body_outline`` a URDF body's hull on it;
- ``missing_ticks``: which ticks of the node's grid a recording lacks;
- ``outputs``: the files a recording writes, checked for writing before it starts.
"""
