r"""Gear pair: two spur gears on links i and j mesh at their pitch point.

A higher pair (one row of Φ, one reaction: the tooth force).  Every symbol
below is in the code under the same name; ``docs/extending.md`` walks through
the same derivation.

Geometry
--------
Gear i turns with link i about its centre C_i (a point of link i), gear j
with link j about C_j; the centres may move.  With D = C_j − C_i,

    d = |D|,   β = atan2(D_y, D_x)   (the line of centres),   e = D/d,   t = e rotated +90°.

Write the pitch point as P = C_i + ρ_i e = C_j + ρ_j e with signed radii:

    external mesh             ρ_i = +r_i,  ρ_j = −r_j
    internal, j the annulus   ρ_i = −r_i,  ρ_j = −r_j      (r_j > r_i)
    internal, i the annulus   ρ_i = +r_i,  ρ_j = +r_j      (r_i > r_j)

so the nominal centre distance is d₀ = ρ_i − ρ_j = r_i + r_j or |r_i − r_j|.
The other joints of the linkage must hold d at d₀ (the type does not; see
"the pressure-angle term" below).

Rolling without slipping
------------------------
The material points of the two gears at P have the same velocity along the
common tangent t:

    t·(v_Cj + ω_j ρ_j t − v_Ci − ω_i ρ_i t) = d β̇ + ρ_j ω_j − ρ_i ω_i = 0,

using t·(v_Cj − v_Ci) = t·Ḋ = d β̇.  With d = d₀ = ρ_i − ρ_j this is
ρ_j(ω_j − β̇) − ρ_i(ω_i − β̇) = 0, which integrates to

    ρ_j (θ_j − β) − ρ_i (θ_i − β) = const,

i.e. r_i(θ_i − β) ± r_j(θ_j − β) = const (+ external, − internal): each gear's
rotation measured from the line of centres, weighted by its radius.  For
fixed centres it gives the kinematic ratio ω_j/ω_i = ρ_i/ρ_j = ∓ r_i/r_j.

The pressure-angle term and the flank
-------------------------------------
The tooth force acts along the line of action, inclined by the pressure angle
α to t.  A bilateral constraint with multiplier λ applies Φ_qᵀλ, so for the
reaction to lie along the line of action the gradient of Φ with respect to
C_j must point along it.  The row is therefore

    Φ = κ cos α [ρ_j (θ_j − β − φ) − ρ_i (θ_i − β)] + k (d − d₀),

with κ = ±1 and k = ±sin α.  Its gradient gives the force on link j

    ∂Φ/∂D = G = −κ cos α (ρ_j − ρ_i) t/d + k e = κ cos α (d₀/d) t + k e

applied at C_j together with the couple κ cos α ρ_j, which is the same as the
force G applied at the pitch point P (the moment of G at P about C_j is
ρ_j e × G = κ cos α ρ_j).  At d = d₀, |G| = 1: λ is the tooth force F along
the line of action, and (Fx, Fy) = λ G is the force of gear i on gear j.

- k e is the radial (separating) component.  Teeth push a gear with external
  teeth towards its own centre and an annulus away from it:
  k = −ε_j sgn(ρ_j) sin α (ε_j = −1 for an annulus, +1 otherwise), i.e.
  k = +sin α for an external mesh and −sin α for an internal one.
- κ chooses the loaded flank: ``flank: ccw`` means the tooth force of i turns
  gear j counter-clockwise about C_j (κ ρ_j > 0), ``cw`` the other flank.
  With the flank chosen, F ≥ 0 is a compressive tooth force.  F < 0 at a
  position means the other flank carries the load there; the tangential
  component and every torque are still right, but the radial component
  (and so the bearing reactions) then has the wrong side.  The joint cannot
  switch flanks by itself: the reaction direction would depend on the sign
  of λ, which the linear Newton–Euler solve does not allow.
- k (d − d₀) vanishes while the centre distance is held at d₀, so it does
  not change the motion; it only turns the reaction onto the line of action.
  It is the first-order term of the involute relation, where the contact
  moves along the line of action as the centre distance changes.

Phase and periodicity
---------------------
``phase`` φ fixes the constant: θ_j − β = φ when θ_i − β = 0.  Φ is a length
along the line of action; turning either gear a full turn changes it by a
multiple of the base pitch p_b = 2π r cos α / z, and so does a full turn of
the line of centres.  Φ is therefore wrapped modulo p_b·gcd(z_i, z_j), which
makes it a function of the links' poses alone (no unwrapped angles needed).
Poses differing by a whole number of that period are the same teeth in mesh
after whole turns; the sketch decides among them as for any assembly branch.

Relative coordinate and friction
--------------------------------
The coordinate is c = ½[ρ_i (θ_i − β) + ρ_j (θ_j − β)]: under rolling both
halves advance at the same rate, the pitch-line speed ċ = ρ_i (ω_i − β̇) in the
frame that carries both axles, and λ cos α ċ is the power the tooth force
carries from one gear to the other.  An effort e along c loads each gear with
half of it (a couple ½ e ρ about its centre, in that frame), so friction
opposing ċ takes half its loss from each side.

Friction is a mesh efficiency η: |e| = ζ cos α |λ| with ζ = 2(1 − η)/(1 + η),
the loss over the power of the tooth force.  Then P_out/P_in =
(1 − ζ/2)/(1 + ζ/2) = η exactly, whichever gear drives.  ``friction:
{coefficient: μ}`` sets ζ = (π/2) μ (1/z_i ± 1/z_j): the mean loss of one
tooth pair sliding at |x|·|ω_i − ω_j| (relative to the axles) a distance x
from the pitch point, x spread evenly over one base pitch (contact ratio 1,
equal approach and recess), over the power of the tooth force.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any, ClassVar

import numpy as np

from ..base.arrays import same_fields
from ..base.geometry import dot, perp, turn
from ..base.kernels import helper
from ..base.keys import NAME, NUMBER, Keys, enum, names
from ._mesh import (
    MESH_KEYS,
    MeshFriction,
    read_flank,
    read_length,
    read_loss,
    read_pressure_angle,
    read_shift,
    read_teeth,
    read_tooth_form,
    wrap,
)
from ._meshrelative import gear_motion
from .base import Anchor, Circle, Compiled, Glyph, Joint, Pole, Presentation
from .gearing import GearData

__all__ = ["Gear"]

MESHES = ("external", "internal")


# -- kernels of the compiled backend (base/kernels.py) -------------------------------------
# The formulas of Gear, position by position: the same operations in the same order, so the
# same numbers to the bit.  ``par[0]`` = (c_i, c_j, K_i, K_j, k, ρ_i, ρ_j) (Gear.kernel_params).
@helper
def _frame_at(par, P, i, j, p):
    """``_frame`` at one position: R_i, R_j, D, d and e (t = perp(e) is (−e_y, e_x))."""
    ci, si, cj, sj = P[i, 3, p], P[i, 4, p], P[j, 3, p], P[j, 4, p]
    rix, riy = ci * par[0, 0] - si * par[0, 1], si * par[0, 0] + ci * par[0, 1]
    rjx, rjy = cj * par[0, 2] - sj * par[0, 3], sj * par[0, 2] + cj * par[0, 3]
    dx = P[j, 0, p] + rjx - P[i, 0, p] - rix
    dy = P[j, 1, p] + rjy - P[i, 1, p] - riy
    d = np.hypot(dx, dy)
    return rix, riy, rjx, rjy, d, dx / d, dy / d


@helper
def _gradient_at(par, d, ex, ey):
    """``_gradient``: G = ∂Φ/∂D."""
    a = -((par[0, 5] - par[0, 4]) / d)
    return a * -ey + par[0, 6] * ex, a * ex + par[0, 6] * ey


@helper
def _rates_at(rix, riy, rjx, rjy, d, ex, ey, V, i, j, p):
    """``_rates``: D̈'s velocity part, β̇ and ḋ."""
    wi, wj = V[i, 2, p], V[j, 2, p]
    ddx = V[j, 0, p] + wj * -rjy - V[i, 0, p] - wi * -riy
    ddy = V[j, 1, p] + wj * rjx - V[i, 1, p] - wi * rix
    wj2, wi2 = -(wj * wj), wi * wi
    return (
        wj2 * rjx + wi2 * rix,
        wj2 * rjy + wi2 * riy,
        (-ey * ddx + ex * ddy) / d,
        ex * ddx + ey * ddy,
    )


def _jacobian_kernel(par, P, ends, ji, jj):
    i, j = ends[0, 0], ends[1, 0]
    for p in range(P.shape[2]):
        rix, riy, rjx, rjy, d, ex, ey = _frame_at(par, P, i, j, p)
        g0, g1 = _gradient_at(par, d, ex, ey)
        ji[0, 0, 0, p], ji[0, 0, 1, p] = -g0, -g1
        ji[0, 0, 2, p] = -par[0, 4] - (g0 * -riy + g1 * rix)
        jj[0, 0, 0, p], jj[0, 0, 1, p] = g0, g1
        jj[0, 0, 2, p] = par[0, 5] + (g0 * -rjy + g1 * rjx)


def _gamma_kernel(par, P, V, ends, out):
    i, j = ends[0, 0], ends[1, 0]
    big_k = par[0, 5] - par[0, 4]
    for p in range(P.shape[2]):
        rix, riy, rjx, rjy, d, ex, ey = _frame_at(par, P, i, j, p)
        g0, g1 = _gradient_at(par, d, ex, ey)
        d2x, d2y, beta_d, d_d = _rates_at(rix, riy, rjx, rjy, d, ex, ey, V, i, j, p)
        out[0, 0, p] = -(
            2.0 * big_k * beta_d * d_d / d
            + par[0, 6] * d * (beta_d * beta_d)
            + (g0 * d2x + g1 * d2y)
        )


def _direction_kernel(par, P, ends, gi, gj):
    i, j = ends[0, 0], ends[1, 0]
    half = -0.5 * (par[0, 7] + par[0, 8])
    for p in range(P.shape[2]):
        rix, riy, rjx, rjy, d, ex, ey = _frame_at(par, P, i, j, p)
        c = half / d
        g0, g1 = c * -ey, c * ex
        gi[0, 0, p], gi[0, 1, p] = -g0, -g1
        gi[0, 2, p] = 0.5 * par[0, 7] - (g0 * -riy + g1 * rix)
        gj[0, 0, p], gj[0, 1, p] = g0, g1
        gj[0, 2, p] = 0.5 * par[0, 8] + (g0 * -rjy + g1 * rjx)


def _bias_kernel(par, P, V, ends, out):
    i, j = ends[0, 0], ends[1, 0]
    half = -0.5 * (par[0, 7] + par[0, 8])
    for p in range(P.shape[2]):
        rix, riy, rjx, rjy, d, ex, ey = _frame_at(par, P, i, j, p)
        d2x, d2y, beta_d, d_d = _rates_at(rix, riy, rjx, rjy, d, ex, ey, V, i, j, p)
        out[0, p] = half * ((-ey * d2x + ex * d2y) - 2.0 * d_d * beta_d) / d


@dataclass(frozen=True)
class Gear(MeshFriction, Joint, Presentation, Compiled, kind="gear"):
    """Spur gear pair.  ``c_i``, ``c_j``: the gear centres in each link's frame
    (relative to its centre of mass); pitch radii ``r_i``, ``r_j``.

    Φ = κ cos α [ρ_j (θ_j − β − φ) − ρ_i (θ_i − β)] + k (d − d₀) (1 row, wrapped
    to the tooth period); λ = F, the tooth force of i on j along the line of
    action.  See the module docstring for the derivation and the signs.
    """

    __eq__ = same_fields  # arrays compared by value (base/arrays.py)

    n_eq: ClassVar[int] = 1
    reaction_labels: ClassVar[tuple[str, ...]] = ("F", "Fx", "Fy")
    angular: ClassVar[bool] = False  # the rolling coordinate is an arc length
    letter: ClassVar[str] = "G"
    spec_keys: ClassVar[Keys] = Keys(
        {
            "type": NAME,
            "links": names(2),
            "centres": names(2),
            "teeth": {"type": "array", "items": NUMBER, "minItems": 2, "maxItems": 2},
            "radii": {"type": "array", "items": NUMBER, "minItems": 2, "maxItems": 2},
            "module": NUMBER,
            "mesh": enum(MESHES),
            "shift": {"type": "array", "items": NUMBER, "minItems": 2, "maxItems": 2},
            **MESH_KEYS,
        },
        required=("type", "links", "centres", "teeth"),
    )

    c_i: np.ndarray = None
    c_j: np.ndarray = None
    centre_names: tuple[str, str] = ("", "")
    r_i: float = 0.0
    r_j: float = 0.0
    teeth: tuple[int, int] = (1, 1)
    internal: bool = False
    alpha: float = math.radians(20.0)  # pressure angle, rad
    flank: int = 1  # +1: ccw, −1: cw
    phase: float = 0.0  # rad
    loss: float = 0.0  # 1 − mesh efficiency
    # the tooth form (the gear chapter's; the motion does not read them): the addendum and
    # clearance coefficients h_a*, c* and the profile shift coefficients (x_i, x_j)
    addendum: float = 1.0
    clearance: float = 0.25
    shift: tuple[float, float] = (0.0, 0.0)

    # -- YAML ---------------------------------------------------------------
    @classmethod
    def from_spec(cls, name, entry, links, points):
        entry.check(cls.spec_keys)
        names = tuple(entry.require("centres").names(2))
        c_i = entry.point(links[0], names[0], points, key="centres", index=0)
        c_j = entry.point(links[1], names[1], points, key="centres", index=1)
        teeth = read_teeth(entry["teeth"], 2) if entry.get("teeth") is not None else None
        mesh = "external"
        if (m := entry.get("mesh")) is not None:
            mesh = m.text()
            if mesh is not None and mesh not in MESHES:
                m.error(f"mesh must be external or internal, got '{mesh}'")
                mesh = None
        radii = cls._radii(entry, teeth)
        if teeth is not None and mesh == "internal" and teeth[0] == teeth[1]:
            entry["teeth"].error(
                "an internal mesh needs an annulus larger than its pinion: "
                "the numbers of teeth must differ"
            )
            mesh = None
        alpha = read_pressure_angle(entry)
        flank = read_flank(entry)
        phase = entry["phase"].number("angle") if entry.get("phase") is not None else 0.0
        if phase is not None and not math.isfinite(phase):
            entry["phase"].error("must be a finite angle")
            phase = None
        per_mu = None
        if teeth is not None and mesh is not None:
            inv = 1.0 / teeth[0] + (-1.0 if mesh == "internal" else 1.0) / teeth[1]
            per_mu = 0.5 * math.pi * abs(inv)
        loss = read_loss(entry, per_mu)
        form = read_tooth_form(entry)
        shift = cls._shift(entry, mesh, teeth, alpha)
        values = (c_i, c_j, teeth, mesh, radii, alpha, flank, phase, loss, form, shift)
        if any(v is None for v in values):
            return None
        return cls(
            name,
            links,
            entry.where,
            c_i,
            c_j,
            names,
            radii[0],
            radii[1],
            tuple(teeth),
            mesh == "internal",
            float(alpha),
            flank,
            float(phase),
            float(loss),
            addendum=form[0],
            clearance=form[1],
            shift=shift,
        )

    @staticmethod
    def _shift(entry, mesh, teeth, alpha):
        """``shift`` (x_i, x_j): none for an internal mesh; an external pair's sum must leave
        inv α' = inv α + 2 tan α (x_i + x_j)/(z_i + z_j) positive (a working angle)."""
        shift = read_shift(entry, 2)
        if shift is None or not any(shift) or mesh is None:
            return shift
        if mesh == "internal":
            entry["shift"].error(
                "a profile shift is supported for an external pair and a rack, "
                "not for an internal mesh"
            )
            return None
        if teeth is not None and alpha is not None:
            total = sum(shift) / (teeth[0] + teeth[1])
            if not math.tan(alpha) - alpha + 2.0 * math.tan(alpha) * total > 0.0:
                entry["shift"].error(
                    f"the shifts sum to {sum(shift):g}, too little for {teeth[0]} + "
                    f"{teeth[1]} teeth: the pair has no working pressure angle "
                    "(inv α' = inv α + 2 tan α (x_i + x_j)/(z_i + z_j) ≤ 0)"
                )
                return None
        return shift

    @staticmethod
    def _radii(entry, teeth):
        radii, module = entry.get("radii"), entry.get("module")
        if radii is not None and module is not None:
            module.error("give either the pitch radii (radii) or the module, not both")
            return None
        if radii is None and module is None:
            entry.error(
                "give the pitch radii (radii: [r_i, r_j]) or the module (module: m, "
                "pitch radius m·z/2)"
            )
            return None
        if module is not None:
            m = read_length(module)
            return None if m is None or teeth is None else (0.5 * m * teeth[0], 0.5 * m * teeth[1])
        items = radii.seq()
        if items is None:
            return None
        if len(items) != 2:
            radii.error(f"expected a list of 2 pitch radii, got {len(items)}")
            return None
        r = [read_length(e) for e in items]
        if None in r or teeth is None:
            return None
        if abs(r[0] * teeth[1] - r[1] * teeth[0]) > 1e-9 * max(r[0] * teeth[1], r[1] * teeth[0]):
            radii.error(
                f"the pitch radii must be in the ratio of the teeth "
                f"{teeth[0]}:{teeth[1]} = {teeth[0] / teeth[1]:.6g} (equal modules); "
                f"their ratio is {r[0] / r[1]:.6g}"
            )
            return None
        return r[0], r[1]

    def to_spec(self) -> dict[str, Any]:
        spec: dict[str, Any] = {
            "centres": list(self.centre_names),
            "teeth": list(self.teeth),
            "radii": [self.r_i, self.r_j],
            "mesh": "internal" if self.internal else "external",
            "pressure_angle": self.alpha,
            "flank": "ccw" if self.flank > 0 else "cw",
            "phase": self.phase,
        }
        if self.loss:
            spec["friction"] = {"efficiency": 1.0 - self.loss}
        if (self.addendum, self.clearance) != (1.0, 0.25):
            spec |= {"addendum": self.addendum, "clearance": self.clearance}
        if any(self.shift):
            spec["shift"] = list(self.shift)
        return spec

    # -- constants of the row -------------------------------------------------
    @property
    def signed_radii(self) -> tuple[float, float]:
        """Signed radii (ρ_i, ρ_j): the pitch point is C_i + ρ_i e = C_j + ρ_j e."""
        if not self.internal:
            return self.r_i, -self.r_j
        if self.r_j > self.r_i:
            return -self.r_i, -self.r_j
        return self.r_i, self.r_j

    @property
    def d0(self) -> float:
        """Nominal centre distance r_i + r_j (external) or |r_i − r_j| (internal)."""
        rho_i, rho_j = self.signed_radii
        return rho_i - rho_j

    def _coefficients(self):
        """(K_i, K_j, k): Φ = K_j (θ_j − β − φ) − K_i (θ_i − β) + k (d − d₀)."""
        rho_i, rho_j = self.signed_radii
        kappa = self.flank * (1.0 if rho_j > 0 else -1.0)
        k = (-1.0 if self.internal else 1.0) * math.sin(self.alpha)
        c = kappa * math.cos(self.alpha)
        return c * rho_i, c * rho_j, k

    @property
    def period(self) -> float:
        """Tooth period of Φ: the base pitch times gcd(z_i, z_j)."""
        return (
            2.0 * math.pi * self.r_i * math.cos(self.alpha) / self.teeth[0] * math.gcd(*self.teeth)
        )

    # -- geometry -------------------------------------------------------------
    def _frame(self, qi, qj):
        Ri = turn(qi, self.c_i)
        Rj = turn(qj, self.c_j)
        D = qj[..., :2] + Rj - qi[..., :2] - Ri
        d = np.hypot(D[..., 0], D[..., 1])
        e = D / d[..., None]
        return Ri, Rj, D, d, e, perp(e)

    def _gradient(self, d, e, t):
        """G = ∂Φ/∂D, ``(..., 2)``."""
        K_i, K_j, k = self._coefficients()
        return -((K_j - K_i) / d)[..., None] * t + k * e

    @staticmethod
    def _rates(Ri, Rj, d, e, t, vi, vj):
        wi, wj = vi[..., 2], vj[..., 2]
        Dd = vj[..., :2] + wj[..., None] * perp(Rj) - vi[..., :2] - wi[..., None] * perp(Ri)
        Ddd = -(wj**2)[..., None] * Rj + (wi**2)[..., None] * Ri  # velocity part of D̈
        beta_d = dot(t, Dd) / d
        d_d = dot(e, Dd)
        return Ddd, beta_d, d_d

    # -- kinematics ---------------------------------------------------------
    def residual(self, qi, qj):
        Ri, Rj, D, d, e, t = self._frame(qi, qj)
        K_i, K_j, k = self._coefficients()
        beta = np.arctan2(D[..., 1], D[..., 0])
        phi = K_j * (qj[..., 2] - beta - self.phase) - K_i * (qi[..., 2] - beta) + k * (d - self.d0)
        return wrap(phi, self.period)[..., None]

    def jacobian(self, qi, qj):
        Ri, Rj, D, d, e, t = self._frame(qi, qj)
        K_i, K_j, _ = self._coefficients()
        G = self._gradient(d, e, t)
        shape = d.shape + (1, 3)
        ji, jj = np.zeros(shape), np.zeros(shape)
        ji[..., 0, :2], ji[..., 0, 2] = -G, -K_i - dot(G, perp(Ri))
        jj[..., 0, :2], jj[..., 0, 2] = G, K_j + dot(G, perp(Rj))
        return ji, jj

    def acceleration_rhs(self, qi, qj, vi, vj):
        Ri, Rj, D, d, e, t = self._frame(qi, qj)
        K_i, K_j, k = self._coefficients()
        G = self._gradient(d, e, t)
        Ddd, beta_d, d_d = self._rates(Ri, Rj, d, e, t, vi, vj)
        K = K_j - K_i
        # Φ̇ = G·Ḋ + K_j ω_j − K_i ω_i; its velocity-product part of Φ̈ is
        # Ġ·Ḋ + G·D̈_vel = 2K β̇ ḋ/d + k d β̇² + G·D̈_vel.
        return -(2.0 * K * beta_d * d_d / d + k * d * beta_d**2 + dot(G, Ddd))[..., None]

    def reaction(self, lam, qi, qj):
        Ri, Rj, D, d, e, t = self._frame(qi, qj)
        G = self._gradient(d, e, t)
        f = lam[..., 0]
        return {"F": f, "Fx": f * G[..., 0], "Fy": f * G[..., 1]}

    # -- relative coordinate: c = ½[ρ_i (θ_i − β) + ρ_j (θ_j − β)] ------------------
    def coordinate(self, qi, qj):
        Ri, Rj, D, d, e, t = self._frame(qi, qj)
        rho_i, rho_j = self.signed_radii
        beta = np.arctan2(D[..., 1], D[..., 0])
        return 0.5 * (rho_i * (qi[..., 2] - beta) + rho_j * (qj[..., 2] - beta))

    def _c_gradient(self, d, t):
        """∂c/∂D = −½(ρ_i + ρ_j) t/d."""
        rho_i, rho_j = self.signed_radii
        return (-0.5 * (rho_i + rho_j) / d)[..., None] * t

    def motion_direction(self, qi, qj):
        Ri, Rj, D, d, e, t = self._frame(qi, qj)
        rho_i, rho_j = self.signed_radii
        g = self._c_gradient(d, t)
        gi = np.concatenate((-g, (0.5 * rho_i - dot(g, perp(Ri)))[..., None]), axis=-1)
        gj = np.concatenate((g, (0.5 * rho_j + dot(g, perp(Rj)))[..., None]), axis=-1)
        return gi, gj

    def coordinate_bias(self, qi, qj, vi, vj):
        Ri, Rj, D, d, e, t = self._frame(qi, qj)
        rho_i, rho_j = self.signed_radii
        Ddd, beta_d, d_d = self._rates(Ri, Rj, d, e, t, vi, vj)
        # β̈ = (t·D̈ − 2 ḋ β̇)/d, so the velocity part of c̈ = −½(ρ_i + ρ_j) β̈ is:
        return -0.5 * (rho_i + rho_j) * (dot(t, Ddd) - 2.0 * d_d * beta_d) / d

    # -- compiled backend (base/kernels.py): the formulas above, position by position --
    jacobian_kernel = staticmethod(_jacobian_kernel)
    gamma_kernel = staticmethod(_gamma_kernel)
    direction_kernel = staticmethod(_direction_kernel)
    bias_kernel = staticmethod(_bias_kernel)

    def kernel_params(self, k: int) -> np.ndarray | None:
        """(c_i, c_j, K_i, K_j, k, ρ_i, ρ_j), as ``_coefficients`` and ``signed_radii`` give
        them; None for a stack or for variants that differ in them."""
        values = (self.c_i, self.c_j, *self._coefficients(), *self.signed_radii)
        if k != 1 or [np.size(v) for v in values] != [2, 2, 1, 1, 1, 1, 1]:
            return None
        return np.concatenate([np.ravel(v) for v in values]).astype(float)[None]

    def effort_force(self, effort, qi, qj):
        Ri, Rj, D, d, e, t = self._frame(qi, qj)
        g = self._c_gradient(d, t)
        return {"Fx": effort * g[..., 0], "Fy": effort * g[..., 1]}

    def instant_centre(self, qi, qj):
        """The operating pitch point C_i + ρ_i (d/d₀) e: it divides the centre distance d in
        the ratio of the pitch radii (the base circles'), where the two gears roll without
        slipping while d is held (d constant, as on an arm or on the frame)."""
        Ri, Rj, D, d, e, t = self._frame(qi, qj)
        scale = (self.signed_radii[0] * d / self.d0)[..., None]
        return Pole(qi[..., :2] + Ri + scale * e)

    def relative_motion(self, qi, qj, vi, vj, ai, aj, labels):
        """At the pitch point the gears roll: no relative velocity and the normal
        acceleration of rolling while the centre distance is held (``_meshrelative.py``)."""
        return gear_motion(self, qi, qj, vi, vj, ai, aj, labels)

    # -- description ----------------------------------------------------------
    def anchors(self):
        i, j = self.links
        return (
            Anchor(i, self.centre_names[0], self.c_i),
            Anchor(j, self.centre_names[1], self.c_j),
        )

    def gear_data(self) -> GearData:
        return GearData(
            self.name,
            "internal" if self.internal else "external",
            self.links,
            self.teeth,
            (self.r_i, self.r_j),
            self.alpha,
            self.addendum,
            self.clearance,
            self.shift,
        )

    def glyph(self, qi, qj):
        """The pitch circles about the centres; the pitch point on the line of centres."""
        i, j = self.links
        Ci = qi[..., :2] + turn(qi, self.c_i)
        Cj = qj[..., :2] + turn(qj, self.c_j)
        D = Cj - Ci
        e = D / np.maximum(np.linalg.norm(D, axis=-1, keepdims=True), 1e-300)
        return Glyph(
            point=Ci + self.signed_radii[0] * e,
            circles=(Circle(i, Ci, self.r_i), Circle(j, Cj, self.r_j)),
        )
