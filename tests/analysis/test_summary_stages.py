"""The summary formats; the cycle's stages solve, and only when a caller asks for them.

``result.summary()`` holds what the rows hold; the cycle's quantities (means, strokes,
locked zones' edges, flywheel, drive) come from :func:`cycle_stage`'s records, passed in.
"""

from __future__ import annotations

import dataclasses
import json
import re
from pathlib import Path

import numpy as np
import pytest

import kinetostatics as ks
from kinetostatics.dynamics.stages import Cycle, cycle_stage

ROOT = Path(__file__).resolve().parents[2]

# every function that solves again between the rows, by its home and by the names the
# stages module bound (a plain summary must reach none of them)
SOLVERS = {
    "kinetostatics.analysis.cycle": ["cycle_pieces", "cycle_nodes", "cycle_stats"],
    "kinetostatics.analysis.cuts": ["quiet_analyze", "quiet_near", "breaks"],
    "kinetostatics.analysis.pipeline": ["analyze", "analyze_near"],
    "kinetostatics.analysis.locking": ["locking_zones", "kinetics", "state_at"],
    "kinetostatics.kinematics.events": ["output_strokes", "state_near"],
    "kinetostatics.kinetics.inverse": ["kinetics"],
    "kinetostatics.dynamics.flywheel": ["design", "energy_curve"],
    "kinetostatics.dynamics.drive": ["size"],
    "kinetostatics.dynamics.stages": [
        "cycle_stats",
        "locking_zones",
        "output_strokes",
        "design",
        "size",
    ],
}


@pytest.fixture(scope="module")
def locked():
    """The 12-position slider-crank with 30 times its friction, self-locked at every row:
    its cycle means with friction are a homotopy at every quadrature node (the slowest
    summary there was, 24 times its analysis)."""
    text = (ROOT / "tests" / "hard" / "slider_crank_self_locking.yaml").read_text()
    text = re.sub(r"\n  s: 3 ", "\n  s: 90 ", text)
    text = re.sub(r"positions: 360", "positions: 12", text)
    return ks.analyze(ks.loads(text, file="locked.yaml"))


@pytest.fixture(scope="module")
def slotting():
    return ks.analyze(ks.load(ROOT / "mechanisms" / "slotting_machine.yaml"))


def _forbid_solvers(monkeypatch):
    import importlib

    def refuse(*args, **kwargs):
        raise AssertionError("a plain summary solved")

    for module, names in SOLVERS.items():
        mod = importlib.import_module(module)
        for name in names:
            monkeypatch.setattr(mod, name, refuse)


def test_a_plain_summary_solves_nothing(locked, monkeypatch, tmp_path):
    _forbid_solvers(monkeypatch)
    s = locked.summary()
    locked.to_json(tmp_path / "summary.json")
    assert json.loads((tmp_path / "summary.json").read_text())["name"] == s["name"]
    for key in ("outputs", "self_locking", "flywheel", "drive"):
        assert key not in s
    d = s["drivers"]["motor"]
    assert "mean" not in d and "rms" not in d
    # the peaks are the rows' own: the largest |force| of the rows, NaN without friction
    assert d["peak"] == pytest.approx(np.max(np.abs(locked["motor.force"])), rel=1e-15)
    assert np.isnan(d["peak_friction"])
    assert s["positions"] == 12 and s["checks"]["failed"] == ["friction"]


def test_the_stages_are_reached_when_asked(slotting, monkeypatch):
    """The guard above can fail: the same patching makes the stage refuse."""
    _forbid_solvers(monkeypatch)
    with pytest.raises(AssertionError, match="a plain summary solved"):
        cycle_stage(slotting)


def test_each_record_adds_its_keys_and_the_rows_agree(slotting):
    """A stage asked for adds its key and no other; the peaks of the plain summary are the
    full summary's (the rows' largest |value|), and the parts the rows give are equal."""
    plain = slotting.summary()
    cycle = cycle_stage(slotting, outputs=False, self_locking=False, flywheel=False, drive=False)
    assert cycle.outputs is None and cycle.flywheel is None and cycle.drive is None
    means = slotting.summary(cycle)
    assert set(means) == set(plain)
    full = slotting.summary(cycle_stage(slotting))
    assert set(full) - set(plain) == {"outputs", "self_locking", "flywheel"}
    for key in ("extremes", "reaction_peaks", "events", "singular_positions", "checks"):
        assert full[key] == plain[key], key
    for suffix in ("", "_friction_approx", "_friction"):
        assert (
            full["drivers"]["motor"]["peak" + suffix] == plain["drivers"]["motor"]["peak" + suffix]
        )
    # the mean is the cutting work over a turn, 1000 N over 0.9 of the 100 mm stroke / 2π
    # (docs/validation.md), clockwise; the record's mean is the summary's
    exact = -1000.0 * 0.9 * 0.100 / (2 * np.pi)
    assert means["drivers"]["motor"]["mean"] == pytest.approx(exact, rel=1e-9)
    assert cycle.drivers["motor.torque"]["mean"] == means["drivers"]["motor"]["mean"]


def test_the_records_are_frozen(slotting):
    cycle = cycle_stage(slotting, outputs=True, self_locking=False, flywheel=False, drive=False)
    with pytest.raises(dataclasses.FrozenInstanceError):
        cycle.drivers = None  # type: ignore[misc]
    with pytest.raises(TypeError):
        cycle.drivers["motor.torque"]["mean"] = 0.0  # type: ignore[index]
    with pytest.raises(TypeError):
        cycle.outputs["guide"] = {}  # type: ignore[index]
    assert isinstance(cycle, Cycle)


def test_a_flywheel_design_carries_its_curve_only_when_asked(slotting, monkeypatch):
    """``with_curve`` computes the energy curve once and the record carries it; the pictures
    then solve nothing (the curve is not cached on the frozen design behind its back)."""
    from kinetostatics.dynamics import flywheel

    design = flywheel.design(slotting)
    assert design.energy is None
    carried = design.with_curve()
    assert carried.energy is not None and design.energy is None
    monkeypatch.setattr(flywheel, "energy_curve", lambda *a, **k: 1 / 0)
    np.testing.assert_array_equal(carried.curve["moment"], carried.energy["moment"])
    with pytest.raises(ZeroDivisionError):
        design.curve  # noqa: B018  (computed at each call, nothing kept)


def test_the_torque_curves_show_the_mean_of_the_record_they_are_given(slotting):
    """A picture solves nothing: the cycle mean in its legend is the record's, and without
    a record there is none."""
    pytest.importorskip("matplotlib")
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from kinetostatics.outputs import plotting as pl

    cycle = cycle_stage(slotting, outputs=False, self_locking=False, flywheel=False, drive=False)
    exact = -1000.0 * 0.9 * 0.100 / (2 * np.pi)  # the cutting work over a turn / 2π
    with_mean = pl.torque_curves(slotting, dpi=40, cycle=cycle)
    labels = [t.get_text() for t in with_mean.axes[0].get_legend().get_texts()]
    assert any(f"cycle mean {exact:.4g} N·m" in lab for lab in labels), labels
    plain = pl.torque_curves(slotting, dpi=40)
    labels = [t.get_text() for t in plain.axes[0].get_legend().get_texts()]
    assert labels and not any("cycle mean" in lab for lab in labels), labels
    plt.close(with_mean)
    plt.close(plain)
