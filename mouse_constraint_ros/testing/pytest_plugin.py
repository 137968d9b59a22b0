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
pytest fixtures for testing a node against the body: ``simulated_body`` and its factory.

Registered as a pytest plugin by the package's ``pytest11`` entry point, so that a package that
depends on this one gets the fixtures by installing it. Importing this module imports pytest
only: rclpy and the message packages load when a fixture is first used.

``simulated_body`` is one ``SimulatedBody`` per test, closed after it; its parameters come
from ``@pytest.mark.parametrize('simulated_body', [{'mass': 5.0}], indirect=True)``.
``simulated_body_factory`` makes as many as a test asks for, each with its keywords, and closes
them all after it.
"""

import pytest


@pytest.fixture
def simulated_body(request):
    """Yield a ``SimulatedBody`` with the parameters of an indirect parametrization, if any."""
    from mouse_constraint_ros.testing import SimulatedBody
    keywords = dict(getattr(request, 'param', None) or {})
    with SimulatedBody(**keywords) as body:
        yield body


@pytest.fixture
def simulated_body_factory():
    """Yield ``make(**keywords)``, which returns a new ``SimulatedBody``; all closed after."""
    from mouse_constraint_ros.testing import SimulatedBody
    bodies = []

    def make(**keywords):
        body = SimulatedBody(**keywords)
        bodies.append(body)
        return body

    yield make
    for body in reversed(bodies):
        body.close()
