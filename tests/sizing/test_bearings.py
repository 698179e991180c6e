"""Bearing life (ISO 281) and plain bearings (sizing/bearings.py, sizing/stage.py) against
hand calculations and the published equivalent-speed rule for oscillating motion."""

from __future__ import annotations

import numpy as np
import pytest

import kinetostatics as ks
from kinetostatics.sizing import sizing_stage
from kinetostatics.sizing.bearings import (
    EXPONENTS,
    equivalent_load,
    equivalent_speed,
    plain_loading,
    rating_life,
)
from tests.helpers import ROOT


@pytest.mark.parametrize("kind", ["ball", "roller"])
def test_constant_load_and_speed(kind):
    """A constant radial load at a constant speed: P = F and L10 = (C/P)^p · 10⁶ rev."""
    p = EXPONENTS[kind]
    t = np.full(50, 0.02)  # weights (s) over one second
    omega = np.full(50, 2 * np.pi * 25.0)  # 1500 rpm
    P = equivalent_load(np.full(50, 1800.0), omega, t, p)
    assert P == pytest.approx(1800.0, rel=1e-14)
    C = 12_700.0
    assert rating_life(C, P, p) == pytest.approx((C / 1800.0) ** p * 1e6, rel=1e-12)
    assert equivalent_speed(omega, t) == pytest.approx(25.0, rel=1e-14)
    assert p == (3.0 if kind == "ball" else 10.0 / 3.0)


def test_two_step_spectrum_is_the_hand_cubic_mean():
    """2 kN for 30 % of the time at 100 rpm, then 1 kN for 70 % at 300 rpm: P is the cube
    root of Σ F³·n·t / Σ n·t, by hand: (8·30 + 1·210)/240 kN³ = 1.875 kN³, P = 1.2329 kN."""
    t = np.array([0.3, 0.7])
    n_rpm = np.array([100.0, 300.0])
    F = np.array([2000.0, 1000.0])
    # by hand: revolutions in each step 0.3·100 = 30, 0.7·300 = 210 (per minute of run)
    hand = ((2000.0**3 * 30 + 1000.0**3 * 210) / (30 + 210)) ** (1 / 3)
    assert hand == pytest.approx(1000.0 * (450 / 240) ** (1 / 3), rel=1e-12)  # 1232.9 N
    P = equivalent_load(F, n_rpm * 2 * np.pi / 60, t, 3.0)
    assert P == pytest.approx(hand, rel=1e-13)


def test_oscillation_follows_the_equivalent_speed_rule():
    """A swing of φ = 40° at f = 3 Hz, θ = (φ/2)·sin(2πft): the mean speed is that of the
    rule of ISO 281 and the bearing makers, n_eq = f · 2φ/360° rev/s (SKF, *Rolling
    bearings*, "Oscillating movements"), and a constant load gives L10 in hours as that
    speed does."""
    f, phi = 3.0, np.radians(40.0)
    x, w = np.polynomial.legendre.leggauss(16)
    edges = np.linspace(0.0, 1.0 / f, 41)  # Gauss–Legendre on pieces of the period
    half = np.diff(edges)[:, None] / 2
    t = (edges[:-1, None] + half * (x + 1)).ravel()
    weights = (half * w).ravel()
    omega = (phi / 2) * 2 * np.pi * f * np.cos(2 * np.pi * f * t)
    n_eq = f * 2 * 40.0 / 360.0
    assert equivalent_speed(omega, weights) == pytest.approx(n_eq, rel=1e-10)
    P = equivalent_load(np.full(t.shape, 900.0), omega, weights, 10 / 3)
    assert P == pytest.approx(900.0, rel=1e-12)


@pytest.fixture(scope="module")
def sized():
    result = ks.analyze(ks.load(ROOT / "mechanisms" / "slider_crank_sized.yaml"))
    return result, sizing_stage(result)


def test_the_wrist_pin_oscillates_by_the_rods_swing(sized):
    """B joins the rod and the slider, which does not turn: its relative angle is the rod's,
    β = asin((e − a·sin θ)/b), whose swing is asin((a − e)/b) + asin((a + e)/b), and it
    turns 2·swing per crank revolution (the equivalent-speed rule at 300 rpm)."""
    _, sizing = sized
    b = next(x for x in sizing.bearings if x.joint == "B")
    a, rod, e = 100.0, 350.0, -20.0
    swing = np.degrees(np.arcsin((a - e) / rod) + np.arcsin((a + e) / rod))
    assert b.motion == "oscillating"
    assert b.swing == pytest.approx(swing, abs=1e-3)  # the rows and nodes hold the extremes
    # ∫|ω|dt by the cycle's quadrature, which does not cut at the reversals (|ω| kinks
    # there): a few 1e-5
    assert b.speed == pytest.approx(5.0 * 2 * swing / 360.0, rel=1e-4)
    assert b.life[1] == pytest.approx(b.life[0] / (3600 * b.speed), rel=1e-12)
    assert b.life[0] == pytest.approx((5600.0 / b.P) ** (10 / 3) * 1e6, rel=1e-12)


def test_the_shaft_bearing_turns_with_the_crank(sized):
    result, sizing = sized
    o = next(x for x in sizing.bearings if x.joint == "O")
    assert o.motion == "rotating" and o.speed == pytest.approx(5.0, rel=1e-9)
    mag = np.hypot(result["O.Fx"], result["O.Fy"])
    assert np.max(np.abs(o.force - mag)) < 1e-9 * mag.max()
    # P lies between the least and the largest load, and near the cubic mean of the rows
    # (equally spaced in time at constant speed: the rows are samples of the cycle)
    assert mag.min() <= o.P <= mag.max()
    assert o.P == pytest.approx(np.mean(mag**3) ** (1 / 3), rel=2e-3)


def test_plain_bearing_by_hand(sized):
    result, sizing = sized
    a = next(x for x in sizing.bearings if x.joint == "A")
    d, width = 0.016, 0.020
    mag = np.hypot(result["A.Fx"], result["A.Fy"])
    w_rel = result["rod.omega"] - result["crank.omega"]
    p, v, pv = (a.plain[k][0] for k in ("p", "v", "pv"))
    assert np.allclose(p, mag / (d * width), rtol=1e-12, atol=0)
    assert np.allclose(v, np.abs(w_rel) * d / 2, rtol=1e-12, atol=0)
    assert np.allclose(pv, mag / (d * width) * np.abs(w_rel) * d / 2, rtol=1e-12, atol=0)
    assert a.plain["p"][1] >= p.max()
    assert a.plain["p"][3] == pytest.approx(14e6)  # p_max: 14 N/mm² read as Pa
    q, vv, _ = plain_loading([1000.0], [10.0], 0.02, 0.01)
    assert (q[0], vv[0]) == (pytest.approx(5e6), pytest.approx(0.1))


def test_a_limit_exceeded_is_a_warning():
    text = (ROOT / "mechanisms" / "slider_crank_sized.yaml").read_text()
    text = text.replace("p_max: 14,", "p_max: 2,")
    result = ks.analyze(ks.loads(text, file="limits.yaml"))
    sizing = sizing_stage(result)
    assert any(
        "joint 'A'" in w and "peak p" in w and "p_max = 2 MPa" in w for w in sizing.warnings
    ), sizing.warnings
