"""Model (b), contact–impact clearance, converges to the ideal joint (docs/clearance.md).

A crank-rod-slider: the crank turns at a prescribed 60 rpm, a constant 200 N pushes
the slider towards the crank, so the rod stays in compression (the inertia forces are
< 20 N) and the contact at B is persistent after the start.  The free coordinates are
the clearance's two (the journal's angle and centre distance s); they start touching
at rest, unloaded.  Independent truth: the ideal joint's slider position in closed
form, x = a cos θ + √(b² − a² sin² θ).  In persistent contact the journal sits e + δ
from the bushing centre, δ = (F/K)^(2/3) the Hertzian penetration under F = 200 N, so
the slider is displaced by −(e + δ): the deviation → 0 as e → 0 at fixed K down to
the compliance floor δ, and as K → ∞ at fixed e down to the geometric floor e.
"""

from __future__ import annotations

import numpy as np
import pytest

import kinetostatics as ks
from kinetostatics.dynamics.clearance import with_clearance
from kinetostatics.dynamics.contact import ContactLaw, simulate_contact

CRANK_ROD_SLIDER = """
name: crank-rod-slider with a clearance at B
units: {length: mm, angle: deg, speed: rpm, mass: kg, force: N, inertia: kg*m^2}
gravity: [0, 0]
links:
  ground: {points: {O: [0, 0], guide: [0, 0]}}
  crank: {points: {O: [0, 0], A: [100, 0]}, com: [30, 0], mass: 2, inertia: 0.006}
  rod: {points: {A: [0, 0], B: [350, 0]}, com: [120, 0], mass: 3, inertia: 0.031}
  slider: {points: {B: [0, 0]}, mass: 4}
joints:
  O: {type: revolute, links: [ground, crank]}
  A: {type: revolute, links: [crank, rod]}
  B: {type: revolute, links: [rod, slider]}
  slide: {type: prismatic, links: [ground, slider], axis: {point: guide, direction: [1, 0]},
          point: B}
drivers:
  motor: {joint: O, motion: {speed: 60}}
loads:
  push: {type: force, link: slider, point: B, value: [-200, 0]}
clearance:
  B: {size: 0.1, model: contact, contact: {journal_radius: 10, restitution: 0.9}}
sketch: {A: [86.6025, 50], B: [433.0127, 0]}
analysis: {start: 30, sweep: 360, positions: 36}
"""
A, B, OMEGA, THETA0, PUSH = 0.1, 0.35, 2 * np.pi, np.radians(30.0), 200.0
T = 0.02  # s: the start-up transient and ~10 ms settled


@pytest.fixture(scope="module")
def model():
    return ks.loads(CRANK_ROD_SLIDER)


def _ideal(t):
    th = THETA0 + OMEGA * t
    root = np.sqrt(B**2 - (A * np.sin(th)) ** 2)
    x = A * np.cos(th) + root
    v = -A * OMEGA * np.sin(th) * (1.0 + A * np.cos(th) / root)
    return x, v


_RUNS: dict = {}


def deviation(model, e: float, k: float) -> dict:
    """Slider deviations from the ideal joint over 0–T: max |Δx|, the settled mean Δx
    (second half), max |Δv|, max |Δa| (m, m/s, m/s²)."""
    if (e, k) not in _RUNS:
        law = ContactLaw(journal_radius=0.01, restitution=0.9, stiffness=k)
        run = simulate_contact(
            with_clearance(model, size=e, contact=law), T, rtol=1e-5, method="RK45"
        )
        dyn = run.dynamics
        t = np.linspace(0.0, T, 101)
        j = 3 * dyn.system.link_index("slider")
        ev = [dyn.state(float(tk), yk) for tk, yk in zip(t, run.sample(t))]
        x = np.array([s.q[j] for s in ev])
        v = np.array([s.qd[j] for s in ev])
        a = np.array([(s.qdd0 + s.accel @ s.dqdd)[j] for s in ev])
        xi, vi = _ideal(t)
        ai = np.gradient(vi, t)
        late = t >= T / 2
        _RUNS[e, k] = {
            "dx": np.max(np.abs(x - xi)),
            "settled": float(np.mean((x - xi)[late])),
            "dv": np.max(np.abs(v - vi)),
            "da": np.max(np.abs(a - ai)),
            "separations": len(run.separations),
        }
    return _RUNS[e, k]


def penetration(k: float) -> float:
    return (PUSH / k) ** (2.0 / 3.0)


@pytest.mark.parametrize("k", [1e9, 1e10])
def test_persistent_contact_offset_is_clearance_plus_hertz_penetration(model, k):
    """Once the start-up oscillation has died out (K ≥ 1e9: within 10 ms)."""
    d = deviation(model, 1e-6, k)
    assert d["separations"] == 0
    assert -d["settled"] == pytest.approx(1e-6 + penetration(k), rel=0.05)


def test_contact_converges_to_ideal_as_stiffness_grows(model):
    """e = 1 µm: max |Δx| ∝ K^(-2/3) (×4.6 per decade), the start-up velocity jolt
    ∝ K^(-1/3) (×2.2); the acceleration jolt does not shrink (it is set by the unloaded
    start: the slider first feels the 200 N alone), only its duration does."""
    d = [deviation(model, 1e-6, k) for k in (1e8, 1e9, 1e10)]
    dx, dv, da = (np.array([r[key] for r in d]) for key in ("dx", "dv", "da"))
    assert np.all(dx[1:] < dx[:-1]) and np.all(dx[:-1] / dx[1:] > 3.5)
    assert np.all(dv[1:] < dv[:-1]) and np.all(dv[:-1] / dv[1:] > 1.6)
    assert np.max(da) / np.min(da) < 1.2 and np.min(da) > 0.8 * PUSH / 4.0


def test_contact_converges_to_ideal_as_clearance_shrinks(model):
    """K = 1e10 N/m^1.5 fixed (δ = 7.4 µm): max |Δx| ≈ e + δ falls ×3.5 per e/4, towards δ."""
    sizes = (1e-3, 2.5e-4, 6.25e-5)
    dx = np.array([deviation(model, e, 1e10)["dx"] for e in sizes])
    assert np.all(dx[:-1] / dx[1:] > 3.0)
    np.testing.assert_allclose(dx, np.array(sizes) + penetration(1e10), rtol=0.05)
