"""Prismatic pair: a point of link j slides along an axis of link i."""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any, ClassVar

import numpy as np

from ..base.arrays import entry_major_zeros, same_fields
from ..base.geometry import dot, perp, turn, wrap_angle
from ..base.kernels import helper
from ..base.keys import NAME, NUMBER, Keys, names
from .base import (
    AXIS_KEYS,
    Anchor,
    Block,
    Compiled,
    Friction,
    Glyph,
    Joint,
    Line,
    Pole,
    Presentation,
)
from .relative import RelativeMotion, RelativeTerm

FRICTION_KEYS = Keys({"coefficient": NUMBER}, required=("coefficient",))

__all__ = ["Prismatic"]


# -- kernels of the compiled backend (base/kernels.py) -------------------------------------
# The formulas of Prismatic, position by position: the same operations in the same order,
# so the same numbers to the bit.  ``par[m]`` = (a, u, p, angle) of joint m of a stack;
# P (n + 1, 5, N) the poses (x, y, θ, cos θ, sin θ), V (n + 1, 3, N) the rates; the
# friction kernel reads (N, M) from ``x (N, n_λ)`` at its ``rows (1, 2)``, ``par`` = (f, L).
@helper
def _frame_at(par, P, m, i, j, p):
    """``_frame`` at one position: A, U, P, d (N = perp(U) is (−U_y, U_x))."""
    ci, si, cj, sj = P[i, 3, p], P[i, 4, p], P[j, 3, p], P[j, 4, p]
    ax, ay = ci * par[m, 0] - si * par[m, 1], si * par[m, 0] + ci * par[m, 1]
    ux, uy = ci * par[m, 2] - si * par[m, 3], si * par[m, 2] + ci * par[m, 3]
    px, py = cj * par[m, 4] - sj * par[m, 5], sj * par[m, 4] + cj * par[m, 5]
    dx = P[j, 0, p] + px - P[i, 0, p] - ax
    dy = P[j, 1, p] + py - P[i, 1, p] - ay
    return ax, ay, ux, uy, px, py, dx, dy


@helper
def _rates_at(ax, ay, px, py, V, i, j, p):
    """``_rates`` at one position: ω_i, ḋ and the velocity part of d̈."""
    wi, wj = V[i, 2, p], V[j, 2, p]
    ddx = V[j, 0, p] + wj * -py - V[i, 0, p] - wi * -ay
    ddy = V[j, 1, p] + wj * px - V[i, 1, p] - wi * ax
    wj2, wi2 = -(wj * wj), wi * wi
    return wi, ddx, ddy, wj2 * px + wi2 * ax, wj2 * py + wi2 * ay


def _residual_kernel(par, P, ends, out):
    for m in range(ends.shape[1]):
        i, j = ends[0, m], ends[1, m]
        for p in range(P.shape[2]):
            ax, ay, ux, uy, px, py, dx, dy = _frame_at(par, P, m, i, j, p)
            out[m, 0, p] = -uy * dx + ux * dy
            turned = P[j, 2, p] - P[i, 2, p] - par[m, 6]
            out[m, 1, p] = (turned + np.pi) % (2.0 * np.pi) - np.pi


def _jacobian_kernel(par, P, ends, ji, jj):
    for m in range(ends.shape[1]):
        i, j = ends[0, m], ends[1, m]
        for p in range(P.shape[2]):
            ax, ay, ux, uy, px, py, dx, dy = _frame_at(par, P, m, i, j, p)
            ji[m, 0, 0, p], ji[m, 0, 1, p] = uy, -ux  # −N, N = (−U_y, U_x)
            ji[m, 0, 2, p] = -(ux * dx + uy * dy) - (-uy * -ay + ux * ax)
            jj[m, 0, 0, p], jj[m, 0, 1, p], jj[m, 0, 2, p] = -uy, ux, -uy * -py + ux * px
            ji[m, 1, 0, p], ji[m, 1, 1, p], ji[m, 1, 2, p] = 0.0, 0.0, -1.0
            jj[m, 1, 0, p], jj[m, 1, 1, p], jj[m, 1, 2, p] = 0.0, 0.0, 1.0


def _gamma_kernel(par, P, V, ends, out):
    for m in range(ends.shape[1]):
        i, j = ends[0, m], ends[1, m]
        for p in range(P.shape[2]):
            ax, ay, ux, uy, px, py, dx, dy = _frame_at(par, P, m, i, j, p)
            wi, ddx, ddy, d2x, d2y = _rates_at(ax, ay, px, py, V, i, j, p)
            out[m, 0, p] = (
                wi * wi * (-uy * dx + ux * dy)
                + 2.0 * wi * (ux * ddx + uy * ddy)
                - (-uy * d2x + ux * d2y)
            )
            out[m, 1, p] = 0.0


def _direction_kernel(par, P, ends, gi, gj):
    for m in range(ends.shape[1]):
        i, j = ends[0, m], ends[1, m]
        for p in range(P.shape[2]):
            ax, ay, ux, uy, px, py, dx, dy = _frame_at(par, P, m, i, j, p)
            gi[m, 0, p], gi[m, 1, p] = -ux, -uy
            gi[m, 2, p] = (-uy * dx + ux * dy) - (ux * -ay + uy * ax)
            gj[m, 0, p], gj[m, 1, p], gj[m, 2, p] = ux, uy, ux * -py + uy * px


def _bias_kernel(par, P, V, ends, out):
    for m in range(ends.shape[1]):
        i, j = ends[0, m], ends[1, m]
        for p in range(P.shape[2]):
            ax, ay, ux, uy, px, py, dx, dy = _frame_at(par, P, m, i, j, p)
            wi, ddx, ddy, d2x, d2y = _rates_at(ax, ay, px, py, V, i, j, p)
            out[m, p] = (
                -(wi * wi) * (ux * dx + uy * dy)
                + 2.0 * wi * (-uy * ddx + ux * ddy)
                + (ux * d2x + uy * d2y)
            )


def _friction_kernel(par, x, rows, out):
    for m in range(rows.shape[0]):
        a, b, f, length = rows[m, 0], rows[m, 1], par[m, 0], par[m, 1]
        for p in range(x.shape[0]):
            if length != length:  # no contact length: f|N|
                out[m, p] = f * abs(x[p, a])
            else:  # two edges, N/2 ± M/L
                half = 0.5 * x[p, a]
                out[m, p] = f * (abs(half + x[p, b] / length) + abs(half - x[p, b] / length))


@dataclass(frozen=True)
class Prismatic(Joint, Presentation, Friction, Compiled, kind="prismatic"):
    """Slider.  The axis belongs to link i: point ``a`` and unit ``u`` (local, ``a``
    relative to i's CoM); ``p`` is the sliding point of link j (relative to j's CoM).

    Φ₁ = n·(P_j − A_i) (P_j on the axis, n = u rotated +90°),
    Φ₂ = θ_j − θ_i − ``angle`` (no relative rotation).
    λ₁ = N, the force of i on j along n; λ₂ = M, the couple of i on j about P_j.
    Relative coordinate s = (P_j − A_i)·u.  Coulomb friction f|N| along u opposes ṡ;
    with ``length`` L the block bears on two edges, N₁,₂ = N/2 ± M/L, and the
    friction is f(|N₁| + |N₂|).
    """

    __eq__ = same_fields  # arrays compared by value (base/arrays.py)

    n_eq: ClassVar[int] = 2
    reaction_labels: ClassVar[tuple[str, ...]] = ("Fx", "Fy", "N", "M")
    angular: ClassVar[bool] = False
    letter: ClassVar[str] = "P"
    spec_keys: ClassVar[Keys] = Keys(
        {
            "type": NAME,
            "links": names(2),
            "axis": AXIS_KEYS,
            "point": NAME,
            "angle": NUMBER,
            "length": NUMBER,
            "friction": FRICTION_KEYS,
        },
        required=("type", "links", "axis"),
    )
    reports_stroke: ClassVar[bool] = True

    stacked_vectors: ClassVar[tuple[str, ...]] = ("a", "u", "p")
    stacked_scalars: ClassVar[tuple[str, ...]] = ("angle",)

    a: np.ndarray = None
    u: np.ndarray = None
    p: np.ndarray = None
    angle: float = 0.0
    axis_names: tuple[str, ...] = ()
    point_name: str = ""
    f: float = 0.0
    length: float | None = None

    # -- YAML ---------------------------------------------------------------
    @classmethod
    def from_spec(cls, name, entry, links, points):
        entry.check(cls.spec_keys)
        axis, a, u, axis_names = entry.require("axis"), None, None, ()
        if axis is not None:
            axis.check(AXIS_KEYS)
            if axis.get("points") is not None:
                pa, pb = axis["points"].names(2) or (None, None)
                a = axis.point(links[0], pa, points, key="points", index=0)
                b = axis.point(links[0], pb, points, key="points", index=1)
                axis_names = (pa, pb)
                if a is not None and b is not None:
                    u = axis["points"].unit(b - a)
            else:
                pa = axis.require("point").names(1)
                a = axis.point(links[0], pa and pa[0], points, key="point")
                d = axis.require("direction").vector(None)
                u = None if d is None else axis["direction"].unit(d)
                axis_names = (pa and pa[0],)
        pname = entry["point"].names(1)[0] if entry.get("point") is not None else name
        p = entry.point(links[1], pname, points, key="point")
        angle = entry["angle"].number("angle") if entry.get("angle") is not None else 0.0
        length = None
        if entry.get("length") is not None:
            length = entry["length"].number("length", minimum=0.0, strict=True)
        f = 0.0
        if (fr := entry.get("friction")) is not None:
            fr.check(FRICTION_KEYS)
            f = fr["coefficient"].coefficient() if fr.get("coefficient") else 0.0
        if a is None or u is None or p is None or angle is None or f is None:
            return None
        return cls(
            name, links, entry.where, a, u, p, float(angle), axis_names, pname, float(f), length
        )

    def to_spec(self) -> dict[str, Any]:
        if len(self.axis_names) == 2:
            axis: dict[str, Any] = {"points": list(self.axis_names)}
        else:
            axis = {"point": self.axis_names[0], "direction": [float(c) for c in self.u]}
        spec: dict[str, Any] = {"axis": axis, "point": self.point_name, "angle": self.angle}
        if self.length is not None:
            spec["length"] = self.length
        if self.f:
            spec["friction"] = {"coefficient": self.f}
        return spec

    # -- geometry -----------------------------------------------------------
    def _frame(self, qi, qj):
        A = turn(qi, self.a)
        U = turn(qi, self.u)
        P = turn(qj, self.p)
        d = qj[..., :2] + P - qi[..., :2] - A
        return A, U, perp(U), P, d

    def residual(self, qi, qj):
        A, U, N, P, d = self._frame(qi, qj)
        return np.stack((dot(N, d), wrap_angle(qj[..., 2] - qi[..., 2] - self.angle)), axis=-1)

    def jacobian(self, qi, qj):
        A, U, N, P, d = self._frame(qi, qj)
        shape = d.shape[:-1] + (2, 3)
        ji, jj = entry_major_zeros(shape), entry_major_zeros(shape)
        ji[..., 0, :2], ji[..., 0, 2] = -N, -dot(U, d) - dot(N, perp(A))
        jj[..., 0, :2], jj[..., 0, 2] = N, dot(N, perp(P))
        ji[..., 1, 2], jj[..., 1, 2] = -1.0, 1.0
        return ji, jj

    @staticmethod
    def _rates(A, P, vi, vj):
        wi, wj = vi[..., 2], vj[..., 2]
        dd = vj[..., :2] + wj[..., None] * perp(P) - vi[..., :2] - wi[..., None] * perp(A)
        dd2 = -(wj**2)[..., None] * P + (wi**2)[..., None] * A  # velocity part of d̈
        return wi, dd, dd2

    def acceleration_rhs(self, qi, qj, vi, vj):
        A, U, N, P, d = self._frame(qi, qj)
        wi, dd, dd2 = self._rates(A, P, vi, vj)
        g1 = wi**2 * dot(N, d) + 2.0 * wi * dot(U, dd) - dot(N, dd2)
        return np.stack((g1, np.zeros_like(g1)), axis=-1)

    def reaction(self, lam, qi, qj):
        N = perp(turn(qi, self.u))  # the slide's normal: the frame's other parts unread
        n_force, couple = lam[..., 0], lam[..., 1]
        return {"Fx": n_force * N[..., 0], "Fy": n_force * N[..., 1], "N": n_force, "M": couple}

    def effort_force(self, effort, qi, qj):
        U = turn(qi, self.u)
        return {"Fx": effort * U[..., 0], "Fy": effort * U[..., 1]}

    def instant_centre(self, qi, qj):
        """At infinity normal to the slide: j translates along it relative to i."""
        return Pole(perp(turn(qi, self.u)), at_infinity=True)

    def relative_motion(self, qi, qj, vi, vj, ai, aj, labels):
        """j's sliding point P relative to i's point there: v_r = ṡ u along the slide;
        a_r = s̈ u and the Coriolis term a_k = 2 ω_i × v_r (zero where the guide is still)."""
        (li, lj), n = labels, self.point_name
        point = qj[:2] + turn(qj, self.p)
        u = turn(qi, self.u)
        speed = float(self.relative_speed(qi, qj, vi, vj))
        gi, gj = self.motion_direction(qi, qj)
        accel = float(gi @ ai + gj @ aj + self.coordinate_bias(qi, qj, vi, vj))
        axis = "".join(self.axis_names) if len(self.axis_names) == 2 else f"the axis of {self.name}"
        rel = f"{n}{lj}{n}{li}"
        return RelativeMotion(
            point,
            n,
            turns=False,
            velocity=(RelativeTerm(f"v_{rel}", speed * u, f"∥{axis}"),),
            acceleration=(
                RelativeTerm(f"a^r_{rel}", accel * u, f"∥{axis}"),
                RelativeTerm(
                    f"a^k_{rel}",
                    2.0 * float(vi[2]) * speed * perp(u),
                    f"⊥{axis}",
                    f"2·ω{li}·v_{rel}",
                    rate=False,
                ),
            ),
        )

    # -- compiled backend (base/kernels.py): the formulas above, position by position --
    residual_kernel = staticmethod(_residual_kernel)
    jacobian_kernel = staticmethod(_jacobian_kernel)
    gamma_kernel = staticmethod(_gamma_kernel)
    direction_kernel = staticmethod(_direction_kernel)
    bias_kernel = staticmethod(_bias_kernel)
    friction_kernel = staticmethod(_friction_kernel)
    whole_array_kernels = True  # plain arithmetic only: they also run over whole arrays

    def friction_kernel_params(self, k: int) -> np.ndarray | None:
        """(f, L) of the joint, L NaN without a contact length; None for variants."""
        if k != 1 or np.size(self.f) != 1 or np.size(self.length) > 1:
            return None
        length = np.nan if self.length is None else float(self.length)
        return np.array([[float(self.f), length]])

    # -- relative coordinate --------------------------------------------------
    def coordinate(self, qi, qj):
        A, U, N, P, d = self._frame(qi, qj)
        return dot(U, d)

    def motion_direction(self, qi, qj):
        A, U, N, P, d = self._frame(qi, qj)
        gi = np.concatenate((-U, (dot(N, d) - dot(U, perp(A)))[..., None]), axis=-1)
        gj = np.concatenate((U, dot(U, perp(P))[..., None]), axis=-1)
        return gi, gj

    def coordinate_bias(self, qi, qj, vi, vj):
        A, U, N, P, d = self._frame(qi, qj)
        wi, dd, dd2 = self._rates(A, P, vi, vj)
        return -(wi**2) * dot(U, d) + 2.0 * wi * dot(N, dd) + dot(U, dd2)

    # -- friction -----------------------------------------------------------
    friction_reads_poses: ClassVar[bool] = False  # f|N|, or f(|N₁| + |N₂|) at the edges

    @property
    def has_friction(self) -> bool:
        return bool(np.any(self.f > 0.0))

    def _edges(self, lam):
        half = 0.5 * lam[..., 0]
        return half + lam[..., 1] / self.length, half - lam[..., 1] / self.length

    def friction_magnitude(self, lam, qi, qj):
        if self.length is None:
            return self.f * np.abs(lam[..., 0])
        n1, n2 = self._edges(lam)
        return self.f * (np.abs(n1) + np.abs(n2))

    def friction_kinks(self, lam, qi, qj):
        if self.length is None:
            return lam[..., :1]
        return np.stack(self._edges(lam), axis=-1)

    def friction_gradient(self, lam, qi, qj):
        grad = np.zeros(lam.shape)
        if self.length is None:
            grad[..., 0] = self.f * np.sign(lam[..., 0])
        else:
            s1, s2 = (np.sign(n) for n in self._edges(lam))
            grad[..., 0] = 0.5 * self.f * (s1 + s2)
            grad[..., 1] = self.f * (s1 - s2) / self.length
        return grad

    def friction_constants(self):
        return (self.f,)

    # -- description ----------------------------------------------------------
    def anchors(self):
        i, j = self.links
        named = self.axis_names and self.axis_names[0]  # the axis point A (B's xy is not kept)
        axis = (Anchor(i, self.axis_names[0], self.a),) if named else ()
        return axis + (Anchor(j, self.point_name, self.p, at_joint=True),)

    def glyph(self, qi, qj):
        P = qj[..., :2] + turn(qj, self.p)
        U = turn(qi, self.u)
        A = qi[..., :2] + turn(qi, self.a)
        i, j = self.links
        return Glyph(point=P, block=Block(j, P, U, self.length), guide=Line(i, A, U))

    def label(self):
        return self.point_name

    def describe(self, tr=None):
        tr = tr or (lambda text, **values: text.format(**values))
        i, j = self.links
        axis = "–".join(n for n in self.axis_names if n)
        where = tr("axis {axis} of {i}, point {p} of {j}", axis=axis, i=i, p=self.point_name, j=j)
        if self.length:
            where += tr(", contact length {l} mm", l=f"{self.length * 1e3:.4g}")
        return {"where": where, "friction": f"f = {self.f:.4g}" if self.f else tr("none")}
