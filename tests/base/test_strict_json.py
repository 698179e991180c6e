"""Every JSON file the package writes is strict JSON (issue 36, item 14): a value that is
not a finite number is written as null and listed under ``non_finite`` (its path and what
it was), never as ``Infinity`` or ``NaN``, which strict JSON readers refuse."""

from __future__ import annotations

import json
import math

import numpy as np

from kinetostatics.base.files import NON_FINITE, json_text
from kinetostatics.cli import main

# the parallelogram four-bar (crank = rocker, coupler = frame): at crank 0° and 180° all
# four links are collinear, a singular position of the dyad; 361 positions over a turn
# from 90° land on both
PARALLELOGRAM = """\
name: parallelogram four-bar
units: {length: mm, angle: deg, speed: rpm}
links:
  ground: {points: {O: [0, 0], D: [300, 0]}}
  crank: {points: {O: [0, 0], A: [100, 0]}, com: [50, 0], mass: 1, inertia: 0.001}
  coupler: {points: {A: [0, 0], B: [300, 0]}, com: [150, 0], mass: 2, inertia: 0.02}
  rocker: {points: {D: [0, 0], B: [100, 0]}, com: [50, 0], mass: 1, inertia: 0.001}
joints:
  O: {type: revolute, links: [ground, crank]}
  A: {type: revolute, links: [crank, coupler]}
  B: {type: revolute, links: [coupler, rocker]}
  D: {type: revolute, links: [ground, rocker]}
drivers:
  motor: {joint: O, motion: {speed: 60}}
sketch: {A: [0, 100], B: [300, 100]}
analysis: {start: 90, sweep: 360, positions: 361}
"""


def _strict(text: str):
    """``json.loads`` that refuses ``Infinity``, ``-Infinity`` and ``NaN``."""

    def refuse(name):
        raise ValueError(f"not strict JSON: {name}")

    return json.loads(text, parse_constant=refuse)


def _at(data, path: str):
    """The value at a path written as ``a.b[2].c``."""
    for part in path.replace("[", ".[").split("."):
        data = data[int(part[1:-1])] if part.startswith("[") else data[part]
    return data


def test_json_text_maps_non_finite_to_null_and_flags_it():
    data = {"a": [1.0, np.float64("inf")], "b": {"c": float("nan"), "d": -math.inf}, "e": 2}
    got = _strict(json_text(data))
    assert got == {
        "a": [1.0, None],
        "b": {"c": None, "d": None},
        "e": 2,
        NON_FINITE: {"a[1]": "Infinity", "b.c": "NaN", "b.d": "-Infinity"},
    }
    assert NON_FINITE not in _strict(json_text({"a": [1.0, np.float32(2.5)]}))


def test_parallelogram_summary_is_strict_json(tmp_path):
    """The run's summary.json parses with a reader that refuses Infinity/NaN (the singular
    positions' condition numbers held ``Infinity``); each flagged value is null, and is
    the condition number of a singular position at crank 0° or 180° (mod 360°)."""
    path = tmp_path / "parallelogram.yaml"
    path.write_text(PARALLELOGRAM)
    assert main(["run", str(path), "--out", str(tmp_path / "out")]) == 0
    summary = _strict((tmp_path / "out" / "summary.json").read_text())
    for where, what in summary.get(NON_FINITE, {}).items():
        assert what in ("Infinity", "-Infinity", "NaN")
        assert _at(summary, where) is None
        assert where.endswith(".condition")
        entry = _at(summary, where.removesuffix(".condition"))
        assert min(abs(entry["angle"] % 180.0), 180.0 - entry["angle"] % 180.0) < 1e-6


def test_result_to_json_writes_strict_json(tmp_path):
    """Result.to_json, the writer of run's and batch's summary.json, with a summary holding
    every kind of non-finite value (the parallelogram's may round to a finite one)."""
    import kinetostatics as ks

    result = ks.analyze(ks.loads(PARALLELOGRAM.replace("positions: 361", "positions: 3")))
    out = tmp_path / "summary.json"
    result.to_json(out, summary={"x": [math.inf, -math.inf, math.nan, 1.5]})
    assert _strict(out.read_text()) == {
        "x": [None, None, None, 1.5],
        NON_FINITE: {"x[0]": "Infinity", "x[1]": "-Infinity", "x[2]": "NaN"},
    }
