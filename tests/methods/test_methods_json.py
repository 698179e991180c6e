"""methods.json, written by ``kinetostatics report``: every method that applies to the file,
at the report's positions, each closing on the kinetostatic solution or a closed form.

- the balancing moment by Joukowski's lever and by the power method equals the solution's
  to 1e-9 at each position (their own agreement is tested in test_lever.py; here: the
  report's positions, the student's choice ``--positions`` included);
- the instant centres give the pipeline's velocities to 1e-12;
- the gears' geometry of the geared five-bar: r_b = r cos α and r = m z / 2, by hand;
- the report's gear chapter shows the pair, and a file without gears has no such chapter.
"""

from __future__ import annotations

import json
import math

import pytest

from kinetostatics.cli import main
from tests.helpers import ROOT


def _report(out, name, *extra):
    path = ROOT / "mechanisms" / f"{name}.yaml"
    args = ["report", str(path), "--out", str(out), "--format", "md", "--dpi", "30"]
    assert main(args + list(extra)) == 0
    return json.loads((out / "methods.json").read_text(encoding="utf-8")), out


@pytest.fixture(scope="module")
def geared(tmp_path_factory):
    return _report(tmp_path_factory.mktemp("geared"), "geared_fivebar")


def test_the_methods_close_at_every_report_position(geared):
    data, _ = geared
    assert data["version"] == 1
    assert data["positions"] == [str(k) for k in range(1, 13)]
    bm = data["balancing_moment"]
    assert [p["label"] for p in bm["positions"]] == data["positions"]
    assert bm["max_relative_difference"] <= 1e-9
    centres = data["instant_centres"]
    assert sorted(centres, key=int) == data["positions"]
    for record in centres.values():
        assert record["found"] == record["total"] == 10  # 5 bodies: 5·4/2
        assert record["max_error"] <= 1e-12


def test_the_gears_are_the_textbook_s(geared):
    data, out = geared
    (pair,) = data["gears"]["pairs"].values()
    alpha = math.radians(pair["pressure_angle"])
    for wheel in pair["wheels"]:
        r = wheel["pitch_radius"]
        assert abs(r - pair["module"] * wheel["teeth"] / 2) <= 1e-12 * r
        assert abs(wheel["base_radius"] - r * math.cos(alpha)) <= 1e-12 * r
    text = (out / "report.md").read_text(encoding="utf-8")
    # after the balancing moment (9), the instant centres (10) and the vector equations (11)
    assert "## 12. Gears" in text and "r_b1 = r_1 cos α" in text
    assert text.index("## 10. Instant centres") < text.index("## 11. Vector equations")
    assert text.index("## 9. The balancing moment") < text.index("## 10. Instant centres")


def test_the_student_s_positions_and_no_gear_chapter_without_gears(tmp_path, capsys):
    data, out = _report(tmp_path, "slotting_machine", "--positions", "7,2")
    assert data["positions"] == ["2", "7"]
    assert "gears" not in data and "cam_design" not in data
    assert [p["label"] for p in data["balancing_moment"]["positions"]] == ["2", "7"]
    assert data["balancing_moment"]["max_relative_difference"] <= 1e-9
    assert "Gears" not in (out / "report.md").read_text(encoding="utf-8")
    assert str(out / "methods.json") in capsys.readouterr().out
