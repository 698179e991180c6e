"""The six-bar slotting machine: course-design geometry, stroke H, time ratio K,
the course-design positions, exact cutting events, and derivatives against
central differences of the computed positions."""

import numpy as np
import pytest

import kinetostatics as ks
from kinetostatics.dynamics.stages import full_summary


@pytest.fixture(scope="module")
def model():
    return ks.load("mechanisms/slotting_machine.yaml")


@pytest.fixture(scope="module")
def result(model):
    return ks.analyze(model)


def test_derived_dimensions(model):
    p = model.parameters
    assert p["theta"] == pytest.approx(60.0, abs=1e-12)
    assert p["L_O2A"] == pytest.approx(75.0, abs=1e-12)
    assert p["L_O3B"] == pytest.approx(100.0, abs=1e-12)
    assert p["L_BC"] == pytest.approx(100.0, abs=1e-12)
    assert p["X"] == pytest.approx(93.30127018922193, abs=1e-12)
    assert round(p["X"], 2) == 93.30


def test_stroke_and_time_ratio(result):
    out = full_summary(result)["outputs"]["guide"]
    assert out["stroke"] == pytest.approx(0.100, rel=1e-12)
    assert out["time_ratio"] == pytest.approx(2.0, rel=1e-9)
    # limit positions: ram top at position 1 (300°), bottom at position 9 (60°)
    assert out["limit_positions"]["max"]["angle"] == pytest.approx(300.0, abs=1e-7)
    assert out["limit_positions"]["min"]["angle"] == pytest.approx(60.0, abs=1e-7)


def test_course_design_positions(result):
    """Rows 0, 30, …, 330 are positions 1…12: crank at 300° − 30°(k−1)."""
    rows = np.arange(0, 360, 30)
    expected = (300.0 - 30.0 * np.arange(12)) % 360.0
    np.testing.assert_allclose(result["angle"][rows], expected, atol=1e-9)
    y = result["ram.y"]
    assert np.argmax(y) == 0  # position 1: ram at the top
    assert np.argmin(y) == 240  # position 9 (row 240): at the bottom
    # O2A ⟂ O3A at position 1 (the guide bar is tangent to the crank circle)
    a = np.array([result["crank.A.x"][0], result["crank.A.y"][0]])
    o2 = np.array([-0.150, 0.0])
    assert np.dot(a - o2, a) == pytest.approx(0.0, abs=1e-14)


def test_cutting_starts_and_ends_where_the_band_says(result):
    ev = {(e.switch): e for e in result.events}
    assert np.degrees(ev["on"].coordinate) % 360 == pytest.approx(270.422, abs=5e-4)
    assert np.degrees(ev["off"].coordinate) % 360 == pytest.approx(88.632, abs=5e-4)
    # the ram has travelled exactly 0.05 H and 0.95 H below its top there
    for e, frac in ((ev["on"], 0.05), (ev["off"], 0.95)):
        r = ks.analyze(result.system, positions=[e.coordinate])
        assert result["ram.y"].max() - r["ram.y"][0] == pytest.approx(frac * 0.1, abs=1e-12)


def test_derivatives_match_central_differences(model):
    r = ks.analyze(model, positions=np.radians(300 - np.arange(0, 360, 0.5)))
    h = r.t[1] - r.t[0]
    for x, dx, name in ((r.q, r.qd, "velocity"), (r.qd, r.qdd, "acceleration")):
        fd = (x[2:] - x[:-2]) / (2 * h)
        err = np.max(np.abs(fd - dx[1:-1]), axis=0) / np.maximum(np.max(np.abs(dx), axis=0), 1e-300)
        # central differences are second order: error ≈ h² x‴/6
        assert np.max(err[np.max(np.abs(dx), axis=0) > 1e-9]) < 5e-4, name


def test_frictionless_power_balance(result):
    scale = max(
        np.max(np.abs(result[f"power.{k}"])) for k in ("input", "kinetic", "potential", "external")
    )
    assert np.max(np.abs(result["power.residual"])) <= 1e-9 * scale
    assert (
        np.max(np.abs(result["power.residual_friction"][result["friction.status"] < 2]))
        <= 1e-9 * scale
    )
