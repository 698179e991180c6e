"""Independent closed-form oracle: kinetostatics of an offset slider-crank.

Test helper only. It does not import the package under test. Everything is
written out by hand (no generic linear system, no finite differences) so that
the generic Newton-Euler code can be compared against it.

Conventions (``docs/conventions.md``): SI; x right, y up; angles CCW from +x;
angular velocities, accelerations, couples and torques CCW positive. A joint
``[i, j]`` reports the force exerted **by link i on link j**:

* ``O``     = [ground, crank]   -> ``F_O``  force of ground on crank
* ``A``     = [crank, rod]      -> ``F_A``  force of crank on rod
* ``B``     = [rod, slider]     -> ``F_B``  force of rod on slider
* ``slide`` = [ground, slider]  -> ``N``    force of ground on slider along
  n = u rotated +90 deg = (0, 1) (u = (1, 0)); ``M_slide`` couple of ground on
  slider about B.
* ``M1`` torque of ground on crank (driving / balancing torque).

Geometry (``docs/validation.md``, "The reference machines"): crank OA (length a, angle phi1 of
O->A, constant speed omega1), rod AB (length b, angle phi2 of A->B), slider B
on the line y = e, B to the right of A (cos phi2 > 0). CoM of the crank at r1
from O on OA, of the rod at r2 from A on AB, of the slider at B.

Loads: gravity ``m_k * g`` at every CoM (``g`` any 2-vector); resistance on
the slider along x, ``F_res = -Fr * sign(vB)`` while ``vB > 0`` (working
stroke), else 0, acting through B.

All functions broadcast over an array of crank angles ``phi1`` (radians).

Run ``python tests/oracles/slider_crank_closed_form.py`` for a self-check.
"""

from __future__ import annotations

from dataclasses import dataclass, replace

import numpy as np

__all__ = [
    "SliderCrank",
    "kinematics",
    "relative_speeds",
    "reactions",
    "power_terms",
    "friction_terms",
    "friction_approx_torque_eq9",
]

#: docs/conventions.md "Zero relative speed": |x| <= ZERO_REL * x_ref counts as zero.
ZERO_REL = 1e-9


@dataclass(frozen=True)
class SliderCrank:
    """Data of the offset slider-crank; defaults: the reference one (docs/validation.md)."""

    a: float = 0.10  # crank OA [m]
    b: float = 0.35  # rod AB [m]
    e: float = -0.02  # guide line y = e [m]
    r1: float = 0.03  # O -> crank CoM [m]
    r2: float = 0.12  # A -> rod CoM [m]
    m1: float = 2.0  # [kg]
    m2: float = 3.0
    m3: float = 4.0
    J1: float = 0.006  # about the crank CoM [kg m^2]
    J2: float = 0.031  # about the rod CoM [kg m^2]
    omega1: float = 300.0 * 2.0 * np.pi / 60.0  # signed, CCW positive [rad/s]
    g: tuple[float, float] = (0.0, -9.81)  # gravity vector [m/s^2]
    Fr: float = 1000.0  # resistance magnitude, working stroke only [N]
    rho_O: float = 1.5e-3  # friction-circle radii [m]
    rho_A: float = 1.2e-3
    rho_B: float = 1.0e-3
    f: float = 0.10  # slide Coulomb coefficient
    L_ref: float | None = None  # length scale for the zero-speed rule (None: a)

    @property
    def v_zero(self) -> float:
        """Sliding speeds with |v| <= v_zero count as zero (docs/conventions.md)."""
        L = self.a if self.L_ref is None else self.L_ref
        return ZERO_REL * abs(self.omega1) * L

    @property
    def w_zero(self) -> float:
        """Relative angular speeds with |w| <= w_zero count as zero (docs/conventions.md)."""
        return ZERO_REL * abs(self.omega1)


def _cross(ux, uy, vx, vy):
    """z-component of the planar cross product u x v."""
    return ux * vy - uy * vx


# ---------------------------------------------------------------------------
# Kinematics
# ---------------------------------------------------------------------------
def kinematics(p: SliderCrank, phi1) -> dict:
    """Closed-form positions, velocities and accelerations.

    Loop equations (B - A along the rod, B on y = e):
        a sin(phi1) + b sin(phi2) = e
        xB = a cos(phi1) + b cos(phi2)
    Differentiated once (alpha1 = 0, omega1 constant):
        a w1 cos(phi1) + b w2 cos(phi2) = 0
        vB = -a w1 sin(phi1) - b w2 sin(phi2)
    and twice:
        -a w1^2 sin(phi1) - b w2^2 sin(phi2) + b alpha2 cos(phi2) = 0
        aB = -a w1^2 cos(phi1) - b w2^2 cos(phi2) - b alpha2 sin(phi2)

    Keys: phi1, omega1, alpha1, phi2, omega2, alpha2, xB, yB, vB, aB,
    and for points A (crank pin), S1 (crank CoM), S2 (rod CoM):
    ``<P>_x, <P>_y, <P>_vx, <P>_vy, <P>_ax, <P>_ay``. Slider CoM = B
    (vy = ay = 0).
    """
    phi1 = np.asarray(phi1, dtype=float)
    a, b, e, r1, r2 = p.a, p.b, p.e, p.r1, p.r2
    w1 = float(p.omega1)
    al1 = 0.0  # constant crank speed

    c1, s1 = np.cos(phi1), np.sin(phi1)
    s2 = (e - a * s1) / b
    if np.any(np.abs(s2) > 1.0):
        bad = np.degrees(np.atleast_1d(phi1)[np.atleast_1d(np.abs(s2) > 1.0)])
        raise ValueError(
            f"slider-crank cannot assemble at phi1 = {bad[:5]} deg: "
            f"|e - a sin(phi1)| > b (a={a}, b={b}, e={e})"
        )
    c2 = np.sqrt(1.0 - s2 * s2)  # B to the right of A
    phi2 = np.arctan2(s2, c2)

    w2 = -a * w1 * c1 / (b * c2)
    al2 = (a * w1**2 * s1 - a * al1 * c1 + b * w2**2 * s2) / (b * c2)

    xB = a * c1 + b * c2
    vB = -a * w1 * s1 - b * w2 * s2
    aB = -a * w1**2 * c1 - a * al1 * s1 - b * w2**2 * c2 - b * al2 * s2

    # crank pin A
    Ax, Ay = a * c1, a * s1
    Avx, Avy = -a * w1 * s1, a * w1 * c1
    Aax, Aay = -a * w1**2 * c1 - a * al1 * s1, -a * w1**2 * s1 + a * al1 * c1
    # crank CoM S1 = r1 (c1, s1)
    S1x, S1y = r1 * c1, r1 * s1
    S1vx, S1vy = -r1 * w1 * s1, r1 * w1 * c1
    S1ax, S1ay = -r1 * w1**2 * c1 - r1 * al1 * s1, -r1 * w1**2 * s1 + r1 * al1 * c1
    # rod CoM S2 = A + r2 (c2, s2)
    S2x, S2y = Ax + r2 * c2, Ay + r2 * s2
    S2vx, S2vy = Avx - r2 * w2 * s2, Avy + r2 * w2 * c2
    S2ax = Aax - r2 * w2**2 * c2 - r2 * al2 * s2
    S2ay = Aay - r2 * w2**2 * s2 + r2 * al2 * c2

    full = np.broadcast_to  # constants as arrays of the same shape
    shp = phi1.shape
    return {
        "phi1": phi1,
        "omega1": full(np.float64(w1), shp).copy(),
        "alpha1": full(np.float64(al1), shp).copy(),
        "phi2": phi2,
        "omega2": w2,
        "alpha2": al2,
        "xB": xB,
        "yB": full(np.float64(e), shp).copy(),
        "vB": vB,
        "aB": aB,
        "A_x": Ax,
        "A_y": Ay,
        "A_vx": Avx,
        "A_vy": Avy,
        "A_ax": Aax,
        "A_ay": Aay,
        "S1_x": S1x,
        "S1_y": S1y,
        "S1_vx": S1vx,
        "S1_vy": S1vy,
        "S1_ax": S1ax,
        "S1_ay": S1ay,
        "S2_x": S2x,
        "S2_y": S2y,
        "S2_vx": S2vx,
        "S2_vy": S2vy,
        "S2_ax": S2ax,
        "S2_ay": S2ay,
    }


def state(p: SliderCrank, phi1) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(q, q̇, q̈) ``(n, 9)`` in the library's coordinate layout: crank, rod,
    slider, each (x, y of the centre of mass, θ of the link's local x axis)."""
    k = kinematics(p, phi1)
    z = np.zeros_like(k["phi2"])
    q = np.stack(
        [k["S1_x"], k["S1_y"], k["phi1"], k["S2_x"], k["S2_y"], k["phi2"], k["xB"], k["yB"], z], -1
    )
    qd = np.stack(
        [k["S1_vx"], k["S1_vy"], k["omega1"], k["S2_vx"], k["S2_vy"], k["omega2"], k["vB"], z, z],
        -1,
    )
    qdd = np.stack(
        [k["S1_ax"], k["S1_ay"], k["alpha1"], k["S2_ax"], k["S2_ay"], k["alpha2"], k["aB"], z, z],
        -1,
    )
    return q, qd, qdd


def relative_speeds(p: SliderCrank, phi1) -> dict:
    """Relative speeds of the joints, second link minus first link.

    Keys: ``O`` = omega_crank - omega_ground = omega1,
    ``A`` = omega_rod - omega_crank = omega2 - omega1,
    ``B`` = omega_slider - omega_rod = 0 - omega2,
    ``slide`` = sliding speed of the slider along u = (1, 0) = vB.
    """
    k = kinematics(p, phi1)
    return {
        "O": k["omega1"] - 0.0,
        "A": k["omega2"] - k["omega1"],
        "B": 0.0 - k["omega2"],
        "slide": k["vB"],
    }


def _resistance(p: SliderCrank, vB):
    """F_res along x: -Fr*sign(vB) while vB > 0 (working stroke), else 0."""
    vB = np.asarray(vB, dtype=float)
    return np.where(vB > p.v_zero, -p.Fr * np.sign(vB), 0.0)


# ---------------------------------------------------------------------------
# Frictionless kinetostatics
# ---------------------------------------------------------------------------
def reactions(p: SliderCrank, phi1) -> dict:
    """Frictionless joint reactions and driving torque, solved by hand.

    Newton-Euler per body (sum of applied forces = m a_S; sum of moments
    about a point P = J alpha + (S - P) x m a_S), with F_ji = -F_ij.

    Slider 3 (forces F_B at B, N n at B, m3 g, F_res x-hat; a3 = (aB, 0)):
        x:  F_Bx + F_res + m3 gx = m3 aB       -> F_Bx
        y:  F_By + N + m3 gy = 0               -> N  (after F_By from the rod)
        moment about B: M_slide = 0 (every force passes through B).
    Rod 2 (F_A at A, -F_B at B, m2 g at S2), moments about A,
    d = B - A = b (c2, s2), q = S2 - A = r2 (c2, s2):
        d x (-F_B) + q x m2 g = J2 alpha2 + q x m2 a_S2
        b (s2 F_Bx - c2 F_By) = J2 alpha2 + m2 r2 [c2 (a2y - gy) - s2 (a2x - gx)]
                                                        -> F_By
        forces: F_A - F_B + m2 g = m2 a_S2     -> F_A = F_B + m2 (a_S2 - g)
    Crank 1 (F_O at O, -F_A at A, m1 g at S1, M1), forces and moments about O:
        F_O - F_A + m1 g = m1 a_S1             -> F_O = F_A + m1 (a_S1 - g)
        M1 + A x (-F_A) + S1 x m1 g = J1 alpha1 + S1 x m1 a_S1
        M1 = J1 alpha1 + m1 r1 [c1 (a1y - gy) - s1 (a1x - gx)]
             + a (c1 F_Ay - s1 F_Ax)

    Keys: F_Ox, F_Oy, F_Ax, F_Ay, F_Bx, F_By (components), F_O, F_A, F_B
    (stacked, shape (..., 2)), N, M_slide, M1, F_res (the resistance along x
    actually applied).
    """
    k = kinematics(p, phi1)
    gx, gy = float(p.g[0]), float(p.g[1])
    c1, s1 = np.cos(k["phi1"]), np.sin(k["phi1"])
    c2, s2 = np.cos(k["phi2"]), np.sin(k["phi2"])
    a, b, r1, r2 = p.a, p.b, p.r1, p.r2
    m1, m2, m3 = p.m1, p.m2, p.m3

    F_res = _resistance(p, k["vB"])

    # slider, x equation
    F_Bx = m3 * k["aB"] - m3 * gx - F_res
    # rod, moments about A
    rhs = p.J2 * k["alpha2"] + m2 * r2 * (c2 * (k["S2_ay"] - gy) - s2 * (k["S2_ax"] - gx))
    F_By = (b * s2 * F_Bx - rhs) / (b * c2)
    # slider, y equation (a3y = 0) and moment about B
    N = -F_By - m3 * gy
    M_slide = np.zeros_like(N)
    # rod, force equations
    F_Ax = F_Bx + m2 * (k["S2_ax"] - gx)
    F_Ay = F_By + m2 * (k["S2_ay"] - gy)
    # crank, force equations
    F_Ox = F_Ax + m1 * (k["S1_ax"] - gx)
    F_Oy = F_Ay + m1 * (k["S1_ay"] - gy)
    # crank, moments about O
    M1 = (
        p.J1 * k["alpha1"]
        + m1 * r1 * (c1 * (k["S1_ay"] - gy) - s1 * (k["S1_ax"] - gx))
        + a * (c1 * F_Ay - s1 * F_Ax)
    )

    return {
        "F_Ox": F_Ox,
        "F_Oy": F_Oy,
        "F_Ax": F_Ax,
        "F_Ay": F_Ay,
        "F_Bx": F_Bx,
        "F_By": F_By,
        "F_O": np.stack([F_Ox, F_Oy], axis=-1),
        "F_A": np.stack([F_Ax, F_Ay], axis=-1),
        "F_B": np.stack([F_Bx, F_By], axis=-1),
        "N": N,
        "M_slide": M_slide,
        "M1": M1,
        "F_res": F_res,
    }


def power_terms(p: SliderCrank, phi1) -> dict:
    """Frictionless power balance terms (docs/theory.md).

    Keys:
      input     = M1 * omega1
      kinetic   = dT/dt = sum m v_S . a_S + J omega alpha
      potential = dV/dt = -sum m g . v_S
      external  = P_ext = -(F_res * vB)   (>= 0 when it resists)
      residual  = input - (kinetic + potential + external)
    """
    k = kinematics(p, phi1)
    r = reactions(p, phi1)
    gx, gy = float(p.g[0]), float(p.g[1])
    kinetic = (
        p.m1 * (k["S1_vx"] * k["S1_ax"] + k["S1_vy"] * k["S1_ay"])
        + p.J1 * k["omega1"] * k["alpha1"]
        + p.m2 * (k["S2_vx"] * k["S2_ax"] + k["S2_vy"] * k["S2_ay"])
        + p.J2 * k["omega2"] * k["alpha2"]
        + p.m3 * k["vB"] * k["aB"]
    )
    potential = -(
        p.m1 * (gx * k["S1_vx"] + gy * k["S1_vy"])
        + p.m2 * (gx * k["S2_vx"] + gy * k["S2_vy"])
        + p.m3 * (gx * k["vB"] + gy * 0.0)
    )
    external = -(r["F_res"] * k["vB"])
    inp = r["M1"] * k["omega1"]
    return {
        "input": inp,
        "kinetic": kinetic,
        "potential": potential,
        "external": external,
        "residual": inp - (kinetic + potential + external),
    }


# ---------------------------------------------------------------------------
# Approximate friction (the source's method)
# ---------------------------------------------------------------------------
def friction_terms(p: SliderCrank, phi1) -> dict:
    """Friction loads from the FRICTIONLESS reactions and their powers.

    Keys: Mf_O, Mf_A, Mf_B (= rho * |F| at each revolute), Ff_slide
    (= f * |N|), P_O, P_A, P_B, P_slide (= |load * relative speed|, zero
    where the relative speed is zero by the rule of docs/conventions.md), P_fric (sum).
    """
    r = reactions(p, phi1)
    w = relative_speeds(p, phi1)
    Mf_O = p.rho_O * np.hypot(r["F_Ox"], r["F_Oy"])
    Mf_A = p.rho_A * np.hypot(r["F_Ax"], r["F_Ay"])
    Mf_B = p.rho_B * np.hypot(r["F_Bx"], r["F_By"])
    Ff = p.f * np.abs(r["N"])

    def pw(load, rel, tol):
        return np.where(np.abs(rel) > tol, np.abs(load * rel), 0.0)

    P_O = pw(Mf_O, w["O"], p.w_zero)
    P_A = pw(Mf_A, w["A"], p.w_zero)
    P_B = pw(Mf_B, w["B"], p.w_zero)
    P_s = pw(Ff, w["slide"], p.v_zero)
    return {
        "Mf_O": Mf_O,
        "Mf_A": Mf_A,
        "Mf_B": Mf_B,
        "Ff_slide": Ff,
        "P_O": P_O,
        "P_A": P_A,
        "P_B": P_B,
        "P_slide": P_s,
        "P_fric": P_O + P_A + P_B + P_s,
    }


def friction_approx_torque_eq9(p: SliderCrank, phi1) -> np.ndarray:
    """Driving torque with friction M1' by the source's eq. (9).

    M1' omega1 = sum|F_f v_rel| + sum|M_f w_rel| + dV/dt + |F_r v| + dT/dt,
    with the friction loads from the frictionless reactions (friction_terms)
    and relative speeds O: omega1, A: omega2 - omega1, B: -omega2, slide: vB.
    """
    if p.omega1 == 0.0:
        raise ValueError("eq. 9 needs omega1 != 0")
    k = kinematics(p, phi1)
    pt = power_terms(p, phi1)
    fr = friction_terms(p, phi1)
    P_res = np.abs(_resistance(p, k["vB"]) * k["vB"])  # |F_r v|
    return (fr["P_fric"] + pt["potential"] + P_res + pt["kinetic"]) / p.omega1


# ---------------------------------------------------------------------------
# Self-check (independent means): python tests/oracles/slider_crank_closed_form.py
# ---------------------------------------------------------------------------
def _rel(x, ref):
    x, ref = np.asarray(x), np.asarray(ref)
    return float(np.max(np.abs(x - ref)) / max(np.max(np.abs(ref)), 1e-300))


def _self_check() -> dict:
    out = {}
    phi = np.radians(np.arange(360.0))
    base = SliderCrank()
    variants = {
        "default": base,
        "no_resistance": replace(base, Fr=0.0),
        "no_gravity": replace(base, g=(0.0, 0.0)),
        "bare": replace(base, Fr=0.0, g=(0.0, 0.0)),
        "cw_tilted_g": replace(base, omega1=-base.omega1, g=(3.0, -8.0), e=0.03),
    }
    for name, p in variants.items():
        # (1) finite differences over phi1 (d/dt = omega1 d/dphi1)
        h = 1e-5
        kp, km, k = kinematics(p, phi + h), kinematics(p, phi - h), kinematics(p, phi)
        d = lambda key, kp=kp, km=km, h=h, p=p: (kp[key] - km[key]) / (2 * h) * p.omega1  # noqa: E731
        fd = max(
            _rel(d("phi2"), k["omega2"]),
            _rel(d("omega2"), k["alpha2"]),
            _rel(d("xB"), k["vB"]),
            _rel(d("vB"), k["aB"]),
            *(_rel(d(f"{P}_{c}"), k[f"{P}_v{c}"]) for P in ("A", "S1", "S2") for c in "xy"),
            *(_rel(d(f"{P}_v{c}"), k[f"{P}_a{c}"]) for P in ("A", "S1", "S2") for c in "xy"),
        )
        # (2) power balance
        pt = power_terms(p, phi)
        big = max(np.max(np.abs(pt[t])) for t in ("input", "kinetic", "potential", "external"))
        pb = float(np.max(np.abs(pt["residual"])) / big)
        # (4) eq. 9 with no friction
        p0 = replace(p, rho_O=0.0, rho_A=0.0, rho_B=0.0, f=0.0)
        e9 = _rel(friction_approx_torque_eq9(p0, phi), reactions(p0, phi)["M1"])
        out[name] = {"fd": fd, "power": pb, "eq9_nofric": e9}
    return out


if __name__ == "__main__":
    res = _self_check()
    ok = True
    for name, r in res.items():
        good = r["fd"] < 1e-6 and r["power"] < 1e-10 and r["eq9_nofric"] < 1e-12
        ok &= good
        print(
            f"{name:15s} fd={r['fd']:.2e} power={r['power']:.2e} "
            f"eq9(no friction)={r['eq9_nofric']:.2e} {'ok' if good else 'FAIL'}"
        )
    p = SliderCrank()
    phi = np.radians(np.arange(360.0))
    M1 = reactions(p, phi)["M1"]
    M1f = friction_approx_torque_eq9(p, phi)
    print(
        f"default: M1 in [{M1.min():.3f}, {M1.max():.3f}] N m, "
        f"M1' - M1 in [{(M1f - M1).min():.4f}, {(M1f - M1).max():.4f}] N m"
    )
    raise SystemExit(0 if ok else 1)
