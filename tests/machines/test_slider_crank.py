"""The offset slider-crank against an independent closed-form derivation
(tests/oracles/slider_crank_closed_form.py, written from the free-body
equations by hand): kinematics, reactions, driving torque, the source's
eq. 9, and the power balance with friction."""

from dataclasses import replace

import numpy as np
import pytest

import kinetostatics as ks
from tests.helpers import rel_err, variant
from tests.oracles import slider_crank_closed_form as cf

CCW = cf.SliderCrank()
CW = replace(CCW, omega1=-CCW.omega1)


@pytest.fixture(scope="module", params=["ccw", "cw"])
def case(request):
    if request.param == "ccw":
        model, p = ks.load("mechanisms/slider_crank.yaml"), CCW
    else:
        model, p = variant("slider_crank", speed=(r"speed: 300", "speed: -300")), CW
    return ks.analyze(model), p


def test_kinematics_match_closed_form(case):
    r, p = case
    phi1 = np.radians(r["angle"])
    k = cf.kinematics(p, phi1)
    assert rel_err(r["crank.omega"], np.full_like(phi1, p.omega1)) < 1e-12
    assert rel_err(np.unwrap(np.radians(r["rod.theta"])), np.unwrap(k["phi2"])) < 1e-9
    for ours, theirs in [
        ("rod.omega", "omega2"),
        ("rod.alpha", "alpha2"),
        ("slider.x", "xB"),
        ("slider.vx", "vB"),
        ("slider.ax", "aB"),
        ("rod.x", "S2_x"),
        ("rod.y", "S2_y"),
        ("rod.vx", "S2_vx"),
        ("rod.vy", "S2_vy"),
        ("rod.ax", "S2_ax"),
        ("rod.ay", "S2_ay"),
        ("crank.ax", "S1_ax"),
        ("crank.A.x", "A_x"),
        ("crank.A.vy", "A_vy"),
        ("rod.A.ay", "A_ay"),
    ]:
        assert rel_err(r[ours], k[theirs]) < 1e-9, ours


def test_reactions_and_torque_match_closed_form(case):
    r, p = case
    ref = cf.reactions(p, np.radians(r["angle"]))
    assert rel_err(r["motor.torque"], ref["M1"]) < 1e-9
    for joint, key in [("O", "F_O"), ("A", "F_A"), ("B", "F_B")]:
        assert rel_err(r[f"{joint}.Fx"], ref[key + "x"]) < 1e-9
        assert rel_err(r[f"{joint}.Fy"], ref[key + "y"]) < 1e-9
    assert rel_err(r["slide.N"], ref["N"]) < 1e-9
    assert np.max(np.abs(r["slide.M"])) < 1e-9 * np.max(np.abs(ref["N"]))


def test_approximate_friction_torque_is_eq9(case):
    r, p = case
    assert (
        rel_err(
            r["motor.torque_friction_approx"],
            cf.friction_approx_torque_eq9(p, np.radians(r["angle"])),
        )
        < 1e-9
    )


def test_power_balance_frictionless_and_consistent(case):
    r, _ = case
    scale = max(
        np.max(np.abs(r[f"power.{k}"])) for k in ("input", "kinetic", "potential", "external")
    )
    assert np.max(np.abs(r["power.residual"])) <= 1e-9 * scale
    ok = np.isin(r["friction.status"], (0, 1, 3))
    assert ok.all()
    assert np.max(np.abs(r["power.residual_friction"])) <= 1e-9 * scale
    # friction only ever costs input power
    assert np.all(r["power.friction"] >= 0)


def test_consistent_solution_is_an_equilibrium_with_its_own_friction(case):
    """Re-derive the friction loads from the consistent reactions and check the
    closed-form crank equilibrium: M1' = M1_frictionless(with those loads)."""
    r, p = case
    st = r["friction.status"]
    fO = r["O.friction"]
    # the friction couple at O is ρ_O |F_O| from the consistent reaction, opposing ω1
    mag = np.hypot(r["O.Fx_friction"], r["O.Fy_friction"]) * p.rho_O
    np.testing.assert_allclose(np.abs(fO[st == 0]), mag[st == 0], rtol=1e-12)
    assert np.all(np.sign(fO[st == 0]) == -np.sign(p.omega1))


def test_events_are_the_slider_dead_centres():
    r = ks.analyze(ks.load("mechanisms/slider_crank.yaml"))
    phi = np.array([e.coordinate for e in r.events])
    k = cf.kinematics(CCW, phi)
    np.testing.assert_allclose(k["vB"], 0.0, atol=1e-12)
    assert [e.switch for e in r.events] == ["on", "off"]
