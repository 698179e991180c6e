"""summary.json's extremes: each column's largest and smallest value and where, with
round-off counted as zero (the rule of the report's tables)."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

import kinetostatics as ks
from kinetostatics.outputs.summary import ROUND_OFF, summarize

ROOT = Path(__file__).resolve().parents[2]


@pytest.fixture(scope="module")
def slotting():
    result = ks.analyze(ks.load(ROOT / "mechanisms" / "slotting_machine.yaml"))
    return result, summarize(result)["extremes"]


def test_a_fixed_pivot_has_extremes_zero_at_the_first_row(slotting):
    """The guide bar turns about O3 at the origin: the point does not move, so its x, y,
    velocity and acceleration are 0 (the analysis gives ±1e-17 m and the like: round-off),
    and the summary names no position of a "largest" one."""
    result, extremes = slotting
    for c in ("x", "y", "vx", "vy", "ax", "ay"):
        e = extremes[f"bar.O3.{c}"]
        assert e["max"] == e["min"] == 0.0, c
        assert e["at_max"] == e["at_min"] == float(result["angle"][0])
        assert np.max(np.abs(result[f"bar.O3.{c}"])) < 1e-9  # what was round-off


def test_every_extreme_is_its_columns_or_round_off(slotting):
    """Each reported max/min is the column's own (its row given by at_max/at_min), or 0
    where the column's value there is within ROUND_OFF of its unit's largest."""
    result, extremes = slotting
    scale: dict[str, float] = {}
    for name in result.columns:
        v = np.asarray(result[name], float)
        if np.isfinite(v).any():
            u = result.units[name]
            scale[u] = max(scale.get(u, 0.0), float(np.nanmax(np.abs(v))))
    assert set(extremes) == {n for n in result.columns if np.isfinite(result[n]).any()}
    for name, e in extremes.items():
        v = np.asarray(result[name], float)
        floor = ROUND_OFF * scale[result.units[name]]
        for key, f in (("max", np.nanmax), ("min", np.nanmin)):
            true = float(f(v))
            if abs(true) > floor:
                assert e[key] == true, (name, key)
                k = int(np.flatnonzero(v == true)[0])
                assert e[f"at_{key}"] == float(result["angle"][k]), (name, key)
            else:  # round-off: the extreme of the column with it counted as 0
                assert e[key] == 0.0, (name, key)
