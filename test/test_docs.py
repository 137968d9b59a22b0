"""README's parameter table names every declared parameter with its real default."""

import math
from pathlib import Path
import re

from mouse_constraint_ros.node.parameters import PARAMETERS

README = Path(__file__).resolve().parent.parent / 'README.md'


def yaml_literal(value) -> str:
    """Return a default as config/params.yaml and README write it."""
    if isinstance(value, bool):
        return str(value).lower()
    if isinstance(value, float) and math.isinf(value):
        return '.inf'
    return str(value)


def test_readme_parameter_table_matches_the_declarations():
    """One row per parameter, and the default in the row is the declared one."""
    section = README.read_text().split('### Parameters', 1)[1].split('\n## ', 1)[0]
    rows = dict(re.findall(r'^\| `(\w+)` \| `([^`]*)` \|', section, re.MULTILINE))
    assert set(rows) == {p.name for p in PARAMETERS}
    for parameter in PARAMETERS:
        assert rows[parameter.name] == yaml_literal(parameter.default), parameter.name
