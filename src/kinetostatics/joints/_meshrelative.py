r"""The relative motion of a toothed pair's links at its pitch point P (``gear.py``'s and
``rack.py``'s ``relative_motion``): the textbook's terms of a vector equation.

While the centre distance is held (the pinion's height over the rack's pitch line), the
two links' points at P have one velocity and their relative acceleration is the normal
term of rolling, along the line of centres towards the centre of link j:

    gear pair   a_PjPi = (ω_j − ω_i)² r_i r_j / d₀         (d₀ = r_i ± r_j)
    rack        a_PjPi = (ω_j − ω_i)² r                     (r the pinion's pitch radius)

(for gears on the frame: ω_i² r_i + ω_j² r_j, each gear's own normal acceleration at P).
Where the distance changes, the pair's row (``gear.py``, ``rack.py``) still fixes the
component of the relative motion along the line of action, and the rest is written too:
a relative velocity ḋ w and acceleration d̈ w along w ⊥ the line of action, and the
known terms of the changing distance (2ḋβ̇ for the gears, 2ω_i ḣ for the rack's turning
frame).  With d = |D| (D = C_j − C_i), e = D/d, t = perp(e), β̇ = t·Ḋ/d, ḋ = e·Ḋ and
μ = ρ/d₀ of the signed radii (``gear.py``), the material points at P = C_i + μ_i D give

    v_Pj − v_Pi = ḋ w,                       w = e − (k d / (κ cos α d₀)) t
    a_Pj − a_Pi = d̈ w + 2ḋβ̇ t + d (μ_i ω_i² − μ_j ω_j² − β̇²) e,

the last term being −μ_i μ_j d (ω_j − ω_i)² e when ḋ = 0.  For the rack, with s = U·D and
h = N·D in the rack's frame (D = C_j − A_i), the point P = C_j − ν r N gives

    v_Pj − v_Pi = ḣ w,                       w = N − (ν sin α / (κ ν cos α)) U
    a_Pj − a_Pi = ḧ w + 2 ω_i ḣ perp(w) + ν r (ω_j − ω_i)² N.

Terms smaller than :data:`HELD` of their scale are left out (a held distance).
"""

from __future__ import annotations

import numpy as np

from ..base.geometry import dot, perp
from .relative import RelativeMotion, RelativeTerm

__all__ = ["HELD", "gear_motion", "rack_motion"]

HELD = 1e-13  # a distance's rate below this times its scale: held (its terms left out)


def _points(q, v, a, R):
    """(velocity, acceleration) of the point at R (global offset from the centre of mass)."""
    w = float(v[2])
    return v[:2] + w * perp(R), a[:2] + float(a[2]) * perp(R) - w * w * R


def _changing(rate, second, w, coriolis, names) -> tuple[tuple, tuple]:
    """The terms of a changing distance: (velocity terms, acceleration terms)."""
    rel, direction = names
    velocity = (RelativeTerm(f"v_{rel}", rate * w, "⊥ the line of action"),)
    acceleration = (
        RelativeTerm(f"a^r_{rel}", second * w, "⊥ the line of action"),
        RelativeTerm(f"a^k_{rel}", coriolis, direction, "known", rate=False),
    )
    return velocity, acceleration


def gear_motion(gear, qi, qj, vi, vj, ai, aj, labels) -> RelativeMotion:
    """The gear pair's terms at its pitch point (module docstring)."""
    li, lj = labels
    Ri, Rj, D, d, e, t = gear._frame(qi, qj)
    d = float(d)
    rho_i, rho_j = gear.signed_radii
    d0 = gear.d0
    mi, mj = rho_i / d0, rho_j / d0
    K_i, K_j, k = gear._coefficients()
    c = K_j / rho_j  # κ cos α
    wi, wj = float(vi[2]), float(vj[2])
    vci, aci = _points(qi, vi, ai, Ri)
    vcj, acj = _points(qj, vj, aj, Rj)
    Dd, Ddd = vcj - vci, acj - aci
    d_d, beta_d = float(dot(e, Dd)), float(dot(t, Dd)) / d
    d_dd = float(dot(e, Ddd)) + d * beta_d**2
    point = qi[:2] + Ri + mi * D
    oi, oj = gear.centre_names
    n, rel = gear.name, f"{gear.name}{lj}{gear.name}{li}"
    normal = d * (mi * wi**2 - mj * wj**2 - beta_d**2) * e
    scale_v = (abs(wi) + abs(wj)) * d0 + float(np.hypot(*Dd))
    scale_a = (abs(wi) + abs(wj)) ** 2 * d0 + (abs(ai[2]) + abs(aj[2])) * d0
    held = abs(d_d) <= HELD * scale_v and abs(d_dd) <= HELD * (scale_a + float(np.hypot(*Ddd)))
    if held:
        towards = oj if float(dot(normal, e)) >= 0.0 else oi
        rolling = RelativeTerm(
            f"a^n_{rel}",
            normal,
            f"{n}→{towards}",
            f"(ω{lj}−ω{li})²·r{li}·r{lj}/l_{oi}{oj}",
            rate=False,
        )
        return RelativeMotion(point, n, turns=True, acceleration=(rolling,))
    w = e - (k * d / (c * d0)) * t
    velocity, changing = _changing(d_d, d_dd, w, 2.0 * d_d * beta_d * t, (rel, f"⊥{oi}{oj}"))
    rolling = RelativeTerm(f"a^n_{rel}", normal, f"∥{oi}{oj}", "known", rate=False)
    return RelativeMotion(point, n, True, velocity, (rolling, *changing))


def rack_motion(rack, qi, qj, vi, vj, ai, aj, labels) -> RelativeMotion:
    """The rack and pinion's terms at its pitch point (module docstring)."""
    li, lj = labels
    A, U, N, C, D, nu = rack._frame(qi, qj)
    nu = float(nu)
    kc, ks = rack._gains(nu)
    wi, wj = float(vi[2]), float(vj[2])
    vai, aai = _points(qi, vi, ai, A)
    vcj, acj = _points(qj, vj, aj, C)
    Dd, Ddd = vcj - vai, acj - aai
    h_d = float(dot(N, Dd)) - wi * float(dot(U, D))
    h_dd = (
        float(dot(N, Ddd))
        - 2.0 * wi * float(dot(U, Dd))
        - float(ai[2]) * float(dot(U, D))
        - wi**2 * float(dot(N, D))
    )
    point = qj[:2] + C - nu * rack.r * N
    n, oj = rack.name, rack.centre_name
    rel = f"{n}{lj}{n}{li}"
    normal = nu * rack.r * (wj - wi) ** 2 * N
    scale_v = (abs(wi) + abs(wj)) * rack.r + float(np.hypot(*Dd))
    scale_a = (abs(wi) + abs(wj)) ** 2 * rack.r + (abs(ai[2]) + abs(aj[2])) * rack.r
    held = abs(h_d) <= HELD * scale_v and abs(h_dd) <= HELD * (scale_a + float(np.hypot(*Ddd)))
    rolling = RelativeTerm(
        f"a^n_{rel}",
        normal,
        f"{n}→{oj}" if held else "known",
        f"(ω{lj}−ω{li})²·r{lj}" if held else "known",
        rate=False,
    )
    if held:
        return RelativeMotion(point, n, turns=True, acceleration=(rolling,))
    w = N - (ks / kc) * U
    coriolis = 2.0 * wi * h_d * perp(w)
    velocity, changing = _changing(h_d, h_dd, w, coriolis, (rel, "∥ the line of action"))
    return RelativeMotion(point, n, True, velocity, (rolling, *changing))
