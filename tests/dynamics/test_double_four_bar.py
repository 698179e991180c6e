"""The double four-bar mechanism (IFToMM benchmark A02, N = 2; mechanisms/double_four_bar.yaml;
docs/benchmarks.md) by forward dynamics: the start pose, the reduced inertia and gravity
torque of the parallelogram mode in closed form, the motion through two singular positions
against the exact pendulum motion with the parallelogram mode kept, and B0 at t = 10 s
against the exact motion and Exudyn's published values (tests/double_four_bar_reference.py)."""

from __future__ import annotations

import numpy as np
import pytest

import kinetostatics as ks
from kinetostatics.dynamics import simulate
from tests import double_four_bar_reference as ref
from tests.helpers import ROOT

PATH = ROOT / "mechanisms" / "double_four_bar.yaml"
START = {"free": (ref.THETA0, ref.OMEGA0)}


@pytest.fixture(scope="module")
def model():
    return ks.load(PATH)


def _angles(sim, t):
    y = sim.sample([t])[0]
    ev = sim.dynamics.evaluate(t, y[:1], y[1:2])
    system = sim.dynamics.system
    return {n: ev.q[3 * system.link_index(n) + 2] for n in system.links}, ev


def _wrapped(a):
    return np.abs(np.angle(np.exp(1j * np.asarray(a))))


@pytest.fixture(scope="module")
def two_passes(model):
    """1.5 s: θ from 90° through 0 (t ≈ 0.72 s) and −180° (t ≈ 1.1 s) to about −290°."""
    sim = simulate(model, 1.5, initial=START, method="DOP853", rtol=1e-10)
    return sim


def test_the_start_and_the_reduced_equation(model, two_passes):
    """Cranks vertical, couplers level at y = 1 m; along the motion the equivalent inertia
    is 3 kg·m² (2T/θ̇², T = 1.5 θ̇²) and θ̈ = −(7g/6) cos θ."""
    th, ev = _angles(two_passes, 0.0)
    assert (
        _wrapped([th["crank0"] - np.pi / 2, th["crank1"] - np.pi / 2, th["coupler1"]]).max() < 1e-12
    )
    system = two_passes.dynamics.system
    k = system.link_index("coupler2")
    assert ev.q[3 * k + 1] == pytest.approx(1.0, abs=1e-12)  # its centre at height L
    cols, _ = two_passes.table(points=151)
    np.testing.assert_allclose(cols["equivalent.inertia"], 3.0, rtol=1e-10)
    theta = np.radians(cols["free.angle"])
    want = -7.0 * ref.G / 6.0 * np.cos(theta)
    np.testing.assert_allclose(cols["free.acceleration"], want, rtol=0, atol=1e-8 * 7 * ref.G / 6)


def test_through_two_singular_positions(two_passes):
    """θ and θ̇ equal the exact motion, the energy is constant, and after both singular
    positions the cranks are parallel and the couplers level (the parallelogram mode)."""
    t = np.linspace(0.0, 1.5, 301)
    cols, _ = two_passes.table(t=t)
    theta, omega = np.radians(cols["free.angle"]), cols["free.speed"]
    assert theta[-1] < -np.pi - 0.5  # both singular poses passed
    th_x, om_x = ref.exact(t)
    assert np.max(np.abs(theta - th_x)) <= 1e-7
    assert np.max(np.abs(omega - om_x)) <= 1e-7 * np.max(np.abs(om_x))
    e = cols["energy.total"]
    assert e[0] == pytest.approx(1.5 + 3.5 * ref.G, rel=1e-12)  # kinetic 1.5 J at the top
    assert np.max(np.abs(e - e[0])) <= 1e-8 * e[0]
    for tt in t[::10]:
        th, _ = _angles(two_passes, tt)
        c = th["crank0"]
        dev = _wrapped([th["crank1"] - c, th["crank2"] - c, th["coupler1"], th["coupler2"]])
        assert dev.max() <= 1e-9, tt


def test_b0_at_ten_seconds_against_the_exact_motion_and_exudyn(model):
    """Eight singular positions in 10 s; B0's (x, y, vx, vy) at 10 s: to the exact motion
    within 1e-6, and to Exudyn's finest published values within their own step error
    (their last two steps differ by 4e-6 in velocity; the exact limit is 1.8e-6 away)."""
    sim = simulate(model, ref.T_END, initial=START, method="DOP853", rtol=1e-9)
    cols, _ = sim.table(t=[ref.T_END])
    theta, omega = np.radians(cols["free.angle"][-1]), cols["free.speed"][-1]
    assert theta < ref.THETA0 - 8 * np.pi  # passes 0, −180°, … eight times
    got = ref.b0(theta, omega)
    th_x, om_x = ref.exact([ref.T_END])
    assert np.max(np.abs(got - ref.b0(th_x[0], om_x[0]))) <= 1e-6
    assert np.max(np.abs(got[:2] - ref.EXUDYN_B0[:2])) <= 1.5e-6
    assert np.max(np.abs(got[2:] - ref.EXUDYN_B0[2:])) <= 3e-6
