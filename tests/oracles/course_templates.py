"""Closed forms for the course-design templates (src/kinetostatics/templates/*.yaml).

Written independently of the program, with points and vectors of the plane as complex
numbers z = x + iy:

- positions by the loop-closure equations solved by hand: the crank, the guide bar
  through a fixed pivot carrying the crank's block (the crank–guide-bar inversion, an
  RPR group), the dyad of two revolutes (RRR: two circles meet) and the dyad with a
  slider on a fixed line (RRP: a circle meets a line);
- velocities and accelerations by differentiating each loop equation in time
  analytically (the complex-number vector loop): each gives two real linear equations
  in the two unknown rates, solved by Cramer's rule;
- frictionless reactions from the Newton–Euler equations of each Assur group: for each
  body ΣF = m·a_S and ΣM_S = J·α, the joint forces named as the program names them
  (docs/conventions.md: a joint [i, j] gives the force of i on j; a prismatic pair the
  force N of i on j along the axis turned +90° and the couple M of i on j), solved
  group by group from the last group to the driving link.

The saw template is a slider-crank: its closed form is tests/oracles/slider_crank_closed_form.py.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np


def cross(u, v):
    """The z-component of u × v for plane vectors as complex numbers."""
    return (np.conj(u) * v).imag


def solve2(c1, c2, r):
    """The real x1, x2 with x1·c1 + x2·c2 = r (Cramer's rule on the plane vectors)."""
    det = cross(c1, c2)
    return cross(r, c2) / det, cross(c1, r) / det


@dataclass(frozen=True)
class Motion:
    """A point's position, velocity and acceleration (complex)."""

    z: complex
    v: complex = 0j
    a: complex = 0j


def on_link(ref: Motion, omega: float, alpha: float, offset: complex) -> Motion:
    """The point ``ref.z + offset`` of a link turning at ω, α:
    v = v_ref + iω·offset, a = a_ref + (iα − ω²)·offset."""
    return Motion(
        ref.z + offset, ref.v + 1j * omega * offset, ref.a + (1j * alpha - omega**2) * offset
    )


def crank(pivot: complex, r: float, phi: float, omega: float) -> Motion:
    """The crank pin at angle φ on a crank turning at constant ω about a fixed pivot."""
    return on_link(Motion(pivot), omega, 0.0, r * np.exp(1j * phi))


@dataclass(frozen=True)
class Bar:
    """A bar turning about a fixed pivot P with a block sliding on it at A:
    A − P = s·e^{iθ}; θ, ω, α of the direction P → A; s, ṡ, s̈ the block's place."""

    theta: float
    omega: float
    alpha: float
    s: float
    sd: float
    sdd: float


def guide_bar(pivot: complex, block: Motion) -> Bar:
    """The crank–guide-bar inversion: θ = arg(A − P), s = |A − P|; from
    v_A = (ṡ + i·s·ω)·e^{iθ} and a_A = (s̈ − s·ω² + i·(s·α + 2·ṡ·ω))·e^{iθ}."""
    d = block.z - pivot
    s = abs(d)
    e = d / s
    v = block.v * np.conj(e)
    a = block.a * np.conj(e)
    sd, omega = v.real, v.imag / s
    sdd, alpha = a.real + s * omega**2, (a.imag - 2 * sd * omega) / s
    return Bar(float(np.angle(d)), omega, alpha, s, sd, sdd)


@dataclass(frozen=True)
class Dyad:
    """An RRP or RRR group solved: the inner joint C, the first link's angle (of
    C − B) and rates, and for an RRR the second link's (of C − D)."""

    C: Motion
    phi1: float
    omega1: float
    alpha1: float
    phi2: float = 0.0
    omega2: float = 0.0
    alpha2: float = 0.0


def rrp(B: Motion, length: float, origin: complex, u: complex, branch: int) -> Dyad:
    """C = origin + x·u on a fixed line (u a unit complex) with |C − B| = L:
    x = d∥ + branch·√(L² − d⊥²), d = (B − origin)·ū.  Differentiating C − B = L·e^{iφ}:
    ẋ·u − iLφ̇·e^{iφ} = v_B and ẍ·u − iLφ̈·e^{iφ} = a_B − Lφ̇²·e^{iφ}."""
    d = (B.z - origin) * np.conj(u)
    x = d.real + branch * np.sqrt(length**2 - d.imag**2)
    C = origin + x * u
    e = (C - B.z) / length
    xd, w = solve2(u, -1j * length * e, B.v)
    xdd, al = solve2(u, -1j * length * e, B.a - length * w**2 * e)
    return Dyad(Motion(C, xd * u, xdd * u), float(np.angle(e)), w, al)


def rrr(B: Motion, l1: float, D: Motion, l2: float, branch: int) -> Dyad:
    """C with |C − B| = l1 and |C − D| = l2 (two circles): along B → D at
    (l1² − l2² + |D − B|²)/(2|D − B|), branch·h across (+: to the left of B → D).
    Differentiating C − B = l1·e^{iφ1} and C − D = l2·e^{iφ2}:
    i(C − B)ω1 − i(C − D)ω2 = v_D − v_B,
    i(C − B)α1 − i(C − D)α2 = a_D − a_B + ω1²(C − B) − ω2²(C − D)."""
    d = D.z - B.z
    dist = abs(d)
    along = (l1**2 - l2**2 + dist**2) / (2 * dist)
    C = B.z + (along + 1j * branch * np.sqrt(l1**2 - along**2)) * d / dist
    r1, r2 = C - B.z, C - D.z
    w1, w2 = solve2(1j * r1, -1j * r2, D.v - B.v)
    a1, a2 = solve2(1j * r1, -1j * r2, D.a - B.a + w1**2 * r1 - w2**2 * r2)
    vC, aC = B.v + 1j * w1 * r1, B.a + (1j * a1 - w1**2) * r1
    return Dyad(Motion(C, vC, aC), float(np.angle(r1)), w1, a1, float(np.angle(r2)), w2, a2)


# -- Newton–Euler of one Assur group ------------------------------------------------------
@dataclass
class Body:
    """One link of a group: mass m at S (acceleration a_S), J about S, angular
    acceleration α, and the known forces (F, at) and couples acting on it."""

    m: float = 0.0
    J: float = 0.0
    S: complex = 0j
    aS: complex = 0j
    alpha: float = 0.0
    forces: list = None
    couples: list = None

    def __post_init__(self):
        self.forces = list(self.forces or [])
        self.couples = list(self.couples or [])


@dataclass(frozen=True)
class Unknown:
    """A joint's unknown effort: ``pin`` (a force Fx + iFy at ``at``), ``normal`` (a
    force N·``direction`` at ``at``) or ``couple`` (M).  ``on``: the bodies of the group
    it acts on with its sign (+1 on j, −1 on i for the effort of i on j)."""

    name: str
    kind: str
    on: tuple
    at: complex = 0j
    direction: complex = 1 + 0j


def solve_group(bodies: dict, unknowns: list[Unknown]) -> dict:
    """ΣF = m·a_S (x, y) and ΣM_S = J·α for every body of the group, the unknown joint
    efforts as the columns: one linear solve.  Returns ``{name: value}``, a pin as the
    complex force Fx + iFy."""
    names = list(bodies)
    cols = []  # (unknown, component)
    for u in unknowns:
        cols += [(u, 1.0 + 0j), (u, 1j)] if u.kind == "pin" else [(u, None)]
    n = 3 * len(names)
    if len(cols) != n:
        raise ValueError(f"{len(cols)} unknowns for {n} equations")
    mat = np.zeros((n, n))
    rhs = np.zeros(n)
    for b, name in enumerate(names):
        body = bodies[name]
        # known terms: Σ F_known − m a_S = −(unknown part); moments about S
        f = sum((F for F, _ in body.forces), 0j) - body.m * body.aS
        mom = sum(cross(at - body.S, F) for F, at in body.forces) + sum(body.couples)
        mom -= body.J * body.alpha
        rhs[3 * b : 3 * b + 3] = [-f.real, -f.imag, -mom]
        for k, (u, comp) in enumerate(cols):
            sign = dict(u.on).get(name, 0.0)
            if not sign:
                continue
            if u.kind == "couple":
                mat[3 * b + 2, k] += sign
                continue
            F = sign * (comp if u.kind == "pin" else u.direction)
            mat[3 * b, k] += F.real
            mat[3 * b + 1, k] += F.imag
            mat[3 * b + 2, k] += cross(u.at - body.S, F)
    x = np.linalg.solve(mat, rhs)
    out, k = {}, 0
    for u in unknowns:
        if u.kind == "pin":
            out[u.name] = x[k] + 1j * x[k + 1]
            k += 2
        else:
            out[u.name] = x[k]
            k += 1
    return out
