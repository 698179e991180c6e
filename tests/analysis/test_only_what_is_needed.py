"""An analysis computes only what its requested outputs need."""

import numpy as np

import kinetostatics as ks
from kinetostatics.analysis import pipeline as analysis
from kinetostatics.kinetics import inverse


def test_kinematics_only_assembles_no_loads(monkeypatch):
    def forbidden(*args, **kwargs):
        raise AssertionError("kinetics was called")

    monkeypatch.setattr(analysis, "kinetics", forbidden)
    monkeypatch.setattr(analysis, "inverse_dynamics", forbidden)
    monkeypatch.setattr(analysis, "load_events", forbidden)
    r = ks.analyze(ks.load("mechanisms/slotting_machine.yaml"), kinematics_only=True)
    assert "ram.vy" in r.columns and "rod_ram.pressure_angle" in r.columns
    assert not [c for c in r.columns if c.startswith(("power.", "motor.", "shaking."))]


def test_kinematics_only_equals_the_full_analysis_kinematics():
    model = ks.load("mechanisms/slotting_machine.yaml")
    a, b = ks.analyze(model, kinematics_only=True), ks.analyze(model)
    for name in a.columns:
        np.testing.assert_array_equal(a[name], b[name])


def test_a_file_without_friction_runs_no_friction_solve(monkeypatch):
    def forbidden(*args, **kwargs):
        raise AssertionError("a friction solve ran")

    monkeypatch.setattr(inverse.fr, "consistent", forbidden)
    monkeypatch.setattr(inverse.fr, "approximate", forbidden)
    r = ks.analyze(ks.load("tests/hard/fourbar_change_point.yaml"), positions=np.radians([100.0]))
    assert "friction.status" not in r.columns


def test_one_reaction_builds_only_its_own_columns():
    r = ks.analyze(ks.load("mechanisms/slotting_machine.yaml"))
    assert r.columns.computed == 0
    fx = r["O3.Fx"]
    assert r.columns.computed == 2  # O3.Fx and O3.Fy, nothing else
    np.testing.assert_array_equal(fx, r["O3.Fx"])
    assert len(r.columns) > 100
    assert "guide.N" in r.columns and "guide.N_friction" in r.columns and "x.Fx" not in r.columns
    assert r.columns.computed == 2  # asking whether a column is there computes nothing


def test_a_joints_reaction_is_solved_once_for_all_its_columns(monkeypatch):
    from kinetostatics.joints.prismatic import Prismatic

    calls = []
    real = Prismatic.reaction
    monkeypatch.setattr(Prismatic, "reaction", lambda *a: calls.append(1) or real(*a))
    r = ks.analyze(ks.load("mechanisms/slotting_machine.yaml"))
    labels = [c for c in r.columns if c.startswith("guide.") and c[6:] in ("N", "M", "Fx", "Fy")]
    assert len(labels) > 1
    for c in labels:
        r[c]
    assert len(calls) == 1


def test_a_run_imports_only_what_its_file_uses():
    """The slotting machine (revolutes and slides, constant speed, no clearance) imports
    no gear or cam module, no motion-law or contact-law module, and no difflib (the
    "did you mean" of an error): each costs the start of every run."""
    import os
    import subprocess
    import sys
    from pathlib import Path

    lazy = [
        "difflib",
        "kinetostatics.joints.cam",
        "kinetostatics.joints.gear",
        "kinetostatics.joints.rack",
        "kinetostatics.model.motion",
        "kinetostatics.model.contact_law",
    ]
    code = (
        "import sys, kinetostatics as ks;"
        "r = ks.analyze(ks.load('mechanisms/slotting_machine.yaml')); r.summary();"
        f"print([m for m in {lazy!r} if m in sys.modules])"
    )
    root = Path(__file__).resolve().parents[2]
    env = {k: v for k, v in os.environ.items() if k != "KINETOSTATICS_BACKEND"}  # the
    out = subprocess.run(  # default backend's run (numba imports difflib itself)
        [sys.executable, "-c", code], capture_output=True, text=True, check=True, cwd=root, env=env
    )
    assert out.stdout.strip() == "[]"


def test_a_small_analysis_reads_no_memory_figures_and_a_large_one_does(monkeypatch):
    """Rows needing less than pipeline.ALWAYS_FITS (8 MiB, 1,024 positions) skip reading
    /proc/meminfo (~50 µs a call); above it, too little memory is still refused first."""
    import pytest

    import kinetostatics.base.memory as memory

    calls = []
    monkeypatch.setattr(memory, "available_memory", lambda: calls.append(1) or 2**20)
    model = ks.load("mechanisms/slider_crank.yaml")
    ks.analyze(model, positions=np.radians(np.arange(0.0, 360.0, 1.0)), kinematics_only=True)
    assert calls == []
    with pytest.raises(ValueError, match="positions: the analysis at 2000 positions needs"):
        ks.analyze(model, positions=np.linspace(0.0, 6.0, 2000), kinematics_only=True)
    assert calls == [1]


def test_the_shaking_force_is_computed_when_its_columns_are_read(monkeypatch):
    """Lazy as every column: an analysis whose shaking columns are not read never
    assembles the frame's reaction; reading one does, once, for all three."""
    calls = []
    real = analysis.ground_reaction
    monkeypatch.setattr(analysis, "ground_reaction", lambda *a: calls.append(1) or real(*a))
    r = ks.analyze(ks.load("mechanisms/slider_crank.yaml"), friction=False)
    assert "shaking.Fx" in r.columns and calls == []
    fx, fy = r["shaking.Fx"], r["shaking.Fy"]
    assert calls == [1] and np.all(np.isfinite(fx)) and fy.shape == fx.shape
