r"""The profile of a ``cam`` pair synthesised from its follower law (``cam.py`` uses it).

Frame and cam angle
-------------------
The *frame* is the link that carries the cam's axis and the follower's guide or
pivot (usually the ground).  The cam angle θ is the cam's rotation relative to the
frame in its sense of rotation σ (``rotation: ccw`` σ = +1, ``cw`` σ = −1), zero
when the cam link's own axes are parallel to the frame's.  The follower's
geometry is given in the frame, relative to the cam centre O:

* translating: the guide direction u (the direction of rise) and the offset e:
  the follower's line passes at e·w from O, w = −σ·perp(u) (the side where the
  cam's surface moves along u); prime radius r_p = r_b + r_roller, and the
  follower point (knife tip, roller centre) is F(θ) = e w + (√(r_p² − e²) + s) u;
* oscillating: the arm's pivot A and length L; the follower point is
  F = A + L(cos β, sin β) with β = β₀ + κ s (κ = +1: ``rise: ccw``), β₀ the
  angle at which F lies on the prime circle, on the side where the rise moves it
  outwards;
* flat-faced: the face's outward normal N (from the cam to the follower) and its
  distance from O, the support value h: translating N = u, h = r_b + s;
  oscillating N = (cos β, sin β), β = β₀ + κ s, h = N·A − f (the face at f from
  the pivot towards the cam; β₀ gives h = r_b at s = 0).

In the cam's frame (rotated by −σθ) the follower point is P(θ) = Q(θ) F(θ),
Q = exp(−iσθ) as complex numbers, so P' = Q(F' − iσF), P'' = Q(F'' − 2iσF' − F),
P''' = Q(F''' − 3iσF'' − 3F' + iσF).  Its polar angle ψ and log-radius ln R are
the imaginary and real parts of log P, whose derivatives are w₁ = P'/P,
w₂ = P''/P − w₁², w₃ = P'''/P − 3(P''/P)w₁ + 2w₁³.  A flat face's normal angle
in the cam's frame is ν = β_N − σθ.
"""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass, field

import numpy as np

from ..base.geometry import perp
from ._camlaw import CamLaw

__all__ = ["Synthesis"]

GRID = 2048  # cam angles of the inversion table and the quadrature knots
SUBGRID = 64  # and within each segment of the law
GAUSS = np.polynomial.legendre.leggauss(8)
NEWTON = 6  # Newton steps of the inversion


def _wrap(a):
    return (a + math.pi) % (2.0 * math.pi) - math.pi


def _stacked(x) -> bool:
    """Whether ``x`` holds variants on an axis (arrays where numbers were: a model stacked
    by ``model/stacking.py``), whose profile only the per-variant analysis makes."""
    if dataclasses.is_dataclass(x):
        return any(_stacked(getattr(x, f.name)) for f in dataclasses.fields(x) if f.compare)
    if isinstance(x, (tuple, list)):
        return any(_stacked(v) for v in x)
    return np.ndim(x) > 0


@dataclass(frozen=True)
class Synthesis:
    """The follower's placement in the frame (see the module docstring), SI."""

    law: CamLaw
    follower: str  # knife, roller, flat
    radius: float  # roller radius (0 otherwise)
    base: float  # base circle radius r_b
    sigma: int  # +1: the cam turns ccw for increasing θ
    direction: tuple[float, float] | None  # translating: u
    offset: float  # translating: e; flat oscillating: f
    pivot: tuple[float, float] | None  # oscillating: A
    arm: float  # oscillating point follower: L
    kappa: int  # oscillating: +1 the rise turns the arm ccw
    # from the fields above, once (__post_init__): β₀ (or why there is none), the sense
    # in which the pitch point turns, the inversion tables (or why there are none), the
    # outline drawn; None where the follower cannot be placed or the fields are stacked
    _beta0: float | str | None = field(default=None, init=False, repr=False, compare=False)
    turn: float | None = field(default=None, init=False, repr=False, compare=False)
    inversion: tuple | str | None = field(default=None, init=False, repr=False, compare=False)
    outline: tuple | None = field(default=None, init=False, repr=False, compare=False)

    def __post_init__(self):
        if _stacked(self):
            return
        if self.pivot is not None:
            object.__setattr__(self, "_beta0", self._placement())
        if self.placement_problem():
            return
        object.__setattr__(self, "turn", self._turn())
        object.__setattr__(self, "inversion", self.tables())
        if not isinstance(self.inversion, str):
            object.__setattr__(self, "outline", self._outline())

    def placement_problem(self) -> str:
        """Why the follower cannot be placed ('' if it can)."""
        if self.pivot is not None and isinstance(self.beta0(), str):
            return self.beta0()
        if self.pivot is None and not self.flat and abs(self.offset) >= self.base + self.radius:
            return "the offset must be smaller than the prime radius (base radius + roller)"
        return ""

    @property
    def flat(self) -> bool:
        return self.follower == "flat"

    # -- the follower in the frame -------------------------------------------------
    def beta0(self) -> float | str:
        """β₀ of an oscillating follower, or a message why there is none."""
        return self._beta0

    def _placement(self) -> float | str:
        A = np.asarray(self.pivot, float)
        a, ang = math.hypot(*A), math.atan2(A[1], A[0])
        if self.flat:
            c = (self.base + self.offset) / a
            what = "the face (base radius + offset) cannot touch the base circle"
        else:
            rp = self.base + self.radius
            c = (rp * rp - a * a - self.arm**2) / (2.0 * self.arm * a)
            what = "the arm cannot reach the prime circle (base radius + roller)"
        if not abs(c) < 1.0:
            return what + " from this pivot"
        for sgn in (1.0, -1.0):
            b = ang + sgn * math.acos(c)
            # the rise (β growing with κ) moves the point outwards, or the face away:
            # d|F|²/dβ = 2L A·perp(d), dh/dβ = A·perp(N), both κ·(d × A) > 0
            if self.kappa * (math.cos(b) * A[1] - math.sin(b) * A[0]) > 0:
                return b
        return "the pivot lies on the cam centre's line of the rise"

    def frame_point(self, theta, first: bool = False):
        """F, F', F'', F''' (complex, frame) of a knife or roller follower (``first``: F, F'
        only)."""
        s = self.law.value(theta)
        if self.pivot is None:
            u = complex(*self.direction)
            rp = self.base + self.radius
            w = -self.sigma * 1j * u
            F = self.offset * w + (math.sqrt(rp * rp - self.offset**2) + s[0]) * u
            return (F, s[1] * u) if first else (F, s[1] * u, s[2] * u, s[3] * u)
        b0, k, L = self.beta0(), self.kappa, self.arm
        d = np.exp(1j * (b0 + k * s[0]))
        F = complex(*self.pivot) + L * d
        F1 = L * k * s[1] * 1j * d
        if first:
            return F, F1
        F2 = L * (k * s[2] * 1j * d - s[1] ** 2 * d)
        F3 = L * (k * s[3] * 1j * d - 3 * s[1] * s[2] * d - k * s[1] ** 3 * 1j * d)
        return F, F1, F2, F3

    def pitch(self, theta):
        """(ψ, ψ', ψ'', ψ''', ln R, (ln R)', (ln R)'', (ln R)''') over θ, and P (complex)."""
        F, F1, F2, F3 = self.frame_point(theta)
        sj = self.sigma * 1j
        Q = np.exp(-sj * np.asarray(theta, float))
        P = Q * F
        P1 = Q * (F1 - sj * F)
        P2 = Q * (F2 - 2 * sj * F1 - F)
        P3 = Q * (F3 - 3 * sj * F2 - 3 * F1 + sj * F)
        w1 = P1 / P
        w2 = P2 / P - w1 * w1
        w3 = P3 / P - 3 * (P2 / P) * w1 + 2 * w1**3
        return (np.angle(P), w1.imag, w2.imag, w3.imag, np.log(np.abs(P)), w1.real, w2.real,
                w3.real), P  # fmt: skip

    def support(self, theta):
        """(ν, ν', ν'', h, h', h'') over θ of a flat face."""
        s = self.law.value(theta)
        th = np.asarray(theta, float)
        if self.pivot is None:
            b = math.atan2(self.direction[1], self.direction[0])
            z = np.zeros(th.shape)
            return b - self.sigma * th, z - self.sigma, z, self.base + s[0], s[1], s[2]
        k, A = self.kappa, complex(*self.pivot)
        N = np.exp(1j * (self.beta0() + k * s[0]))
        NA, TA = (N.conjugate() * A).real, (N.conjugate() * A).imag  # N·A, T·A (T = iN)
        nu = np.angle(N) - self.sigma * th
        h = NA - self.offset
        return nu, k * s[1] - self.sigma, k * s[2], h, k * s[1] * TA, k * s[2] * TA - s[1] ** 2 * NA

    def angle(self, theta):
        """(a, a') over θ: the polar angle ψ of the pitch point, or the face's ν (the first
        terms of :meth:`pitch` and :meth:`support`, with their formulas)."""
        th = np.asarray(theta, float)
        if self.flat and self.pivot is None:  # ν = β_u − σθ: no lift in it
            b = math.atan2(self.direction[1], self.direction[0])
            return b - self.sigma * th, np.zeros(th.shape) - self.sigma
        if self.flat:
            s = self.law.value(th)
            N = np.exp(1j * (self.beta0() + self.kappa * s[0]))
            return np.angle(N) - self.sigma * th, self.kappa * s[1] - self.sigma
        F, F1 = self.frame_point(th, first=True)
        sj = self.sigma * 1j
        Q = np.exp(-sj * th)
        P = Q * F
        return np.angle(P), (Q * (F1 - sj * F) / P).imag

    def integrand(self, theta):
        """d/dθ of the coordinate's integral: sgn·|P'| (pitch arc), or h ν' (flat)."""
        if self.flat:
            r = self.support(theta)
            return r[3] * r[1]
        r, P = self.pitch(theta)
        return np.sign(self.turn) * np.abs(P) * np.hypot(r[1], r[5])

    def curvature(self, theta):
        """The profile's radius of curvature at cam angles θ (> 0 convex, < 0 concave,
        ±inf straight); a roller's undercut or a flat face's cusp shows as ≤ 0."""
        if self.flat:
            nu, nu1, nu2, h, h1, h2 = self.support(theta)
            hv = h1 / nu1
            return h + (h2 - hv * nu2) / nu1**2  # ρ = h + h''(ν)
        r, P = self.pitch(theta)
        a1, L1, a2, L2 = r[1], r[5], r[2], r[6]
        Lp = L1 / a1
        Lpp = (L2 - Lp * a2) / a1**2
        R = np.abs(P)
        # curvature of ρ = R(ψ): κ = (R² + 2R′² − R R″)/(R² + R′²)^{3/2}
        R1, R2 = R * Lp, R * (Lpp + Lp**2)
        kappa = (R**2 + 2 * R1**2 - R * R2) / (R**2 + R1**2) ** 1.5
        with np.errstate(divide="ignore"):
            rho = np.where(kappa != 0, 1.0 / np.where(kappa != 0, kappa, 1.0), np.inf)
        return rho - self.radius

    # -- the tables: inversion θ(a) and the cumulative integral ------------------
    def _grid(self, narrow: float) -> np.ndarray:
        b = self.law.breaks
        span = np.diff(b)
        t = np.linspace(0.0, 1.0, SUBGRID + 1)
        sub = (b[:-1, None] + span[:, None] * t)[span < narrow].ravel()
        return np.unique(np.concatenate((np.linspace(0.0, 2 * math.pi, GRID + 1), b, sub)))

    @property
    def grid(self) -> np.ndarray:
        """The table's angles: :data:`GRID` uniform ones, the law's breaks, and a segment
        narrower than 8 of their steps on its own :data:`SUBGRID` angles."""
        return self._grid(8 * 2 * math.pi / GRID)

    @property
    def check_grid(self) -> np.ndarray:
        """The angles the profile's checks sample: the uniform ones, and every segment (each
        span between the law's breaks) on its own :data:`SUBGRID` angles, so that no
        segment, however narrow, falls between the samples."""
        return self._grid(math.inf)

    def _turn(self) -> float:
        """+1 if a grows with θ, −1 if it falls."""
        a, a1 = self.angle(np.array([0.0]))
        return 1.0 if a1[0] > 0 else -1.0

    def _outline(self):
        """The profile and (roller) pitch curve over 360 cam angles, cam frame."""
        s = self
        th = np.linspace(0.0, 2 * math.pi, 361)[:-1]
        if s.flat:
            nu, nu1, _, h, h1, _ = s.support(th)
            N = np.stack((np.cos(nu), np.sin(nu)), axis=-1)
            return ((h1 / nu1)[:, None] * perp(N) + h[:, None] * N,)
        r, P = s.pitch(th)
        pitch = np.stack((P.real, P.imag), axis=-1)
        e = pitch / np.abs(P)[:, None]
        n = e - (r[5] / r[1])[:, None] * perp(e)  # e − (R′/R) t
        n /= np.hypot(n[:, 0], n[:, 1])[:, None]
        return (pitch - s.radius * n, pitch) if s.radius else (pitch,)

    def tables(self):
        """(θ_k, b_k = sgn(a − a₀) unwrapped, a₀, I_k the cumulative integral), or a message."""
        th = self.check_grid  # every segment sampled
        sg = self.turn
        bad = np.nonzero(sg * self.angle(th)[1] <= 0)[0]
        if bad.size:
            return (
                f"the {'face normal' if self.flat else 'pitch point'} does not turn one way "
                f"round the cam centre at cam angle {math.degrees(th[bad[0]]):.4g}°"
                + self.law.where(th[bad[0]], self.pivot is not None)
                + (
                    " (|ds/dθ| ≥ 1: a rise too steep for the flat face)"
                    if self.flat
                    else ": a lift too steep there (a longer `over`, a smaller lift or a "
                    "larger base circle)"
                )
            )
        th = self.grid
        a = self.angle(th)[0]
        b = sg * np.unwrap(a - a[0])
        lo, hi = th[:-1], th[1:]
        x, w = GAUSS
        mid, half = 0.5 * (lo + hi), 0.5 * (hi - lo)
        nodes = mid[:, None] + half[:, None] * x
        parts = (self.integrand(nodes.ravel()).reshape(nodes.shape) * w).sum(axis=1) * half
        return th, b, float(a[0]), np.concatenate(([0.0], np.cumsum(parts)))

    def invert(self, tables, target):
        """(θ, turns) with a(θ) = target (a ψ or ν, unwrapped), by :data:`NEWTON` steps of
        Newton from the table.  Once the steps have converged to a fixed point or a cycle
        of two (round-off) the rest are known, and not taken: the same θ to the bit."""
        th, b, a0, _ = tables
        sg = self.turn
        x = sg * (np.asarray(target, float) - a0)
        turns = np.floor(x / (2 * math.pi))
        theta = np.interp(x - 2 * math.pi * turns, b, th)
        seen = [b"", theta.tobytes()]  # the bits of θ two steps and one step back
        for k in range(NEWTON):
            a, a1 = self.angle(theta)
            last, theta = theta, theta - _wrap(a - target) / a1
            bits = theta.tobytes()
            if bits == seen[-2]:  # θ alternates with the last: the rest end on θ if even
                return (theta if (NEWTON - 1 - k) % 2 == 0 else last), turns
            if bits == seen[-1]:
                return theta, turns
            seen.append(bits)
        return theta, turns

    def integral(self, tables, theta, turns):
        """The coordinate's integral at θ, plus whole turns of it."""
        th, _, _, cum = tables
        k = np.clip(np.searchsorted(th, theta) - 1, 0, len(th) - 2)
        lo = th[k]
        x, w = GAUSS
        half = 0.5 * (theta - lo)
        nodes = (lo + half)[..., None] + half[..., None] * x
        part = (self.integrand(nodes) * w).sum(axis=-1) * half
        return turns * cum[-1] + cum[k] + part
