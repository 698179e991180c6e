"""Self-tests of the closed-form slider-crank oracle by independent means."""

from dataclasses import replace

import numpy as np
import pytest

from tests.oracles.slider_crank_closed_form import (
    SliderCrank,
    friction_approx_torque_eq9,
    friction_terms,
    kinematics,
    power_terms,
    reactions,
    relative_speeds,
)

PHI = np.radians(np.arange(360.0))
BASE = SliderCrank()
VARIANTS = {
    "default": BASE,
    "no_resistance": replace(BASE, Fr=0.0),
    "no_gravity": replace(BASE, g=(0.0, 0.0)),
    "no_resistance_no_gravity": replace(BASE, Fr=0.0, g=(0.0, 0.0)),
    "cw_positive_offset_tilted_g": replace(BASE, omega1=-BASE.omega1, e=0.03, g=(3.0, -8.0)),
}


def rel(x, ref):
    """Accuracy (docs/conventions.md): max|x - ref| / max|ref| over the cycle."""
    return np.max(np.abs(np.asarray(x) - ref)) / np.max(np.abs(ref))


def cross(u, v):
    return u[..., 0] * v[..., 1] - u[..., 1] * v[..., 0]


@pytest.fixture(params=list(VARIANTS), ids=list(VARIANTS))
def p(request):
    return VARIANTS[request.param]


def test_geometry_closes(p):
    k = kinematics(p, PHI)
    assert np.allclose(np.hypot(k["xB"] - k["A_x"], k["yB"] - k["A_y"]), p.b, rtol=0, atol=1e-14)
    assert np.all(k["xB"] > k["A_x"])
    assert np.allclose(k["S2_x"], k["A_x"] + p.r2 / p.b * (k["xB"] - k["A_x"]), atol=1e-14)
    assert np.allclose(k["S2_y"], k["A_y"] + p.r2 / p.b * (k["yB"] - k["A_y"]), atol=1e-14)


def test_derivatives_match_central_differences(p):
    h = 1e-5
    kp, km, k = kinematics(p, PHI + h), kinematics(p, PHI - h), kinematics(p, PHI)

    def ddt(key):  # d/dt = omega1 d/dphi1
        return (kp[key] - km[key]) / (2 * h) * p.omega1

    pairs = [("phi2", "omega2"), ("omega2", "alpha2"), ("xB", "vB"), ("vB", "aB")]
    for P in ("A", "S1", "S2"):
        for c in "xy":
            pairs += [(f"{P}_{c}", f"{P}_v{c}"), (f"{P}_v{c}", f"{P}_a{c}")]
    for pos, der in pairs:
        assert rel(ddt(pos), k[der]) < 1e-6, (pos, der)
    # positions differenced twice as well
    k2p, k2m = kinematics(p, PHI + 1e-4), kinematics(p, PHI - 1e-4)
    a_fd = (k2p["xB"] - 2 * k["xB"] + k2m["xB"]) / 1e-8 * p.omega1**2
    assert rel(a_fd, k["aB"]) < 1e-6


def test_power_balance(p):
    pt = power_terms(p, PHI)
    lhs = pt["input"]
    rhs = pt["kinetic"] + pt["potential"] + pt["external"]
    big = max(np.max(np.abs(pt[t])) for t in ("input", "kinetic", "potential", "external"))
    assert np.max(np.abs(lhs - rhs)) <= 1e-10 * big
    assert np.all(pt["external"] >= 0.0)
    if p.Fr == 0.0:
        assert np.all(pt["external"] == 0.0)
    else:
        assert np.max(pt["external"]) > 0.0


def test_resistance_only_in_working_stroke(p):
    k, r = kinematics(p, PHI), reactions(p, PHI)
    assert np.all(r["F_res"][k["vB"] <= 0.0] == 0.0)
    assert np.all(r["F_res"][k["vB"] > 1e-6] == -p.Fr)


def test_free_bodies_newton_euler(p):
    """Recompute every body's balance; moments about the CoMs this time."""
    k, r = kinematics(p, PHI), reactions(p, PHI)
    g = np.asarray(p.g, dtype=float)
    vec = lambda P: np.stack([k[f"{P}_x"], k[f"{P}_y"]], axis=-1)  # noqa: E731
    acc = lambda P: np.stack([k[f"{P}_ax"], k[f"{P}_ay"]], axis=-1)  # noqa: E731
    origin = np.zeros_like(vec("A"))  # the crank pivot O
    A, S1, S2 = vec("A"), vec("S1"), vec("S2")
    B = np.stack([k["xB"], k["yB"]], axis=-1)
    aB = np.stack([k["aB"], np.zeros_like(k["aB"])], axis=-1)
    F_O, F_A, F_B = r["F_O"], r["F_A"], r["F_B"]
    n = np.array([0.0, 1.0])
    F_res = np.stack([r["F_res"], np.zeros_like(r["F_res"])], axis=-1)
    scale = np.max(np.abs(np.concatenate([F_O, F_A, F_B], axis=-1)))
    tol = 1e-12 * scale

    # slider 3: F_B + N n + m3 g + F_res = m3 aB ; moment about B: M_slide = 0
    res3 = F_B + r["N"][..., None] * n + p.m3 * g + F_res - p.m3 * aB
    assert np.max(np.abs(res3)) < tol
    assert np.max(np.abs(r["M_slide"])) < tol * p.b
    # rod 2: F_A + (-F_B) + m2 g = m2 a_S2 ; about S2: sum moments = J2 alpha2
    res2 = F_A - F_B + p.m2 * g - p.m2 * acc("S2")
    assert np.max(np.abs(res2)) < tol
    mom2 = cross(A - S2, F_A) + cross(B - S2, -F_B) - p.J2 * k["alpha2"]
    assert np.max(np.abs(mom2)) < tol * p.b
    # crank 1: F_O + (-F_A) + m1 g = m1 a_S1 ; about S1: M1 + ... = J1 alpha1
    res1 = F_O - F_A + p.m1 * g - p.m1 * acc("S1")
    assert np.max(np.abs(res1)) < tol
    mom1 = r["M1"] + cross(origin - S1, F_O) + cross(A - S1, -F_A) - p.J1 * k["alpha1"]
    assert np.max(np.abs(mom1)) < tol * p.b
    # whole machine: external forces = sum m a (internal pairs cancel)
    tot = F_O + r["N"][..., None] * n + F_res + (p.m1 + p.m2 + p.m3) * g
    assert np.max(np.abs(tot - (p.m1 * acc("S1") + p.m2 * acc("S2") + p.m3 * aB))) < tol


def test_reactions_match_generic_linear_solve(p):
    """A different route: one 8x8 Newton-Euler system per position."""
    k, r = kinematics(p, PHI), reactions(p, PHI)
    g = np.asarray(p.g, dtype=float)
    for i in range(0, 360, 7):
        A = np.array([k["A_x"][i], k["A_y"][i]])
        S1 = np.array([k["S1_x"][i], k["S1_y"][i]])
        S2 = np.array([k["S2_x"][i], k["S2_y"][i]])
        B = np.array([k["xB"][i], p.e])
        a1 = np.array([k["S1_ax"][i], k["S1_ay"][i]])
        a2 = np.array([k["S2_ax"][i], k["S2_ay"][i]])
        # unknowns: FOx FOy FAx FAy FBx FBy N M1   (M_slide = 0 by symmetry)
        M = np.zeros((8, 8))
        rhs = np.zeros(8)
        M[0, [0, 2]] = [1, -1]
        rhs[0] = p.m1 * (a1[0] - g[0])
        M[1, [1, 3]] = [1, -1]
        rhs[1] = p.m1 * (a1[1] - g[1])
        # crank moments about S1
        M[2, 0], M[2, 1] = S1[1], -S1[0]  # (O - S1) x F_O
        M[2, 2], M[2, 3] = (A - S1)[1], -(A - S1)[0]  # (A - S1) x (-F_A)
        M[2, 7] = 1.0
        rhs[2] = p.J1 * k["alpha1"][i]
        M[3, [2, 4]] = [1, -1]
        rhs[3] = p.m2 * (a2[0] - g[0])
        M[4, [3, 5]] = [1, -1]
        rhs[4] = p.m2 * (a2[1] - g[1])
        M[5, 2], M[5, 3] = -(A - S2)[1], (A - S2)[0]
        M[5, 4], M[5, 5] = (B - S2)[1], -(B - S2)[0]
        rhs[5] = p.J2 * k["alpha2"][i]
        M[6, 4] = 1
        rhs[6] = p.m3 * (k["aB"][i] - g[0]) - r["F_res"][i]
        M[7, [5, 6]] = [1, 1]
        rhs[7] = -p.m3 * g[1]
        x = np.linalg.solve(M, rhs)
        want = [r[key][i] for key in ("F_Ox", "F_Oy", "F_Ax", "F_Ay", "F_Bx", "F_By", "N", "M1")]
        assert np.allclose(x, want, rtol=1e-10, atol=1e-9)


def test_relative_speeds(p):
    k, w = kinematics(p, PHI), relative_speeds(p, PHI)
    assert np.all(w["O"] == p.omega1)
    assert np.allclose(w["A"], k["omega2"] - p.omega1)
    assert np.allclose(w["B"], -k["omega2"])
    assert np.allclose(w["slide"], k["vB"])


def test_eq9_without_friction_is_M1(p):
    p0 = replace(p, rho_O=0.0, rho_A=0.0, rho_B=0.0, f=0.0)
    assert rel(friction_approx_torque_eq9(p0, PHI), reactions(p0, PHI)["M1"]) < 1e-12


def test_eq9_friction_adds_its_power(p):
    M1 = reactions(p, PHI)["M1"]
    M1f = friction_approx_torque_eq9(p, PHI)
    fr = friction_terms(p, PHI)
    assert np.allclose((M1f - M1) * p.omega1, fr["P_fric"], rtol=1e-12, atol=1e-9)
    assert np.all(fr["P_fric"] > 0.0)
    # friction always takes power: M1' - M1 has the sign of omega1
    assert np.all(np.sign(M1f - M1) == np.sign(p.omega1))


def test_scalar_input():
    k = kinematics(BASE, 0.3)
    assert np.ndim(k["phi2"]) == 0 and np.ndim(k["omega1"]) == 0
    assert np.shape(reactions(BASE, 0.3)["F_O"]) == (2,)
    assert np.ndim(friction_approx_torque_eq9(BASE, 0.3)) == 0
