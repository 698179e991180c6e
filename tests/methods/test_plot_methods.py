"""``plot`` writes methods.json for the pictures it draws (issue 38): the instant centres
of ``--what centres`` (drawn with the mechanism, ``centres.png``) and the vector equations
behind the velocity and acceleration polygons, at the drawn position — the same stage and
record as ``report``'s, so the entries equal the report's at the same course position."""

from __future__ import annotations

import json

import numpy as np

import kinetostatics as ks
from kinetostatics.cli import main
from kinetostatics.methods.stage import methods_stage
from kinetostatics.outputs import plotting as pl
from tests.helpers import ROOT

SLOTTING = ROOT / "mechanisms" / "slotting_machine.yaml"


def _plot(tmp_path, *args) -> dict | None:
    assert main(["plot", str(SLOTTING), "--out", str(tmp_path), "--dpi", "30", *args]) == 0
    path = tmp_path / "methods.json"
    return json.loads(path.read_text(encoding="utf-8")) if path.exists() else None


def test_plot_writes_the_methods_of_its_pictures(tmp_path):
    data = _plot(tmp_path, "--what", "centres", "velocity", "--position", "30")
    assert (tmp_path / "centres.png").stat().st_size > 0
    assert set(data) == {"version", "positions", "instant_centres", "vector_equations"}
    (label,) = data["positions"]
    centres, equations = data["instant_centres"][label], data["vector_equations"][label]
    # φ = 30° is a course position of the report (its label, not the coordinate)
    report = pl.analyze_for_pictures(ks.load(SLOTTING), course=True, events=True)
    rows = dict(pl.course_positions(report))
    assert label in rows
    assert np.isclose(np.degrees(report.coordinate[rows[label]]) % 360.0, 30.0, atol=1e-9)
    # every centre found, and their velocities are the pipeline's
    assert centres["found"] == centres["total"] == 15
    assert centres["max_error"] <= 1e-12
    assert equations["max_residual"] <= 1e-12
    # the same record as the report's at that course position (its own analysis)
    full = methods_stage(report, [(label, rows[label])], parts=["instant_centres"])
    theirs = {tuple(c["bodies"]): c for c in full["instant_centres"][label]["centres"]}
    for c in centres["centres"]:
        other = theirs[tuple(c["bodies"])]
        assert c["how"] == other["how"] and c["at_infinity"] == other["at_infinity"]
        assert np.allclose(c["xy"], other["xy"], rtol=0, atol=1e-9)  # m (or a unit vector)


def test_plot_between_rows_and_without_methods(tmp_path):
    data = _plot(tmp_path / "a", "--what", "acceleration", "--position", "47.5")
    assert set(data) == {"version", "positions", "vector_equations"}
    assert data["positions"] == ["47.5"]  # not a course position: the coordinate as given
    entry = data["vector_equations"]["47.5"]
    kinds = {e["kind"] for g in entry["groups"] for e in g["equations"]}
    assert kinds == {"velocity", "acceleration"} and entry["max_residual"] <= 1e-12
    # a picture without a method writes no methods.json
    assert _plot(tmp_path / "b", "--what", "motion") is None
