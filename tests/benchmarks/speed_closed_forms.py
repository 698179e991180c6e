"""Closed-form numpy evaluations timed by ``bench_speed.py`` (not collected by pytest).

Each function computes, in one pass over an array of crank angles, the result
columns of ``ks.analyze`` that it names: the moving links' ``x, y, theta (deg),
vx, vy, omega, ax, ay, alpha`` (``level="kinematics"``), then every joint's
reaction columns and ``motor.torque`` (``"frictionless"``), then the source
text's eq. 9 driving torque with friction, ``motor.torque_friction_approx``
(``"friction"``, slider-crank only), then the consistent friction solution by its fixed
point, every joint's friction columns and ``motor.torque_friction`` (``"fixed point"``,
slider-crank only).  No generic linear algebra, no solver: the work a hand derivation
does, written once.

* :func:`slider_crank` — the formulas of ``tests/oracles/slider_crank_closed_form.py``
  (kinematics, ``reactions``, ``friction_approx_torque_eq9``) in a single pass:
  the oracle recomputes the kinematics inside every function (five times for
  eq. 9), which would time the closed form at several times its cost.
  ``bench_speed.py`` checks it against the oracle and against ``ks.analyze``.
* :func:`slotting_machine` — the six-bar of ``mechanisms/slotting_machine.yaml``
  (docs/validation.md, "The reference machines"), derived here; ``bench_speed.py`` checks it against
  ``ks.analyze`` before timing it.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

LEVELS = ("kinematics", "frictionless", "friction", "fixed point")


def _link(cols: dict, name: str, x, y, theta, vx, vy, omega, ax, ay, alpha) -> None:
    """The nine columns of one link (theta in degrees, like the result)."""
    for label, v in zip(
        ("x", "y", "theta", "vx", "vy", "omega", "ax", "ay", "alpha"),
        (x, y, np.degrees(theta), vx, vy, omega, ax, ay, alpha),
    ):
        cols[f"{name}.{label}"] = v


# ---------------------------------------------------------------------------------------
# Offset slider-crank (mechanisms/slider_crank.yaml; tests/oracles/slider_crank_closed_form.py)
# ---------------------------------------------------------------------------------------
def slider_crank(p, phi1: np.ndarray, level: str = "kinematics") -> dict:
    """Columns of the slider-crank ``p`` (an oracle ``SliderCrank``) at crank angles ``phi1``."""
    a, b, e, r1, r2 = p.a, p.b, p.e, p.r1, p.r2
    w1 = float(p.omega1)
    n = phi1.shape
    zero, w1s = np.zeros(n), np.full(n, w1)
    c1, s1 = np.cos(phi1), np.sin(phi1)
    s2 = (e - a * s1) / b
    c2 = np.sqrt(1.0 - s2 * s2)  # B to the right of A
    phi2 = np.arctan2(s2, c2)
    w2 = -a * w1 * c1 / (b * c2)
    al2 = (a * w1**2 * s1 + b * w2**2 * s2) / (b * c2)
    xB = a * c1 + b * c2
    vB = -a * w1 * s1 - b * w2 * s2
    aB = -a * w1**2 * c1 - b * w2**2 * c2 - b * al2 * s2
    Ax, Ay, Avx, Avy = a * c1, a * s1, -a * w1 * s1, a * w1 * c1
    Aax, Aay = -a * w1**2 * c1, -a * w1**2 * s1
    S1x, S1y, S1vx, S1vy = r1 * c1, r1 * s1, -r1 * w1 * s1, r1 * w1 * c1
    S1ax, S1ay = -r1 * w1**2 * c1, -r1 * w1**2 * s1
    S2x, S2y = Ax + r2 * c2, Ay + r2 * s2
    S2vx, S2vy = Avx - r2 * w2 * s2, Avy + r2 * w2 * c2
    S2ax = Aax - r2 * w2**2 * c2 - r2 * al2 * s2
    S2ay = Aay - r2 * w2**2 * s2 + r2 * al2 * c2
    cols: dict = {}
    _link(cols, "crank", S1x, S1y, phi1, S1vx, S1vy, w1s, S1ax, S1ay, zero)
    _link(cols, "rod", S2x, S2y, phi2, S2vx, S2vy, w2, S2ax, S2ay, al2)
    _link(cols, "slider", xB, np.full(n, e), zero, vB, zero, zero, aB, zero, zero)
    if level == "kinematics":
        return cols

    # frictionless Newton-Euler, body by body (the oracle's ``reactions``)
    gx, gy = float(p.g[0]), float(p.g[1])
    m1, m2, m3 = p.m1, p.m2, p.m3
    F_res = np.where(vB > p.v_zero, -p.Fr * np.sign(vB), 0.0)
    F_Bx = m3 * aB - m3 * gx - F_res
    rhs = p.J2 * al2 + m2 * r2 * (c2 * (S2ay - gy) - s2 * (S2ax - gx))
    F_By = (b * s2 * F_Bx - rhs) / (b * c2)
    N = -F_By - m3 * gy
    F_Ax, F_Ay = F_Bx + m2 * (S2ax - gx), F_By + m2 * (S2ay - gy)
    F_Ox, F_Oy = F_Ax + m1 * (S1ax - gx), F_Ay + m1 * (S1ay - gy)
    M1 = m1 * r1 * (c1 * (S1ay - gy) - s1 * (S1ax - gx)) + a * (c1 * F_Ay - s1 * F_Ax)
    cols.update(
        {
            "O.Fx": F_Ox,
            "O.Fy": F_Oy,
            "A.Fx": F_Ax,
            "A.Fy": F_Ay,
            "B.Fx": F_Bx,
            "B.Fy": F_By,
            "slide.Fx": zero,  # N along n = (0, 1)
            "slide.Fy": N,
            "slide.N": N,
            "slide.M": zero,
            "motor.torque": M1,
        }
    )
    if level == "frictionless":
        return cols

    # the source text's eq. 9: friction loads from the frictionless reactions
    def pw(load, rel, tol):
        return np.where(np.abs(rel) > tol, np.abs(load * rel), 0.0)

    P_fric = (
        pw(p.rho_O * np.hypot(F_Ox, F_Oy), w1s, p.w_zero)
        + pw(p.rho_A * np.hypot(F_Ax, F_Ay), w2 - w1, p.w_zero)
        + pw(p.rho_B * np.hypot(F_Bx, F_By), -w2, p.w_zero)
        + pw(p.f * np.abs(N), vB, p.v_zero)
    )
    kinetic = (
        m1 * (S1vx * S1ax + S1vy * S1ay)
        + m2 * (S2vx * S2ax + S2vy * S2ay)
        + p.J2 * w2 * al2
        + m3 * vB * aB
    )
    potential = -(m1 * (gx * S1vx + gy * S1vy) + m2 * (gx * S2vx + gy * S2vy) + m3 * gx * vB)
    cols["motor.torque_friction_approx"] = (P_fric + potential + np.abs(F_res * vB) + kinetic) / w1
    if level == "friction":
        return cols
    cols.update(_slider_crank_fixed_point(p, locals()))
    return cols


def _slider_crank_fixed_point(p, k: dict) -> dict:
    """The consistent friction solution of the slider-crank by its fixed point, written out:
    the friction circles' couples ρ|F| at O, A, B and the slide's Coulomb force f|N|, each
    against its joint's relative motion (none where that is zero, the rule of
    docs/conventions.md), put into the frictionless equations body by body (the oracle's
    ``reactions`` with those loads), and the efforts evaluated again from the reactions
    they give, from the frictionless ones on, until no reaction or torque moves by more
    than 1e-13 of the largest (the library's tolerance).  A joint [i, j] turns link j
    against link i at ω_j − ω_i; its couple on j is −ρ|F| sgn(ω_j − ω_i), on i the
    opposite.  Columns: every joint's ``Fx_friction``, ``Fy_friction`` and ``friction`` (the
    effort on link j: that couple, or the slide's force along its axis), the slide's
    ``N_friction`` and ``M_friction``, and ``motor.torque_friction``."""
    a, b, r1, m1, m2, m3 = p.a, p.b, p.r1, p.m1, p.m2, p.m3
    gx, gy, c1, s1, c2, s2 = k["gx"], k["gy"], k["c1"], k["s1"], k["c2"], k["s2"]
    S1ax, S1ay, S2ax, S2ay = k["S1ax"], k["S1ay"], k["S2ax"], k["S2ay"]
    w1, w2, vB = k["w1s"], k["w2"], k["vB"]

    def sgn(rel, tol):
        return np.where(np.abs(rel) > tol, np.sign(rel), 0.0)

    s_O, s_A, s_B = sgn(w1, p.w_zero), sgn(w2 - w1, p.w_zero), sgn(-w2, p.w_zero)
    s_s = sgn(vB, p.v_zero)
    Bx0, rhs = k["F_Bx"], k["rhs"]  # the slider's x equation, the rod's moments about A
    M1_0 = m1 * r1 * (c1 * (S1ay - gy) - s1 * (S1ax - gx))
    F = {x: k[x] for x in ("F_Ox", "F_Oy", "F_Ax", "F_Ay", "F_Bx", "F_By", "N", "M1")}
    for _ in range(100):
        MO, MA = p.rho_O * np.hypot(F["F_Ox"], F["F_Oy"]), p.rho_A * np.hypot(F["F_Ax"], F["F_Ay"])
        MB, Fs = p.rho_B * np.hypot(F["F_Bx"], F["F_By"]), p.f * np.abs(F["N"])
        new = {"F_Bx": Bx0 + Fs * s_s}  # the slide's friction on the slider: −Fs sgn(vB) on x
        new["F_By"] = (b * s2 * new["F_Bx"] - rhs + (MB * s_B - MA * s_A)) / (b * c2)  # couples
        new["N"] = -new["F_By"] - m3 * gy
        new["F_Ax"], new["F_Ay"] = new["F_Bx"] + m2 * (S2ax - gx), new["F_By"] + m2 * (S2ay - gy)
        new["F_Ox"], new["F_Oy"] = new["F_Ax"] + m1 * (S1ax - gx), new["F_Ay"] + m1 * (S1ay - gy)
        new["M1"] = M1_0 + a * (c1 * new["F_Ay"] - s1 * new["F_Ax"]) + (MO * s_O - MA * s_A)
        scale = {x: (a if x == "M1" else 1.0) for x in new}  # a torque over the crank: a force
        step = max(np.max(np.abs(new[x] - F[x])) / scale[x] for x in new)
        big = max(np.max(np.abs(new[x])) / scale[x] for x in new)
        F = new
        if step <= 1e-13 * big:
            break
    F_Ox, F_Oy, F_Ax, F_Ay, F_Bx, F_By, N, M1 = (
        F[x] for x in ("F_Ox", "F_Oy", "F_Ax", "F_Ay", "F_Bx", "F_By", "N", "M1")
    )
    MO, MA = p.rho_O * np.hypot(F_Ox, F_Oy), p.rho_A * np.hypot(F_Ax, F_Ay)
    MB, Fs = p.rho_B * np.hypot(F_Bx, F_By), p.f * np.abs(N)
    return {
        "O.Fx_friction": F_Ox,
        "O.Fy_friction": F_Oy,
        "O.friction": -MO * s_O,
        "A.Fx_friction": F_Ax,
        "A.Fy_friction": F_Ay,
        "A.friction": -MA * s_A,
        "B.Fx_friction": F_Bx,
        "B.Fy_friction": F_By,
        "B.friction": -MB * s_B,
        "slide.Fx_friction": -Fs * s_s,  # the guide's friction on the slider, along x
        "slide.Fy_friction": N,
        "slide.N_friction": N,
        "slide.M_friction": MB * s_B,  # the guide holds the couple of B's circle on the slider
        "slide.friction": -Fs * s_s,
        "motor.torque_friction": M1,
    }


# ---------------------------------------------------------------------------------------
# Six-bar slotting machine (mechanisms/slotting_machine.yaml, docs/validation.md)
# ---------------------------------------------------------------------------------------
@dataclass(frozen=True)
class SlottingMachine:
    """Course-design data in SI; the dimensions by the course-design formulas."""

    K: float = 2.0  # time-ratio coefficient
    H: float = 0.100  # ram stroke [m]
    L: float = 0.150  # O2O3 [m]
    bc_ratio: float = 1.0  # L_BC / L_O3B
    c: float = 0.125  # O3 -> S3 on the A side [m]
    d: float = 0.120  # cutting force offset from the ram axis [m]
    G3: float = 160.0  # [N]
    G5: float = 320.0
    Q: float = 1000.0  # cutting force [N]
    J3: float = 0.14  # [kg m^2]
    g: float = 10.0  # [m/s^2], downward
    omega1: float = -60.0 * 2.0 * np.pi / 60.0  # 60 rpm clockwise [rad/s]
    band: tuple[float, float] = (0.05, 0.95)  # cutting travel below the top, in H

    @property
    def half_theta(self) -> float:
        return np.pi / 2 * (self.K - 1) / (self.K + 1)

    @property
    def r(self) -> float:  # O2A
        return self.L * np.sin(self.half_theta)

    @property
    def l3(self) -> float:  # O3B
        return self.H / 2 / np.sin(self.half_theta)

    @property
    def l4(self) -> float:  # BC
        return self.bc_ratio * self.l3

    @property
    def X(self) -> float:  # the ram line x = X
        return self.l3 * (1 + np.cos(self.half_theta)) / 2

    @property
    def top(self) -> float:
        """Crank angle of the ram's top (O2A ⟂ O3A)."""
        return 3 * np.pi / 2 + self.half_theta


def slotting_machine(p: SlottingMachine, phi1: np.ndarray, level: str = "kinematics") -> dict:
    """Columns of the slotting machine ``p`` at crank angles ``phi1`` (O2→A, CCW from +x).

    O3 at the origin, O2 = (−L, 0); A on the crank; the guide bar O3B points
    away from A (A = −ρ u3, u3 = (cos θ3, sin θ3)); B = l3 u3; C on x = X above B.
    Crank, block and rod are massless with their centres at O2, A and B (their
    frames' origins); S3 = c·A/ρ; the ram's centre is C.
    """
    r, l3, l4, X, w1 = p.r, p.l3, p.l4, p.X, p.omega1
    n = phi1.shape
    zero = np.zeros(n)
    c1, s1 = np.cos(phi1), np.sin(phi1)
    # crank pin A (α1 = 0)
    Ax, Ay = r * c1 - p.L, r * s1
    Avx, Avy = -r * w1 * s1, r * w1 * c1
    Aax, Aay = -r * w1**2 * c1, -r * w1**2 * s1
    # guide bar: θ3 = angle of −A; ω3 = (A × v_A)/ρ²; α3 = (A × a_A)/ρ² − 2 ω3 (A·v_A)/ρ²
    rho2 = Ax * Ax + Ay * Ay
    rho = np.sqrt(rho2)
    u3x, u3y = -Ax / rho, -Ay / rho
    th3 = np.arctan2(u3y, u3x)
    w3 = (Ax * Avy - Ay * Avx) / rho2
    al3 = (Ax * Aay - Ay * Aax) / rho2 - 2 * w3 * (Ax * Avx + Ay * Avy) / rho2
    # S3 = −c u3 and B = l3 u3: points of the bar (u̇3 = ω3 n3, n3 = (−u3y, u3x))
    S3x, S3y = -p.c * u3x, -p.c * u3y
    S3vx, S3vy = p.c * w3 * u3y, -p.c * w3 * u3x
    S3ax = p.c * (al3 * u3y + w3**2 * u3x)
    S3ay = p.c * (-al3 * u3x + w3**2 * u3y)
    Bx, By = l3 * u3x, l3 * u3y
    Bvx, Bvy = -l3 * w3 * u3y, l3 * w3 * u3x
    Bax = -l3 * (al3 * u3y + w3**2 * u3x)
    Bay = l3 * (al3 * u3x - w3**2 * u3y)
    # rod BC with C on x = X above B: l4 cos θ4 = X − Bx, yC = By + l4 sin θ4
    c4 = (X - Bx) / l4
    s4 = np.sqrt(1.0 - c4 * c4)
    th4 = np.arctan2(s4, c4)
    w4 = Bvx / (l4 * s4)
    al4 = (Bax - l4 * w4**2 * c4) / (l4 * s4)
    yC = By + l4 * s4
    vC = Bvy + l4 * w4 * c4
    aC = Bay + l4 * (al4 * c4 - w4**2 * s4)
    cols: dict = {}
    _link(cols, "crank", np.full(n, -p.L), zero, phi1, zero, zero, np.full(n, w1), zero, zero, zero)
    _link(cols, "block", Ax, Ay, th3, Avx, Avy, w3, Aax, Aay, al3)
    _link(cols, "bar", S3x, S3y, th3, S3vx, S3vy, w3, S3ax, S3ay, al3)
    _link(cols, "rod", Bx, By, th4, Bvx, Bvy, w4, Bax, Bay, al4)
    _link(cols, "ram", np.full(n, X), yC, zero, zero, vC, zero, zero, aC, zero)
    if level == "kinematics":
        return cols

    # cutting force Q up on the ram at C + (d, 0) while it moves down between 0.05 H and
    # 0.95 H below its top (the top at O2A ⟂ O3A: B at θ3 = θ/2)
    h = p.half_theta
    bx_top, by_top = l3 * np.cos(h), l3 * np.sin(h)
    y_top = by_top + np.sqrt(l4 * l4 - (X - bx_top) ** 2)
    down = y_top - yC
    v_zero = 1e-9 * abs(w1) * (l3 + p.c)  # no row sits at a reversal but the ends
    Fq = np.where((vC < -v_zero) & (down >= p.band[0] * p.H) & (down <= p.band[1] * p.H), p.Q, 0.0)
    m3, m5, g = p.G3 / p.g, p.G5 / p.g, p.g
    # ram (a = (0, aC)): rod force F_C along BC (the massless rod is a two-force member)
    FCy = m5 * (aC + g) - Fq
    FCx = FCy * c4 / s4
    # guide: frame on ram, N along n = (−1, 0), couple about C balancing Q's moment
    N5 = FCx
    M5 = -p.d * Fq
    # bar, moments about O3: block force −N2 n3 at A = −ρ u3, rod force −F_C at B
    N2 = (p.J3 * al3 + m3 * (S3x * (S3ay + g) - S3y * S3ax) + (Bx * FCy - By * FCx)) / rho
    n3x, n3y = -u3y, u3x
    FO3x = m3 * S3ax + FCx + N2 * n3x
    FO3y = m3 * (S3ay + g) + FCy + N2 * n3y
    # massless block: crank force on it = −N2 n3; massless crank: M1 = (A − O2) × F_A
    FAx, FAy = -N2 * n3x, -N2 * n3y
    M1 = (Ax + p.L) * FAy - Ay * FAx
    cols.update(
        {
            "O2.Fx": FAx,
            "O2.Fy": FAy,
            "A.Fx": FAx,
            "A.Fy": FAy,
            "slot.Fx": N2 * n3x,
            "slot.Fy": N2 * n3y,
            "slot.N": N2,
            "slot.M": zero,
            "O3.Fx": FO3x,
            "O3.Fy": FO3y,
            "B.Fx": FCx,
            "B.Fy": FCy,
            "C.Fx": FCx,
            "C.Fy": FCy,
            "guide.Fx": -N5,
            "guide.Fy": zero,
            "guide.N": N5,
            "guide.M": M5,
            "motor.torque": M1,
        }
    )
    return cols
