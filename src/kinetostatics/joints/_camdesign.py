r"""The design chart of a ``cam`` pair (``cam.py``'s ``profile_design``): what a course design
computes of a cam besides its motion, as closed forms of the cam angle θ.

* the law s(θ) and its θ-derivatives s′ = ds/dθ, s″ = d²s/dθ² (per unit cam speed: at a
  constant speed ω the follower's velocity and acceleration are ω s′ and ω² s″);
* the pressure angle α(θ; r_b) at any base radius r_b, from the follower's placement alone
  (no profile tables): with F the follower point in the frame (knife tip, roller centre)
  and F′ its θ-derivative, the pitch curve's tangent turned into the frame is
  t = F′ − iσF and its outward normal n = −τ i t (τ = ±1 the sense the pitch point turns
  round the cam centre in the cam's frame); a flat face's normal is N at its contact point
  X = hN + h′T.  The follower point moves along m = u (translating) or m = κ i (X − A)
  (oscillating about A), and α = σ arg(n / m): the angle from m to n, positive in the cam's
  sense of rotation, the same convention as the pair's ``pressure_angle`` column
  (``cam.py``).  For a translating knife or roller this is
  tan α = (s′ − e)/(√(r_p² − e²) + s), r_p = r_b + r_r;
* the radius of curvature of the pitch curve (the roller centre's path; the profile
  itself for a knife edge or a flat face), > 0 where convex;
* where a closed form exists, the base radius that keeps |α(θ)| ≤ [α] at each θ: for a
  translating knife or roller, √(r_p² − e²) ≥ |s′ − e|/tan[α] − s gives
  r_b(θ) = √(max(|s′ − e|/tan[α] − s, 0)² + e²) − r_r, whose largest value over θ is the
  least base radius (the textbook's r_0,min = max √((|s′ ∓ e|/tan[α] − s)² + e²), with the
  bracket held at 0 where it is negative: there any prime radius above |e| serves).
  Other followers have none: the caller bisects on r_b with α(θ; r_b)
  (:meth:`ProfileDesign.base_range` bounds the base radii that place the follower).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, fields

import numpy as np

from ._camprofile import Synthesis

__all__ = ["ProfileDesign"]


@dataclass(frozen=True)
class _Placed(Synthesis):
    """A synthesis at another base radius, placed (β₀, the sense the pitch point turns)
    but without the inversion tables and the outline, which the design does not read."""

    def __post_init__(self):
        if self.pivot is not None:
            object.__setattr__(self, "_beta0", self._placement())
        if not self.placement_problem():
            object.__setattr__(self, "turn", self._turn())


@dataclass(frozen=True)
class ProfileDesign:
    """The design chart of one cam pair, from its synthesis (SI, angles in rad);
    ``allowed`` the file's allowable pressure angle [α] (rad; None: not given)."""

    synthesis: Synthesis
    allowed: float | None = None

    @property
    def follower(self) -> str:
        """knife, roller or flat."""
        return self.synthesis.follower

    @property
    def motion(self) -> str:
        """translating or oscillating."""
        return "translating" if self.synthesis.pivot is None else "oscillating"

    @property
    def lift_units(self) -> tuple[str, str, str]:
        """The units of s, s′, s″: a length (translating) or an angle (oscillating)."""
        if self.synthesis.pivot is None:
            return ("m", "m/rad", "m/rad^2")
        return ("rad", "1", "1/rad")

    @property
    def base(self) -> float:
        """The file's base radius r_b (the working profile's base circle)."""
        return self.synthesis.base

    @property
    def roller(self) -> float:
        """The roller radius r_r (0 for a knife edge or a flat face)."""
        return self.synthesis.radius

    @property
    def grid(self) -> np.ndarray:
        """Cam angles that sample every segment of the law (its ends among them)."""
        return self.synthesis.check_grid

    def curves(self) -> tuple[np.ndarray | None, np.ndarray]:
        """(the pitch curve, the working profile), each ``(360, 2)`` in the cam's frame (m)
        at the cam angles 0°, 1°, …, 359°: the outline the pictures draw.  A knife's pitch
        curve is its profile; a flat face has no pitch curve (None)."""
        out = self.synthesis.outline
        if self.synthesis.flat:
            return None, out[0]
        return (out[1], out[0]) if len(out) == 2 else (out[0], out[0])

    def law(self, theta) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """(s, s′, s″) at cam angles θ."""
        s = self.synthesis.law.value(theta)
        return s[0], s[1], s[2]

    def placed(self, base: float) -> Synthesis | None:
        """The synthesis at base radius ``base`` (None where the follower cannot be placed)."""
        if base == self.synthesis.base:
            return self.synthesis
        values = {f.name: getattr(self.synthesis, f.name) for f in fields(Synthesis) if f.init}
        syn = _Placed(**{**values, "base": float(base)})
        return None if syn.placement_problem() else syn

    def pressure_angle(self, theta, base: float | None = None) -> np.ndarray:
        """α(θ) (rad) at base radius ``base`` (None: the file's); NaN where the follower
        cannot be placed at that base radius."""
        th = np.asarray(theta, float)
        syn = self.placed(self.synthesis.base if base is None else base)
        if syn is None:
            return np.full(th.shape, math.nan)
        rot = np.exp(1j * syn.sigma * th)  # the cam's frame -> the frame
        if syn.flat:
            nu, nu1, _, h, h1, _ = syn.support(th)
            N = np.exp(1j * nu)
            X = (h + 1j * h1 / nu1) * N * rot
            n = N * rot
        else:
            F, F1 = syn.frame_point(th, first=True)
            X = F
            n = -syn.turn * 1j * (F1 - 1j * syn.sigma * F)
        if syn.pivot is None:
            m = complex(*syn.direction)
        else:
            m = syn.kappa * 1j * (X - complex(*syn.pivot))
        return syn.sigma * np.angle(n * np.conj(m))

    def pitch_radius(self, theta) -> np.ndarray:
        """The radius of curvature (m) of the pitch curve (the roller centre's path; the
        profile for a knife edge or a flat face) at cam angles θ: > 0 convex, < 0 concave."""
        return self.synthesis.curvature(theta) + self.synthesis.radius

    def least_base(self, theta, pressure_angle_max: float) -> np.ndarray | None:
        """The least base radius that keeps |α| ≤ ``pressure_angle_max`` (rad) at each θ,
        in closed form (a translating knife or roller); None for the other followers."""
        syn = self.synthesis
        if syn.pivot is not None or syn.flat:
            return None
        s, s1, _ = self.law(theta)
        d = np.maximum(np.abs(s1 - syn.offset) / math.tan(pressure_angle_max) - s, 0.0)
        return np.sqrt(d * d + syn.offset**2) - syn.radius

    def base_range(self) -> tuple[float, float] | None:
        """(lo, hi): the base radii between which the follower can be placed, or None where
        the pressure angle does not depend on the base radius (a translating flat face,
        α ≡ 0).  lo is 0 or where the placement begins; hi may be ``inf``."""
        syn = self.synthesis
        if syn.pivot is None:
            return None if syn.flat else (max(abs(syn.offset) - syn.radius, 0.0), math.inf)
        a = math.hypot(*syn.pivot)
        if syn.flat:
            return max(-a - syn.offset, 0.0), a - syn.offset
        return max(abs(a - syn.arm) - syn.radius, 0.0), a + syn.arm - syn.radius
