"""docs/friction.md shows exactly what docs/scripts/friction_levels.py prints."""

import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]


def test_friction_tables_are_current():
    out = subprocess.run(
        [sys.executable, str(ROOT / "docs/scripts/friction_levels.py")],
        capture_output=True,
        text=True,
        check=True,
    ).stdout
    doc = (ROOT / "docs/friction.md").read_text()
    assert out.strip() in doc
