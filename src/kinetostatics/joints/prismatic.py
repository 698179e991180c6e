"""Prismatic pair: a point of link j slides along an axis of link i."""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any, ClassVar

import numpy as np

from ..base.arrays import entry_major_zeros
from ..base.geometry import dot, perp, turn, wrap_angle
from ..base.keys import NAME, NUMBER, Keys, names
from .base import AXIS_KEYS, Anchor, Block, Glyph, Joint, Line

FRICTION_KEYS = Keys({"coefficient": NUMBER}, required=("coefficient",))

__all__ = ["Prismatic"]


@dataclass(frozen=True)
class Prismatic(Joint, kind="prismatic"):
    """Slider.  The axis belongs to link i: point ``a`` and unit ``u`` (local, ``a``
    relative to i's CoM); ``p`` is the sliding point of link j (relative to j's CoM).

    Φ₁ = n·(P_j − A_i) (P_j on the axis, n = u rotated +90°),
    Φ₂ = θ_j − θ_i − ``angle`` (no relative rotation).
    λ₁ = N, the force of i on j along n; λ₂ = M, the couple of i on j about P_j.
    Relative coordinate s = (P_j − A_i)·u.  Coulomb friction f|N| along u opposes ṡ;
    with ``length`` L the block bears on two edges, N₁,₂ = N/2 ± M/L, and the
    friction is f(|N₁| + |N₂|).
    """

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
            f = fr["coefficient"].number(None, minimum=0.0) if fr.get("coefficient") else 0.0
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
        A, U, N, P, d = self._frame(qi, qj)
        n_force, couple = lam[..., 0], lam[..., 1]
        return {"Fx": n_force * N[..., 0], "Fy": n_force * N[..., 1], "N": n_force, "M": couple}

    def effort_force(self, effort, qi, qj):
        U = turn(qi, self.u)
        return {"Fx": effort * U[..., 0], "Fy": effort * U[..., 1]}

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
