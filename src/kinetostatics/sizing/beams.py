"""Axial force, shear force and bending moment along a link's axis: a beam loaded by
point forces and couples and, for a uniform link, the linearly distributed inertia and
weight (docs/sizing.md, "Links").

The beam runs from the link's first pin (station s = 0) to its second (s = L), along
the unit vector e, with n = e turned +90°.  Every load is given in these axes:
a point force (f_e, f_n) at (x, y), a couple C at station x, and for a uniform link the
load per unit length

    w(x) = (m/L)·[(u_e + ω²·x)·e + (u_n − α·x)·n],   u = g − a(0),

the d'Alembert load −(m/L)·a(x) of the rigid body's acceleration a(x) = a(0) + α·x·n −
ω²·x·e, plus its weight.  At a station s the loads of the part [0, s] sum to R(s) with a
moment M_L(s) about the section's centre (s, 0); the part beyond s acts on it with

    N(s) = −R(s)·e  (tension positive),  V(s) = −R(s)·n,  M(s) = −M_L(s)  (CCW positive).

Loads at s = 0 belong to the part [0, s] from s = 0 on; the loads at the far pin never do
(they are the support of the part beyond): so N(0) = −F₀·e, N(L) = F₁·e, and M(L) = 0
where the link is in equilibrium.  The distributed load's resultants are its integrals in
closed form:

    ∫₀ˢ w = (m/L)·[(u_e·s + ω²s²/2)·e + (u_n·s − α·s²/2)·n],
    ∫₀ˢ (x − s)·w_n dx = (m/L)·(−u_n·s²/2 + α·s³/6).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

__all__ = ["BeamLoads", "beam_forces"]


@dataclass(frozen=True, eq=False)
class BeamLoads:
    """The loads on one link in its beam axes, at ``n`` positions.

    ``length`` L (m); ``points``: ((x, y, force (n, 2) as (f_e, f_n), far), …) with
    ``far`` True for the loads at the far pin; ``couples``: ((x, couple (n,)), …);
    ``distributed``: None, or (m/L, u (n, 2), α (n,), ω² (n,)) of a uniform link."""

    length: float
    points: tuple
    couples: tuple
    distributed: tuple | None = None


def beam_forces(loads: BeamLoads, stations: np.ndarray):
    """(N, V, M), each ``(n, len(stations))``: the internal forces at ``stations`` (m from
    the first pin)."""
    s = np.asarray(stations, float)[None, :]
    n_rows = _rows(loads)
    re = np.zeros((n_rows, s.shape[1]))
    rn = np.zeros_like(re)
    ml = np.zeros_like(re)
    tol = 1e-9 * loads.length
    for x, y, f, far in loads.points:
        if far:
            continue
        on = (x <= s + tol).astype(float)
        fe, fn = f[:, 0:1], f[:, 1:2]
        re += on * fe
        rn += on * fn
        ml += on * ((x - s) * fn - y * fe)
    for x, c in loads.couples:
        if x >= loads.length - tol:
            continue
        ml += (x <= s + tol).astype(float) * c[:, None]
    if loads.distributed is not None:
        q, u, alpha, w2 = loads.distributed
        re += q * (u[:, 0:1] * s + w2[:, None] * s**2 / 2)
        rn += q * (u[:, 1:2] * s - alpha[:, None] * s**2 / 2)
        ml += q * (-u[:, 1:2] * s**2 / 2 + alpha[:, None] * s**3 / 6)
    return -re, -rn, -ml


def _rows(loads: BeamLoads) -> int:
    for _, _, f, _ in loads.points:
        return len(f)
    for _, c in loads.couples:
        return len(c)
    return len(loads.distributed[1]) if loads.distributed is not None else 1
