"""docs/sizing.md shows exactly what docs/scripts/sizing_example.py prints, and `run` of
the shipped sized file writes sizing.json (and of a file without sizing data, none)."""

from __future__ import annotations

import json
import subprocess
import sys

from kinetostatics.cli import main
from tests.helpers import ROOT


def test_the_worked_example_is_current():
    out = subprocess.run(
        [sys.executable, str(ROOT / "docs" / "scripts" / "sizing_example.py")],
        capture_output=True, text=True, check=True,
    ).stdout  # fmt: skip
    doc = (ROOT / "docs" / "sizing.md").read_text(encoding="utf-8")
    assert out.strip() in doc, "run `python docs/scripts/sizing_example.py --write`"
    assert "slider_crank_sized.yaml" in doc


def test_run_writes_sizing_json(tmp_path, capsys):
    assert main(["run", str(ROOT / "mechanisms" / "slider_crank_sized.yaml"), "--out",
                 str(tmp_path / "a")]) == 0  # fmt: skip
    line = next(x for x in capsys.readouterr().out.splitlines() if x.startswith("sizing:"))
    assert "least safety factor" in line and "L10" in line
    data = json.loads((tmp_path / "a" / "sizing.json").read_text(encoding="utf-8"))
    assert set(data["bearings"]) == {"O", "A", "B"} and set(data["links"]) == {"crank", "rod"}
    rod = data["links"]["rod"]
    assert len(rod["critical"]["M"]) == len(data["angles"]) == 360
    assert main(["run", str(ROOT / "mechanisms" / "slider_crank.yaml"), "--out",
                 str(tmp_path / "b")]) == 0  # fmt: skip
    assert not (tmp_path / "b" / "sizing.json").exists()
