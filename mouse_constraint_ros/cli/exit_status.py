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
What a command line tool exits with when a stop ends it before it finished.

``mouse_ctl``'s console script (``console``, before the command is imported) and its command
(``ctl``, a call stopped before its answer), ``mouse_record`` stopped before the first pose
(nothing recorded) and the check for a running node all end so. Standard library only, nothing
imported: a console script must load in no time.
"""

# The exit status of a tool stopped before it finished: 128 + SIGINT.
INTERRUPTED_STATUS = 130
