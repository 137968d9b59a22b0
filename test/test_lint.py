"""The code follows ament's flake8 conventions: 99 columns, single quotes, pep257."""

from pathlib import Path
import subprocess
import sys

ROOT = Path(__file__).resolve().parent.parent


def test_flake8():
    """Flake8 with the repository's ament-mirroring configuration reports nothing."""
    names = ('mouse_constraint_ros', 'test', 'test_support', 'bench', 'launch', 'setup.py')
    paths = [str(ROOT / name) for name in names if (ROOT / name).exists()]
    result = subprocess.run([sys.executable, '-m', 'flake8', '--config', str(ROOT / '.flake8'),
                             *paths], capture_output=True, text=True, cwd=ROOT)
    assert result.returncode == 0, result.stdout + result.stderr
