"""Revolute pair: a point of link i coincides with a point of link j."""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any, ClassVar

import numpy as np

from ..base.arrays import entry_major_zeros, same_fields
from ..base.geometry import perp, turn
from ..base.keys import NAME, NUMBER, Keys, enum, names
from .base import Anchor, Compiled, Friction, Glyph, Joint, Pole, Presentation
from .relative import RelativeMotion

_TURN_I, _TURN_J = np.array([0.0, 0.0, -1.0]), np.array([0.0, 0.0, 1.0])  # θ_j − θ_i
_TURN_I.flags.writeable = _TURN_J.flags.writeable = False

FRICTION_KEYS = Keys(
    {"radius": NUMBER, "journal_radius": NUMBER, "coefficient": NUMBER},
    # a journal radius with its coefficient (friction_radius); a coefficient alone takes
    # the diameter of the joint's bearing (the loader says so where there is none)
    extra={"dependentRequired": {"journal_radius": ["coefficient"]}},
)
# the sizing data of a pin joint (io/sizing.py reads them, docs/sizing.md)
BEARING_KEYS = Keys(
    {
        "type": enum(("ball", "roller", "plain")),
        "C": NUMBER,
        "width": NUMBER,
        "diameter": NUMBER,
        "p_max": NUMBER,
        "v_max": NUMBER,
        "pv_max": NUMBER,
    },
    required=("type",),
)
PIN_KEYS = Keys(
    {"diameter": NUMBER, "shear": enum(("single", "double")), "eye_width": NUMBER},
    required=("diameter",),
)

__all__ = ["Revolute"]


# -- kernels of the compiled backend (base/kernels.py) -------------------------------------
# The formulas of Revolute, position by position: the same operations in the same order, so
# the same numbers to the bit.  ``par[m]`` = (p_i, p_j) of joint m of a stack; P (n + 1, 5, N)
# the poses (x, y, θ, cos θ, sin θ), V (n + 1, 3, N) the rates, component-major; the
# friction kernel reads λ from ``x (N, n_λ)`` at its ``rows (k, 2)``, ``par[m]`` = (ρ,).
def _residual_kernel(par, P, ends, out):
    for m in range(ends.shape[1]):
        i, j = ends[0, m], ends[1, m]
        ax, ay, bx, by = par[m, 0], par[m, 1], par[m, 2], par[m, 3]
        for p in range(P.shape[2]):
            ci, si, cj, sj = P[i, 3, p], P[i, 4, p], P[j, 3, p], P[j, 4, p]
            out[m, 0, p] = P[i, 0, p] + (ci * ax - si * ay) - P[j, 0, p] - (cj * bx - sj * by)
            out[m, 1, p] = P[i, 1, p] + (si * ax + ci * ay) - P[j, 1, p] - (sj * bx + cj * by)


def _jacobian_kernel(par, P, ends, ji, jj):
    for m in range(ends.shape[1]):
        i, j = ends[0, m], ends[1, m]
        ax, ay, bx, by = par[m, 0], par[m, 1], par[m, 2], par[m, 3]
        for p in range(P.shape[2]):
            c, s = P[i, 3, p], P[i, 4, p]
            ji[m, 0, 0, p], ji[m, 0, 1, p], ji[m, 0, 2, p] = 1.0, 0.0, -(s * ax + c * ay)
            ji[m, 1, 0, p], ji[m, 1, 1, p], ji[m, 1, 2, p] = 0.0, 1.0, c * ax - s * ay
            c, s = P[j, 3, p], P[j, 4, p]
            jj[m, 0, 0, p], jj[m, 0, 1, p], jj[m, 0, 2, p] = -1.0, 0.0, s * bx + c * by
            jj[m, 1, 0, p], jj[m, 1, 1, p], jj[m, 1, 2, p] = 0.0, -1.0, -(c * bx - s * by)


def _gamma_kernel(par, P, V, ends, out):
    for m in range(ends.shape[1]):
        i, j = ends[0, m], ends[1, m]
        ax, ay, bx, by = par[m, 0], par[m, 1], par[m, 2], par[m, 3]
        for p in range(P.shape[2]):
            ci, si, cj, sj = P[i, 3, p], P[i, 4, p], P[j, 3, p], P[j, 4, p]
            wi, wj = V[i, 2, p] * V[i, 2, p], V[j, 2, p] * V[j, 2, p]
            out[m, 0, p] = (ci * ax - si * ay) * wi - (cj * bx - sj * by) * wj
            out[m, 1, p] = (si * ax + ci * ay) * wi - (sj * bx + cj * by) * wj


def _direction_kernel(par, P, ends, gi, gj):
    for m in range(ends.shape[1]):
        for p in range(P.shape[2]):
            gi[m, 0, p], gi[m, 1, p], gi[m, 2, p] = 0.0, 0.0, -1.0
            gj[m, 0, p], gj[m, 1, p], gj[m, 2, p] = 0.0, 0.0, 1.0


def _bias_kernel(par, P, V, ends, out):
    for m in range(ends.shape[1]):
        for p in range(P.shape[2]):
            out[m, p] = 0.0


def _friction_kernel(par, x, rows, out):
    for m in range(rows.shape[0]):
        a, b, rho = rows[m, 0], rows[m, 1], par[m, 0]
        for p in range(x.shape[0]):
            out[m, p] = rho * np.sqrt(x[p, a] * x[p, a] + x[p, b] * x[p, b])


def _bearing_radius(entry, f) -> float | None:
    """ρ = μ·d/2 of ``friction: {coefficient: μ}`` with the bore d of the joint's
    ``bearing:`` (a plain bearing's journal, a rolling bearing's bore: docs/sizing.md)."""
    b = entry.get("bearing")
    d = b.get("diameter") if b is not None and b.mapping() else None
    if d is None:
        f["coefficient"].error(
            "a friction coefficient alone needs the diameter of the joint's bearing "
            "(bearing: {diameter: ...}); else give journal_radius with it, or radius"
        )
        return None
    mu = f["coefficient"].coefficient()
    dv = d.number("length", minimum=0.0, strict=True)
    return None if mu is None or dv is None else mu * dv / 2.0


@dataclass(frozen=True)
class Revolute(Joint, Presentation, Friction, Compiled, kind="revolute"):
    """Pin joint.  ``p_i``, ``p_j``: the pin in each link's frame, relative to its CoM.

    Φ = r_i + A_i p_i − r_j − A_j p_j (2 rows).  λ is the constraint force on
    link i, so the reaction of i on j is ``F = −λ``.  Friction: the friction
    circle, a couple of magnitude ρ|F| opposing ω_j − ω_i.
    """

    __eq__ = same_fields  # arrays compared by value (base/arrays.py)

    n_eq: ClassVar[int] = 2
    reaction_labels: ClassVar[tuple[str, ...]] = ("Fx", "Fy")
    angular: ClassVar[bool] = True
    fixed_direction: ClassVar = (tuple(_TURN_I.tolist()), tuple(_TURN_J.tolist()))
    letter: ClassVar[str] = "R"
    reports_swing: ClassVar[bool] = True
    # links: two, or three or more sharing one pin (io/bodies.py), with as many points
    spec_keys: ClassVar[Keys] = Keys(
        {
            "type": NAME,
            "links": names(minimum=2),
            "points": names(minimum=2),
            "friction": FRICTION_KEYS,
            "bearing": BEARING_KEYS,
            "pin": PIN_KEYS,
        },
        required=("type", "links"),
        # a friction coefficient without a journal radius takes the bearing's diameter
        extra={
            "if": {
                "properties": {
                    "friction": {
                        "required": ["coefficient"],
                        "not": {"required": ["journal_radius"]},
                    }
                },
                "required": ["friction"],
            },
            "then": {
                "required": ["bearing"],
                "properties": {"bearing": {"required": ["diameter"]}},
            },
        },
    )
    pin: ClassVar[bool] = True

    stacked_vectors: ClassVar[tuple[str, ...]] = ("p_i", "p_j")
    friction_scalars: ClassVar[tuple[str, ...]] = ("rho",)
    friction_reads_poses: ClassVar[bool] = False  # ρ|F|

    p_i: np.ndarray = None
    p_j: np.ndarray = None
    point_names: tuple[str, str] = ("", "")
    rho: float = 0.0  # friction-circle radius, m

    # -- YAML ---------------------------------------------------------------
    @classmethod
    def from_spec(cls, name, entry, links, points):
        entry.check(cls.spec_keys)
        names = (name, name)
        if (e := entry.get("points")) is not None:
            names = tuple(e.names(2))
        p_i = entry.point(links[0], names[0], points, key="points", index=0)
        p_j = entry.point(links[1], names[1], points, key="points", index=1)
        rho = cls.friction_radius(entry)
        if p_i is None or p_j is None or rho is None:
            return None
        return cls(name, links, entry.where, p_i, p_j, names, float(rho))

    @staticmethod
    def friction_radius(entry) -> float | None:
        """ρ (m) of the entry's ``friction:`` (0 without one), or None where it is in error."""
        rho = 0.0
        if (f := entry.get("friction")) is not None:
            f.check(FRICTION_KEYS)
            if f.get("radius") is not None:
                if f.get("journal_radius") is not None or f.get("coefficient") is not None:
                    f.error("give either radius, or journal_radius with coefficient")
                rho = f["radius"].number("length", minimum=0.0)
            elif f.get("journal_radius") is None and f.get("coefficient") is not None:
                rho = _bearing_radius(entry, f)
            elif f.get("journal_radius") is not None or f.get("coefficient") is not None:
                r = f.require("journal_radius").number("length", minimum=0.0)
                fv = f.require("coefficient").coefficient()
                rho = None if r is None or fv is None else r * fv
            else:
                f.error(
                    "give radius (the friction-circle radius), or journal_radius and coefficient"
                )
        return rho

    def to_spec(self) -> dict[str, Any]:
        spec: dict[str, Any] = {"points": list(self.point_names)}
        if self.rho:
            spec["friction"] = {"radius": self.rho}
        return spec

    # -- kinematics ---------------------------------------------------------
    def residual(self, qi, qj):
        return qi[..., :2] + turn(qi, self.p_i) - qj[..., :2] - turn(qj, self.p_j)

    def jacobian(self, qi, qj):
        shape = np.broadcast_shapes(qi.shape, qj.shape)[:-1] + (2, 3)
        ji, jj = entry_major_zeros(shape), entry_major_zeros(shape)
        ji[..., 0, 0] = ji[..., 1, 1] = 1.0
        jj[..., 0, 0] = jj[..., 1, 1] = -1.0
        ji[..., :, 2] = perp(turn(qi, self.p_i))
        jj[..., :, 2] = -perp(turn(qj, self.p_j))
        return ji, jj

    def acceleration_rhs(self, qi, qj, vi, vj):
        return turn(qi, self.p_i) * vi[..., 2:3] ** 2 - turn(qj, self.p_j) * vj[..., 2:3] ** 2

    def reaction(self, lam, qi, qj):
        return {"Fx": -lam[..., 0], "Fy": -lam[..., 1]}

    def instant_centre(self, qi, qj):
        """The pin: both links' points there have one velocity."""
        return Pole(qj[..., :2] + turn(qj, self.p_j))

    def relative_motion(self, qi, qj, vi, vj, ai, aj, labels):
        """The pins coincide: no relative term; the links turn relative to each other."""
        return RelativeMotion(qj[:2] + turn(qj, self.p_j), self.point_names[1], turns=True)

    # -- compiled backend (base/kernels.py): the formulas above, position by position --
    residual_kernel = staticmethod(_residual_kernel)
    jacobian_kernel = staticmethod(_jacobian_kernel)
    gamma_kernel = staticmethod(_gamma_kernel)
    direction_kernel = staticmethod(_direction_kernel)
    bias_kernel = staticmethod(_bias_kernel)
    friction_kernel = staticmethod(_friction_kernel)
    whole_array_kernels = True  # plain arithmetic only: they also run over whole arrays

    # -- relative coordinate --------------------------------------------------
    def coordinate(self, qi, qj):
        return qj[..., 2] - qi[..., 2]

    def motion_direction(self, qi, qj):
        # θ_j − θ_i: the same at every position, so read-only views of one row (nothing
        # allocated or written per position)
        shape = np.broadcast_shapes(qi.shape[:-1], qj.shape[:-1]) + (3,)
        return np.broadcast_to(_TURN_I, shape), np.broadcast_to(_TURN_J, shape)

    # -- friction -----------------------------------------------------------
    @property
    def has_friction(self) -> bool:
        return bool(np.any(self.rho > 0.0))

    def friction_magnitude(self, lam, qi, qj):
        # |F| as √(Fx² + Fy²), not np.hypot (~2.3× slower, and evaluated at every iteration
        # of the friction fixed point): the two differ by an ulp, and the squares overflow
        # only for a reaction above 1e154 N
        fx, fy = lam[..., 0], lam[..., 1]
        return self.rho * np.sqrt(fx * fx + fy * fy)

    def friction_gradient(self, lam, qi, qj):
        norm = np.hypot(lam[..., 0], lam[..., 1])[..., None]
        return self.rho * np.divide(lam, norm, out=np.zeros_like(lam), where=norm > 0)

    def friction_constants(self):
        return (self.rho,)

    # -- description ----------------------------------------------------------
    def anchors(self):
        i, j = self.links
        return (
            Anchor(i, self.point_names[0], self.p_i, at_joint=True),
            Anchor(j, self.point_names[1], self.p_j, at_joint=True),
        )

    def coincident(self):
        return (self.anchors(),)

    def glyph(self, qi, qj):
        return Glyph(point=qj[..., :2] + turn(qj, self.p_j))

    def describe(self, tr=None):
        tr = tr or (lambda text, **values: text.format(**values))
        i, j = self.links
        a, b = self.point_names
        return {
            "where": tr("{a} on {i}, {b} on {j}", a=a, i=i, b=b, j=j),
            "friction": tr("friction circle ρ = {rho} mm", rho=f"{self.rho * 1e3:.4g}")
            if self.rho
            else tr("none"),
        }
