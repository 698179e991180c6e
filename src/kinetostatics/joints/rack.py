r"""Rack and pinion: a pinion (or sector) on link j rolls on the pitch line of a rack on link i.

A higher pair (one row of Φ, one reaction: the tooth force).  The derivation
follows the gear pair's (``gear.py``); ``docs/extending.md`` has both.

Geometry
--------
The rack is link i: its pitch line passes through the point A_i with the unit
direction u (both fixed in link i, like a prismatic axis); n = u rotated +90°.
The pinion is link j with centre C_j and pitch radius r.  With D = C_j − A_i,

    s = u·D   (where the pinion centre is along the rack),
    h = n·D   (its signed distance from the pitch line),   ν = sign(h),

so the pitch point is P = C_j − h n, and the other joints must hold |h| at r
(the pinion on the +n side of the line has ν = +1, on the −n side ν = −1).

Rolling without slipping
------------------------
In the frame of the rack the pinion's material point at P moves with
ṡ u + ḣ n + (ω_j − ω_i) × (−ν r n) = (ṡ + ν r (ω_j − ω_i)) u + ḣ n; its
component along the pitch line vanishes:

    s + ν r (θ_j − θ_i) = const,

so for a rack sliding in a ground guide under a pinion on a ground pivot the
ratio is exact: v_rack = ν r ω_pinion (a pinion above the rack, ν = +1, turns
counter-clockwise when the rack moves along +u).

The pressure-angle term and the flank
-------------------------------------
As for the gear pair, the row is written so that its gradient lies along the
line of action (inclined by α to the pitch line):

    Φ = κ cos α [s − s₀ + ν r (θ_j − θ_i)] + sin α (ν h − r),

whose gradient with respect to C_j, G = κ cos α u + sin α ν n, has unit
length, and whose couple about C_j, κ cos α ν r, is the moment of G applied at
the pitch point P.  So λ is the tooth force F along the line of action and
(Fx, Fy) = λ G the force of the rack on the pinion.  sin α ν n pushes the
pinion away from the rack (towards its own centre); κ = ±ν picks the loaded
flank: ``flank: ccw`` (κ ν > 0) when the rack's tooth force turns the pinion
counter-clockwise, ``cw`` otherwise.  F < 0 at a position means the other flank
is loaded there (torques and forces along the rack stay right; the radial
component has the wrong side).  ν h − r vanishes while the other joints hold
the pinion at its pitch distance, so it does not change the motion.

``phase`` s₀ fixes the constant: the pinion centre is at s = s₀ when
θ_j − θ_i = 0.  Turning either link a full turn changes Φ by 2π r cos α, so
Φ is wrapped modulo that length and needs no unwrapped angles.

Relative coordinate and friction
--------------------------------
The coordinate is c = ½[s − ν r (θ_j − θ_i)]: under rolling both halves move
at the pitch-line speed ṡ (the rack's travel past the pinion's axle), and
λ cos α ṡ is the power of the tooth force.  An effort e along c is half a
force ½ e along u on the rack and half a couple on the pinion, so friction
takes half its loss from each side.  As for the gear pair, a mesh efficiency
η gives |e| = ζ cos α |λ| with ζ = 2(1 − η)/(1 + η) (P_out/P_in = η, whichever
side drives), and a tooth friction coefficient μ gives ζ = (π/2) μ / z
(z = ``teeth`` of the pinion: the gear-pair model with an infinite rack).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any, ClassVar

import numpy as np

from ..base.arrays import same_fields
from ..base.geometry import dot, perp, turn
from ..base.kernels import helper
from ..base.keys import NAME, NUMBER, Keys, names
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
from ._meshrelative import rack_motion
from .base import AXIS_KEYS, Anchor, Circle, Compiled, Glyph, Joint, Line, Pole, Presentation
from .gearing import GearData

__all__ = ["Rack"]


# -- kernels of the compiled backend (base/kernels.py) -------------------------------------
# The formulas of Rack, position by position: the same operations in the same order, so the
# same numbers to the bit.  ``par[0]`` = (a, u, c, κ, cos α, sin α, r) (Rack.kernel_params).
@helper
def _frame_at(par, P, i, j, p):
    """``_frame`` at one position: A, U, C, D and ν (N = perp(U) is (−U_y, U_x))."""
    ci, si, cj, sj = P[i, 3, p], P[i, 4, p], P[j, 3, p], P[j, 4, p]
    ax, ay = ci * par[0, 0] - si * par[0, 1], si * par[0, 0] + ci * par[0, 1]
    ux, uy = ci * par[0, 2] - si * par[0, 3], si * par[0, 2] + ci * par[0, 3]
    cx, cy = cj * par[0, 4] - sj * par[0, 5], sj * par[0, 4] + cj * par[0, 5]
    dx = P[j, 0, p] + cx - P[i, 0, p] - ax
    dy = P[j, 1, p] + cy - P[i, 1, p] - ay
    nu = 1.0 if -uy * dx + ux * dy >= 0.0 else -1.0
    return ax, ay, ux, uy, cx, cy, dx, dy, nu


@helper
def _rates_at(ax, ay, ux, uy, cx, cy, dx, dy, V, i, j, p):
    """``_rates``: the velocity-product parts of s̈ and ḧ."""
    wi, wj = V[i, 2, p], V[j, 2, p]
    ddx = V[j, 0, p] + wj * -cy - V[i, 0, p] - wi * -ay
    ddy = V[j, 1, p] + wj * cx - V[i, 1, p] - wi * ax
    wj2, wi2 = -(wj * wj), wi * wi
    d2x, d2y = wj2 * cx + wi2 * ax, wj2 * cy + wi2 * ay
    s_b = (
        -(wi * wi) * (ux * dx + uy * dy) + 2.0 * wi * (-uy * ddx + ux * ddy) + (ux * d2x + uy * d2y)
    )
    h_b = (
        -(wi * wi) * (-uy * dx + ux * dy)
        - 2.0 * wi * (ux * ddx + uy * ddy)
        + (-uy * d2x + ux * d2y)
    )
    return s_b, h_b


def _jacobian_kernel(par, P, ends, ji, jj):
    i, j = ends[0, 0], ends[1, 0]
    for p in range(P.shape[2]):
        ax, ay, ux, uy, cx, cy, dx, dy, nu = _frame_at(par, P, i, j, p)
        kc, ks = par[0, 6] * nu * par[0, 7], par[0, 8] * nu
        g0, g1 = kc * ux + ks * -uy, kc * uy + ks * ux
        s, h = ux * dx + uy * dy, -uy * dx + ux * dy
        ji[0, 0, 0, p], ji[0, 0, 1, p] = -g0, -g1
        ji[0, 0, 2, p] = kc * (h - nu * par[0, 9]) - ks * s - (g0 * -ay + g1 * ax)
        jj[0, 0, 0, p], jj[0, 0, 1, p] = g0, g1
        jj[0, 0, 2, p] = kc * nu * par[0, 9] + (g0 * -cy + g1 * cx)


def _gamma_kernel(par, P, V, ends, out):
    i, j = ends[0, 0], ends[1, 0]
    for p in range(P.shape[2]):
        ax, ay, ux, uy, cx, cy, dx, dy, nu = _frame_at(par, P, i, j, p)
        kc, ks = par[0, 6] * nu * par[0, 7], par[0, 8] * nu
        s_b, h_b = _rates_at(ax, ay, ux, uy, cx, cy, dx, dy, V, i, j, p)
        out[0, 0, p] = -(kc * s_b + ks * h_b)


def _direction_kernel(par, P, ends, gi, gj):
    i, j = ends[0, 0], ends[1, 0]
    for p in range(P.shape[2]):
        ax, ay, ux, uy, cx, cy, dx, dy, nu = _frame_at(par, P, i, j, p)
        half = 0.5 * nu * par[0, 9]
        gi[0, 0, p], gi[0, 1, p] = -0.5 * ux, -0.5 * uy
        gi[0, 2, p] = 0.5 * ((-uy * dx + ux * dy) - (ux * -ay + uy * ax)) + half
        gj[0, 0, p], gj[0, 1, p] = 0.5 * ux, 0.5 * uy
        gj[0, 2, p] = 0.5 * (ux * -cy + uy * cx) - half


def _bias_kernel(par, P, V, ends, out):
    i, j = ends[0, 0], ends[1, 0]
    for p in range(P.shape[2]):
        ax, ay, ux, uy, cx, cy, dx, dy, nu = _frame_at(par, P, i, j, p)
        out[0, p] = 0.5 * _rates_at(ax, ay, ux, uy, cx, cy, dx, dy, V, i, j, p)[0]


@dataclass(frozen=True)
class Rack(MeshFriction, Joint, Presentation, Compiled, kind="rack"):
    """Rack (link i: pitch-line point ``a`` and unit ``u``, local, ``a`` relative to
    i's CoM) meshing with a pinion or sector (link j: centre ``c``, pitch radius ``r``).

    Φ = κ cos α [s − s₀ + ν r (θ_j − θ_i)] + sin α (ν h − r) (1 row, wrapped to
    2π r cos α); λ = F, the tooth force of the rack on the pinion along the line
    of action.  See the module docstring for the derivation and the signs.
    """

    __eq__ = same_fields  # arrays compared by value (base/arrays.py)

    n_eq: ClassVar[int] = 1
    reaction_labels: ClassVar[tuple[str, ...]] = ("F", "Fx", "Fy")
    angular: ClassVar[bool] = False  # the coordinate is a travel along the rack
    letter: ClassVar[str] = "K"  # R is the revolute's
    spec_keys: ClassVar[Keys] = Keys(
        {
            "type": NAME,
            "links": names(2),
            "axis": AXIS_KEYS,
            "centre": NAME,
            "radius": NUMBER,
            "module": NUMBER,
            "teeth": NUMBER,
            "shift": NUMBER,
            **MESH_KEYS,
        },
        required=("type", "links", "axis", "centre"),
    )

    a: np.ndarray = None
    u: np.ndarray = None
    c: np.ndarray = None
    axis_names: tuple[str, ...] = ()
    centre_name: str = ""
    r: float = 0.0
    teeth: int | None = None
    alpha: float = math.radians(20.0)  # pressure angle, rad
    flank: int = 1  # +1: ccw, −1: cw
    phase: float = 0.0  # s₀, m
    loss: float = 0.0  # 1 − mesh efficiency
    # the tooth form (the gear chapter's; the motion does not read them): the addendum and
    # clearance coefficients h_a*, c* and the pinion's profile shift coefficient x
    addendum: float = 1.0
    clearance: float = 0.25
    shift: float = 0.0

    # -- YAML ---------------------------------------------------------------
    @classmethod
    def from_spec(cls, name, entry, links, points):
        entry.check(cls.spec_keys)
        a, u, axis_names = cls._axis(entry.require("axis"), links, points)
        cname = entry.require("centre").names(1)[0]
        c = entry.point(links[1], cname, points, key="centre")
        z = None
        if entry.get("teeth") is not None:
            teeth = read_teeth(entry["teeth"], 1)
            if teeth is None:
                return None
            z = teeth[0]
        radius, module = entry.get("radius"), entry.get("module")
        r = None
        if radius is not None and module is not None:
            module.error("give either the pitch radius (radius) or the module, not both")
        elif radius is None and module is None:
            entry.error(
                "give the pitch radius of the pinion (radius: r) or the module and "
                "its teeth (module: m, teeth: z; r = m·z/2)"
            )
        elif radius is not None:
            r = read_length(radius)
        elif z is None:
            module.error("a module needs the pinion's number of teeth (key teeth)")
        else:
            m = read_length(module)
            r = None if m is None else 0.5 * m * z
        alpha = read_pressure_angle(entry)
        flank = read_flank(entry)
        phase = entry["phase"].number("length") if entry.get("phase") is not None else 0.0
        if phase is not None and not math.isfinite(phase):
            entry["phase"].error("must be a finite length")
            phase = None
        loss = read_loss(entry, None if z is None else 0.5 * math.pi / z)
        form, shift = read_tooth_form(entry), read_shift(entry, 1)
        if any(v is None for v in (a, u, c, r, alpha, flank, phase, loss, form, shift)):
            return None
        return cls(
            name,
            links,
            entry.where,
            a,
            u,
            c,
            axis_names,
            cname,
            float(r),
            z,
            float(alpha),
            flank,
            float(phase),
            float(loss),
            addendum=form[0],
            clearance=form[1],
            shift=shift[0],
        )

    @staticmethod
    def _axis(axis, links, points):
        """(a, u, names) of ``axis: {point, direction}`` or ``axis: {points: [A, B]}`` on link i."""
        if not axis:
            return None, None, ()
        if not axis.check(AXIS_KEYS):
            return None, None, ()
        if axis.get("points") is not None:
            pa, pb = axis["points"].names(2)
            a = axis.point(links[0], pa, points, key="points", index=0)
            b = axis.point(links[0], pb, points, key="points", index=1)
            u = None if a is None or b is None else axis["points"].unit(b - a)
            return a, u, (pa, pb)
        pa = axis.require("point").names(1)[0]
        a = axis.point(links[0], pa, points, key="point")
        d = axis.require("direction").vector(None)
        u = None if d is None else axis["direction"].unit(d)
        if u is not None and not np.all(np.isfinite(u)):
            axis["direction"].error("the direction must be finite")
            u = None
        return a, u, (pa,)

    def to_spec(self) -> dict[str, Any]:
        if len(self.axis_names) == 2:
            axis: dict[str, Any] = {"points": list(self.axis_names)}
        else:
            axis = {"point": self.axis_names[0], "direction": [float(x) for x in self.u]}
        spec: dict[str, Any] = {
            "axis": axis,
            "centre": self.centre_name,
            "radius": self.r,
            "pressure_angle": self.alpha,
            "flank": "ccw" if self.flank > 0 else "cw",
            "phase": self.phase,
        }
        if self.teeth is not None:
            spec["teeth"] = self.teeth
        if self.loss:
            spec["friction"] = {"efficiency": 1.0 - self.loss}
        if (self.addendum, self.clearance) != (1.0, 0.25):
            spec |= {"addendum": self.addendum, "clearance": self.clearance}
        if self.shift:
            spec["shift"] = self.shift
        return spec

    # -- geometry -----------------------------------------------------------
    def _frame(self, qi, qj):
        A = turn(qi, self.a)
        U = turn(qi, self.u)
        C = turn(qj, self.c)
        D = qj[..., :2] + C - qi[..., :2] - A
        N = perp(U)
        nu = np.where(dot(N, D) >= 0.0, 1.0, -1.0)
        return A, U, N, C, D, nu

    def _gains(self, nu):
        """(κ cos α, sin α ν) broadcast over positions."""
        return self.flank * nu * math.cos(self.alpha), math.sin(self.alpha) * nu

    @staticmethod
    def _rates(A, U, N, C, D, vi, vj):
        """Velocity-product parts of s̈ and ḧ (as for a prismatic axis)."""
        wi, wj = vi[..., 2], vj[..., 2]
        Dd = vj[..., :2] + wj[..., None] * perp(C) - vi[..., :2] - wi[..., None] * perp(A)
        Ddd = -(wj**2)[..., None] * C + (wi**2)[..., None] * A
        s_b = -(wi**2) * dot(U, D) + 2.0 * wi * dot(N, Dd) + dot(U, Ddd)
        h_b = -(wi**2) * dot(N, D) - 2.0 * wi * dot(U, Dd) + dot(N, Ddd)
        return s_b, h_b

    # -- kinematics ---------------------------------------------------------
    def residual(self, qi, qj):
        A, U, N, C, D, nu = self._frame(qi, qj)
        kc, ks = self._gains(nu)
        phi = (
            kc * (dot(U, D) - self.phase + nu * self.r * (qj[..., 2] - qi[..., 2]))
            + ks * dot(N, D)
            - math.sin(self.alpha) * self.r
        )
        return wrap(phi, 2.0 * math.pi * self.r * math.cos(self.alpha))[..., None]

    def jacobian(self, qi, qj):
        A, U, N, C, D, nu = self._frame(qi, qj)
        kc, ks = self._gains(nu)
        G = kc[..., None] * U + ks[..., None] * N  # ∂Φ/∂D
        s, h = dot(U, D), dot(N, D)
        shape = s.shape + (1, 3)
        ji, jj = np.zeros(shape), np.zeros(shape)
        # ∂s/∂θ_i = h − u·perp(A), ∂h/∂θ_i = −s − n·perp(A)
        ji[..., 0, :2] = -G
        ji[..., 0, 2] = kc * (h - nu * self.r) - ks * s - dot(G, perp(A))
        jj[..., 0, :2] = G
        jj[..., 0, 2] = kc * nu * self.r + dot(G, perp(C))
        return ji, jj

    def acceleration_rhs(self, qi, qj, vi, vj):
        A, U, N, C, D, nu = self._frame(qi, qj)
        kc, ks = self._gains(nu)
        s_b, h_b = self._rates(A, U, N, C, D, vi, vj)
        return -(kc * s_b + ks * h_b)[..., None]

    def reaction(self, lam, qi, qj):
        A, U, N, C, D, nu = self._frame(qi, qj)
        kc, ks = self._gains(nu)
        f = lam[..., 0]
        return {
            "F": f,
            "Fx": f * (kc * U[..., 0] + ks * N[..., 0]),
            "Fy": f * (kc * U[..., 1] + ks * N[..., 1]),
        }

    # -- relative coordinate: c = ½[s − ν r (θ_j − θ_i)] ----------------------------
    def coordinate(self, qi, qj):
        A, U, N, C, D, nu = self._frame(qi, qj)
        return 0.5 * (dot(U, D) - nu * self.r * (qj[..., 2] - qi[..., 2]))

    def motion_direction(self, qi, qj):
        A, U, N, C, D, nu = self._frame(qi, qj)
        half = 0.5 * nu * self.r
        gi = np.concatenate(
            (-0.5 * U, (0.5 * (dot(N, D) - dot(U, perp(A))) + half)[..., None]), axis=-1
        )
        gj = np.concatenate((0.5 * U, (0.5 * dot(U, perp(C)) - half)[..., None]), axis=-1)
        return gi, gj

    def coordinate_bias(self, qi, qj, vi, vj):
        A, U, N, C, D, nu = self._frame(qi, qj)
        return 0.5 * self._rates(A, U, N, C, D, vi, vj)[0]

    # -- compiled backend (base/kernels.py): the formulas above, position by position --
    jacobian_kernel = staticmethod(_jacobian_kernel)
    gamma_kernel = staticmethod(_gamma_kernel)
    direction_kernel = staticmethod(_direction_kernel)
    bias_kernel = staticmethod(_bias_kernel)

    def kernel_params(self, k: int) -> np.ndarray | None:
        """(a, u, c, κ, cos α, sin α, r); None for a stack or for variants that differ."""
        values = (self.a, self.u, self.c, self.flank, self.alpha, self.r)
        if k != 1 or [np.size(v) for v in values] != [2, 2, 2, 1, 1, 1]:
            return None
        scalars = (self.flank, math.cos(self.alpha), math.sin(self.alpha), self.r)
        return np.concatenate([self.a, self.u, self.c, scalars]).astype(float)[None]

    def effort_force(self, effort, qi, qj):
        U = turn(qi, self.u)
        return {"Fx": 0.5 * effort * U[..., 0], "Fy": 0.5 * effort * U[..., 1]}

    def instant_centre(self, qi, qj):
        """The operating pitch point C − ν r n: the pinion's pitch circle rolls without
        slipping on the line parallel to the rack that it touches, while the pinion
        centre keeps its distance from the rack (as on the frame)."""
        A, U, N, C, D, nu = self._frame(qi, qj)
        return Pole(qj[..., :2] + C - (nu * self.r)[..., None] * N)

    def relative_motion(self, qi, qj, vi, vj, ai, aj, labels):
        """At the pitch point the pinion rolls on the rack: no relative velocity and the
        normal acceleration of rolling while its height is held (``_meshrelative.py``)."""
        return rack_motion(self, qi, qj, vi, vj, ai, aj, labels)

    # -- description ----------------------------------------------------------
    def anchors(self):
        i, j = self.links
        named = self.axis_names and self.axis_names[0]
        axis = (Anchor(i, self.axis_names[0], self.a),) if named else ()
        return axis + (Anchor(j, self.centre_name, self.c),)

    def gear_data(self) -> GearData:
        return GearData(
            self.name,
            "rack",
            self.links,
            (None, self.teeth),
            (None, self.r),
            self.alpha,
            self.addendum,
            self.clearance,
            (0.0, self.shift),
        )

    def glyph(self, qi, qj):
        """The pinion's pitch circle, the rack's pitch line; the pitch point is the
        foot of the pinion centre on that line."""
        i, j = self.links
        A = qi[..., :2] + turn(qi, self.a)
        U = turn(qi, self.u)
        C = qj[..., :2] + turn(qj, self.c)
        N = perp(U)
        h = np.sum(N * (C - A), axis=-1, keepdims=True)
        return Glyph(point=C - h * N, circles=(Circle(j, C, self.r),), lines=(Line(i, A, U),))
