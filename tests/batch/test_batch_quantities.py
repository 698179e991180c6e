"""The quantities of a batch row (and of an optimisation's objectives and constraints):
one table of definitions (``variants.QUANTITIES``), listed in docs/batch.md, each equal
to the same quantity computed from the single run's columns.  The relation over every
shipped motion-driven file and generated mechanisms is tests/net (``batch_row``); here:
the cam's pressure angle, whose column is signed (issue 36, item 1)."""

from __future__ import annotations

import csv
import math
import re
from pathlib import Path

import numpy as np
import pytest

import kinetostatics as ks
from kinetostatics import batch
from kinetostatics.batch.sources import Task
from kinetostatics.batch.variants import QUANTITIES

ROOT = Path(__file__).resolve().parents[2]
CAM = ROOT / "mechanisms" / "cam_roller.yaml"


def _cam_text(positions: int = 72) -> str:
    """mechanisms/cam_roller.yaml with its preload as a parameter P (N)."""
    text = CAM.read_text()
    text, n1 = re.subn(r"^parameters:\n", "parameters:\n  P: 30\n", text, flags=re.M)
    text, n2 = re.subn(r"value: \[0, -30\]", "value: [0, -P]", text)
    text, n3 = re.subn(r"positions: 360", f"positions: {positions}", text)
    assert n1 == n2 == n3 == 1
    return text


def _rows(folder: Path) -> dict[str, dict[str, str]]:
    with open(folder / "summary.csv", encoding="utf-8") as fh:
        return {r["variant"]: r for r in csv.DictReader(x for x in fh if not x.startswith("#"))}


def _roller_pressure_angle(theta: np.ndarray) -> np.ndarray:
    """The closed form of mechanisms/cam_roller.yaml's pressure angle (deg, signed) at cam
    angles ``theta`` (rad): tan α = (s' − e)/(s0 + s), prime circle 52 mm, offset e = 10 mm,
    s0 = √(52² − 10²); rise h = 20 mm over β = 120° cycloidal, dwell 60°, return over 120°
    by the 3-4-5 polynomial, dwell 60°."""
    h, beta, e = 20.0, math.radians(120), 10.0
    s0 = math.sqrt(52.0**2 - e**2)
    theta = np.mod(theta, 2 * math.pi)
    s, ds = np.zeros_like(theta), np.zeros_like(theta)
    rise = theta < beta
    u = theta[rise] / beta
    s[rise] = h * (u - np.sin(2 * math.pi * u) / (2 * math.pi))
    ds[rise] = h / beta * (1 - np.cos(2 * math.pi * u))
    dwell = (theta >= beta) & (theta < math.radians(180))
    s[dwell] = h
    back = (theta >= math.radians(180)) & (theta < math.radians(300))
    u = (theta[back] - math.radians(180)) / beta
    s[back] = h * (1 - (10 * u**3 - 15 * u**4 + 6 * u**5))
    ds[back] = -h / beta * (30 * u**2 - 60 * u**3 + 30 * u**4)
    return np.degrees(np.arctan((ds - e) / (s0 + s)))


def test_the_closed_form_worst_pressure_angle_of_the_roller_cam_is_25_degrees():
    alpha = _roller_pressure_angle(np.linspace(0, 2 * math.pi, 720_001))
    assert np.max(np.abs(alpha)) == pytest.approx(24.98, abs=0.005)
    assert np.max(alpha) < 9  # the signed maximum is the rise's, far below


@pytest.mark.parametrize("chunk", [1, 2])
def test_a_cams_pressure_angle_max_is_its_largest_magnitude(tmp_path, chunk):
    """The row's ``contact.pressure_angle_max`` is max |α| over the rows: the return
    stroke's 24.9°, not the signed maximum 8.5° of the rise."""
    path = tmp_path / "cam.yaml"
    path.write_text(_cam_text())
    tasks = [Task(str(k), 0, {"P": p}) for k, p in enumerate((20.0, 40.0))]
    batch.run_batch(str(path), tasks, tmp_path / "b", executor="serial", chunk=chunk)
    rows = _rows(tmp_path / "b")
    # the cam angles of the rows, from a single run; the angle at each from the law
    theta = np.radians(ks.analyze(ks.load(path))["contact.cam_angle"])
    expected = np.max(np.abs(_roller_pressure_angle(theta)))
    assert expected > 24.9
    for row in rows.values():
        assert row["status"] == "ok"
        assert abs(float(row["contact.pressure_angle_max"]) - expected) <= 1e-12 * 90


def test_optimize_calls_a_25_degree_cam_infeasible_under_10_degrees(tmp_path):
    path = tmp_path / "cam.yaml"
    path.write_text(_cam_text(positions=12))
    best = ks.optimize(
        path,
        {"P": (20.0, 40.0)},
        "-P",
        ["contact.pressure_angle_max <= 10"],
        popsize=2,
        maxiter=1,
        polish=False,
        progress=False,
    )
    assert not best.feasible
    assert best.row["contact.pressure_angle_max"] > 20  # 24.9° at 240°


def _docs_table() -> dict[str, tuple[str, str]]:
    """docs/batch.md's table of the quantities: name -> (unit, sense)."""
    text = (ROOT / "docs" / "batch.md").read_text(encoding="utf-8")
    lines = text.split("### The quantities of a row", 1)[1].splitlines()
    start = next(k for k, line in enumerate(lines) if line.startswith("| quantity |"))
    out = {}
    for line in lines[start + 2 :]:
        if not line.startswith("|"):
            break
        cells = [c.strip() for c in line.strip("|").split("|")]
        out[cells[0].strip("`")] = (cells[1], cells[2])
    return out


def test_docs_list_every_quantity_with_its_unit_and_sense():
    assert _docs_table() == {k: (q.unit, q.sense) for k, q in QUANTITIES.items()}


def test_a_sweep_of_a_cams_geometry_in_one_chunk_is_analysed(tmp_path):
    """The cam's profile is synthesised once from its dimensions: variants of another base
    circle cannot share a stacked model, and used to be rows of status 'error' (a
    TypeError) in a chunk of two or more; they are analysed one by one, as alone."""
    path = tmp_path / "cam.yaml"
    path.write_text(_cam_text(positions=24))
    tasks = [Task(str(k), 0, {"rb": rb}) for k, rb in enumerate((36.0, 44.0))]
    for chunk in (2, 1):
        batch.run_batch(str(path), tasks, tmp_path / f"c{chunk}", executor="serial", chunk=chunk)
    rows = [_rows(tmp_path / f"c{chunk}") for chunk in (2, 1)]
    for vid in ("0", "1"):
        assert rows[0][vid]["status"] == "ok", rows[0][vid]["reason"]
        assert rows[0][vid] == rows[1][vid]
