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
One substep's constraint rows of a robot, arrays and lists: the record the row solvers read.

``robot_rows`` picks them from its table; ``robot_block`` and ``robot_sweeps`` solve them.
"""

import math
from typing import List, NamedTuple

import numpy as np


class Rows(NamedTuple):
    """
    One substep's rows, picked from the ``RowTable``.

    The mouse's come first (when it holds), then the stops', then the others'. What the solvers
    read one row at a time (bounds, table numbers, guesses) is in Python numbers: a substep has
    a handful of rows, and indexing a NumPy array for each costs more than a list.

    :param jacobian: A (m x nv).
    :param target: each row's target velocity A v (the mouse's: -(b / a) C).
    :param lower: each row's least accumulated impulse (-inf for none).
    :param upper: each row's largest.
    :param picked: each row's number in the table: what names it from one substep to the next
        (the table's ``kind`` and ``joint`` say what it is and on which joint it acts).
    :param first_guess: the hold each row is tried at when the last substep did not have it.
    :param mouse_rows: ``MOUSE_ROWS`` when the mouse's rows lead, else 0.
    :param mass_scale: the mouse's a (its block of the system is K / a).
    :param bound: the mouse impulse's largest norm h F_max (N s); inf without the mouse.
    """

    jacobian: np.ndarray
    target: np.ndarray
    lower: List[float]
    upper: List[float]
    picked: List[int]
    first_guess: List[int]
    mouse_rows: int = 0
    mass_scale: float = 1.0
    bound: float = math.inf

    @property
    def count(self) -> int:
        """Return the number of rows."""
        return self.target.shape[0]
