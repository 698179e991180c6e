r"""Cam and follower: a disc cam on link i touches a follower on link j.

A higher pair with contact (one row of Φ, one reaction: the contact force along
the profile's normal).  The profile is synthesised from the follower's motion law
s(θ) over the cam angle θ (``_camlaw.py``) and its placement in the frame
(``_camprofile.py``: frame, cam angle, signs); ``docs/extending.md`` walks through
the derivation.

Relative pose
-------------
Everything depends on the pose of the follower in the cam's frame:
z = A_iᵀ(r_j + A_j p − r_i − A_i o) (p the follower point of link j, o the cam
centre on link i) and φ = θ_j − θ_i.  A scalar F(z, φ) with gradient g and Hessian
H gives the Jacobian rows by the chain rule (∂z/∂r_j = A_iᵀ, ∂z/∂θ_j = A_iᵀ perp(A_j p),
∂z/∂r_i = −A_iᵀ, ∂z/∂θ_i = −perp(z) − perp(o)) and its velocity-product part
g·z̈_v + żᵀHż with ż = A_iᵀḋ − ω_i perp(z),
z̈_v = A_iᵀd̈_v − ω_i perp(A_iᵀḋ) − ω_i perp(ż), d̈_v = −ω_j² A_j p + ω_i² A_i o.

Knife edge and roller
---------------------
The follower point P (knife tip, roller centre) stays on the pitch curve, in polar
form ρ = R(ψ) about the cam centre (ψ its polar angle, R from the law by
inverting ψ(θ) with Newton's method):

    Φ = ρ − R(ψ),   ∇Φ = e − R′ t/ρ    (e = z/ρ, t = perp(e))

∇Φ is the pitch curve's outward normal, so λ∇Φ applied at P is the contact force:
F = λ|∇Φ| (> 0: the cam pushes), its line through the roller's contact point.
Sliding: the coordinate c = S(ψ) + (R′/S′)Φ − r φ (S the pitch curve's arc length,
S′ = √(R² + R′²)); the term (R′/S′)Φ cancels the normal part of ∇c on the contact, so
∇c is the unit tangent there: an effort along c is a tangential force at the contact
point (−r φ moves it from P to the roller's rim).  For a roller, ``friction`` is
the equivalent coefficient of its bearing, μ_pin r_pin / r.

Flat face
---------
The face (outward normal N, angle ν = φ + angle of N in j) stays on the
profile's support line: Φ = N·z − h(ν), ∇_z Φ = N, ∂Φ/∂φ = T·z − h′ (T = perp(N)):
the force λN at the contact point X = hN + h′T; F = λ.  Sliding: c = −(T·z + ∫h dν).

Results: ``<joint>.cam_angle`` θ of the contact, the law there (``lift`` s and its
θ-derivatives ``lift_d1``–``lift_d3``, jerk from the law), ``pressure_angle`` α
(between the contact normal and the velocity of the follower's point at the
contact, positive when the normal is turned from that velocity in the cam's sense
of rotation: tan α = (s′ − e)/(s + √(r_p² − e²)) for a translating follower),
``curvature_radius`` of the profile at the contact, ``status`` 1 where the contact
force would pull (the follower leaves the cam; a spring or preload must keep it closed).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from functools import wraps
from typing import Any, ClassVar

import numpy as np

from ..base.arrays import same_fields
from ..base.geometry import dot, perp, rotate, turn, turn_back
from ..base.keys import NAME, NUMBER, VECTOR, Keys, enum, names
from . import _camphase
from ._camdesign import ProfileDesign
from ._camlaw import LAW_SHAPE, read_law
from ._camprofile import Synthesis
from ._camrelative import cam_motion
from ._camspec import _DESIGN, _OSCILLATING, _SENSE, _TRANSLATING, SENSES, allowed_angle, placement
from .base import (
    Anchor,
    Circle,
    Curve,
    Friction,
    Glyph,
    Joint,
    Line,
    Pole,
    Presentation,
    Shaped,
)

__all__ = ["Cam"]

FOLLOWERS = ("knife", "roller", "flat")


def _outer(a, b):
    return a[..., :, None] * b[..., None, :]


def _kept(name):
    """A method of the poses (qi, qj) whose result is kept for the last poses (read-only
    arrays): a position solve asks for Φ and its Jacobian at the same poses, the friction
    solution for the normal at each iteration; each costs an inversion of the profile."""

    def wrap(f):
        @wraps(f)
        def kept(self, qi, qj):
            qi, qj = np.asarray(qi, float), np.asarray(qj, float)
            key = (qi.shape, qj.shape, qi.tobytes(), qj.tobytes())
            hit = self._memo.get(name)
            if hit is None or hit[0] != key:
                out = f(self, qi, qj)
                for a in out:
                    if isinstance(a, np.ndarray):
                        a.flags.writeable = False
                self._memo[name] = hit = (key, out)
            return hit[1]

        return kept

    return wrap


@dataclass(frozen=True)
class Cam(Joint, Presentation, Friction, Shaped, kind="cam"):
    """Disc cam (link i, centre ``o``) and follower (link j, point ``p``); ``synthesis``
    the law and the follower's placement; ``face`` (flat) the face normal in j's
    frame towards the cam; ``f`` the friction coefficient; ``allowed`` the allowable
    pressure angle [α] of its design (rad; ``design: {pressure_angle_max}``), None: not
    given (the design takes the textbook's 30°)."""

    __eq__ = same_fields  # arrays compared by value (base/arrays.py)

    n_eq: ClassVar[int] = 1
    reaction_labels: ClassVar[tuple[str, ...]] = ("F", "Fx", "Fy")
    angular: ClassVar[bool] = False  # the coordinate is a sliding distance
    letter: ClassVar[str] = "C"
    spec_keys: ClassVar[Keys] = Keys(
        {
            "type": NAME,
            "links": names(2),
            "centre": NAME,
            "point": NAME,
            "follower": enum(FOLLOWERS),
            "base_radius": NUMBER,
            "motion": LAW_SHAPE,
            "radius": NUMBER,
            "face_normal": VECTOR,
            "rotation": _SENSE,
            "translating": _TRANSLATING,
            "oscillating": _OSCILLATING,
            "friction": Keys({"coefficient": NUMBER}, required=("coefficient",)),
            "design": _DESIGN,
        },
        required=("type", "links", "centre", "point", "follower", "base_radius", "motion"),
    )

    o: np.ndarray = None
    p: np.ndarray = None
    names: tuple[str, str] = ("", "")
    synthesis: Synthesis = None
    face: np.ndarray | None = None
    f: float = 0.0
    allowed: float | None = None
    _memo: dict = field(default_factory=dict, init=False, repr=False, compare=False)

    # -- YAML -----------------------------------------------------------------
    @classmethod
    def from_spec(cls, name, entry, links, points):
        entry.check(cls.spec_keys)
        cname = entry.require("centre").names(1)[0]
        pname = entry.require("point").names(1)[0]
        o = entry.point(links[0], cname, points, key="centre")
        p = entry.point(links[1], pname, points, key="point")
        kind = entry.require("follower").text()
        if kind is not None and kind not in FOLLOWERS:
            entry["follower"].error(f"follower must be knife, roller or flat, got '{kind}'")
            kind = None
        radius = 0.0
        if kind == "roller":
            radius = entry.require("radius").number("length", minimum=0.0, strict=True)
        elif entry.get("radius") is not None:
            entry["radius"].error("only a roller follower has a radius")
        face = None
        if kind == "flat":
            v = entry.require("face_normal").vector(None)
            face = None if v is None else entry["face_normal"].unit(v)
        base = entry.require("base_radius").number("length", minimum=0.0, strict=True)
        sigma = 1
        if (r := entry.get("rotation")) is not None:
            sigma = SENSES.get(r.text() or "", 0)
            if not sigma:
                r.error("rotation must be ccw or cw (the cam's sense for increasing cam angle)")
        place = placement(entry, kind)
        law = read_law(entry.require("motion"), "angle" if place and place[2] else "length")
        friction = 0.0
        if (fr := entry.get("friction")) is not None:
            fr.check_keys(required=("coefficient",))
            friction = fr["coefficient"].coefficient() if fr.get("coefficient") else None
        allowed = allowed_angle(entry.get("design"))
        if any(v is None for v in (o, p, kind, radius, base, place, law, friction)) or not sigma:
            return None
        if kind == "flat" and face is None or allowed is False:
            return None
        direction, offset, pivot, arm, kappa = place
        syn = Synthesis(law, kind, radius, base, sigma, direction, offset, pivot, arm, kappa)
        joint = cls(
            name, links, entry.where, o, p, (cname, pname), syn, face, float(friction), allowed
        )
        problem = joint._problem()
        if problem:
            entry["motion"].error(f"cam joint '{name}': {problem}")
            return None
        return joint

    def to_spec(self) -> dict[str, Any]:
        s = self.synthesis
        spec: dict[str, Any] = {
            "centre": self.names[0],
            "point": self.names[1],
            "follower": s.follower,
            "base_radius": s.base,
            "rotation": "ccw" if s.sigma > 0 else "cw",
            "motion": s.law.to_spec(),
        }
        if s.follower == "roller":
            spec["radius"] = s.radius
        if self.face is not None:
            spec["face_normal"] = [float(x) for x in self.face]
        if s.pivot is None:
            spec["translating"] = {"direction": list(s.direction), "offset": s.offset}
        else:
            osc: dict[str, Any] = {"pivot": list(s.pivot), "rise": "ccw" if s.kappa > 0 else "cw"}
            osc.update({"offset": s.offset} if s.flat else {"arm": s.arm})
            spec["oscillating"] = osc
        if self.f:
            spec["friction"] = {"coefficient": self.f}
        if self.allowed is not None:
            spec["design"] = {"pressure_angle_max": self.allowed}
        return spec

    # -- the phase at the start ------------------------------------------------------
    def start_problem(self, qi, qj) -> str:
        return _camphase.start_problem(self, qi, qj)

    def profile_design(self) -> ProfileDesign:
        return ProfileDesign(self.synthesis, self.allowed)

    # -- the profile ------------------------------------------------------------
    def _problem(self) -> str:
        """Why this cam cannot be made ('' if it can): placement, inversion, undercut."""
        s = self.synthesis
        if s.placement_problem():
            return s.placement_problem()
        if isinstance(s.inversion, str):
            return s.inversion
        th = s.check_grid
        rc = s.curvature(th)
        bad = np.nonzero((rc <= 0) & (rc > -s.radius))[0] if not s.flat else np.nonzero(rc <= 0)[0]
        if s.follower == "knife":
            bad = bad[:0]
        if bad.size:
            worst = bad[np.argmin(rc[bad])]
            what = "cusp" if s.follower == "flat" else "undercut"
            return (
                f"the profile is {what} at cam angle {math.degrees(th[worst]):.4g}°"
                f"{s.law.where(th[worst], s.pivot is not None)} "
                f"(radius of curvature {rc[worst] * 1e3:.4g} mm, {bad.size} of "
                f"{len(th)} sampled angles): a larger base circle"
                + (" or a smaller roller" if s.follower == "roller" else "")
                + " or a gentler law"
            )
        return ""

    @property
    def _tables(self):
        return self.synthesis.inversion

    def _polar(self, psi):
        """(θ, turns, R, R′, R″, R‴) of the pitch curve at polar angles ψ."""
        s = self.synthesis
        theta, turns = s.invert(self._tables, psi)
        r, P = s.pitch(theta)
        a1, a2, a3, L1, L2, L3 = r[1], r[2], r[3], r[5], r[6], r[7]
        Lp = L1 / a1
        Lpp = (L2 - Lp * a2) / a1**2
        Lppp = (L3 - 3 * Lpp * a1 * a2 - Lp * a3) / a1**3
        R = np.abs(P)
        return theta, turns, R, R * Lp, R * (Lpp + Lp**2), R * (Lppp + 3 * Lp * Lpp + Lp**3)

    def _support(self, nu):
        """(θ, turns, h, h′, h″) of the profile at face-normal angles ν (cam frame)."""
        s = self.synthesis
        theta, turns = s.invert(self._tables, nu)
        _, nu1, nu2, h, h1, h2 = s.support(theta)
        hv = h1 / nu1
        return theta, turns, h, hv, (h2 - hv * nu2) / nu1**2

    # -- the relative pose and the scalar functions of it -----------------------------
    def _pose(self, qi, qj):
        Ao = turn(qi, self.o)
        Ap = turn(qj, self.p)
        d = qj[..., :2] + Ap - qi[..., :2] - Ao
        return Ao, Ap, d, turn_back(qi, d), qj[..., 2] - qi[..., 2]

    def _face_angle(self, phi):
        return phi + math.atan2(-self.face[1], -self.face[0])

    def __getstate__(self):  # the poses kept stay behind: the pickle is the model's key
        return dict(self.__dict__, _memo={})

    @_kept("phi")
    def _phi(self, qi, qj):
        """Φ: (value, ∇_z, ∂/∂φ, H_zz, H_zφ, H_φφ)."""
        Ao, Ap, d, z, phi = self._pose(qi, qj)
        if self.synthesis.flat:
            nu = self._face_angle(phi)
            N = np.stack((np.cos(nu), np.sin(nu)), axis=-1)
            T = perp(N)
            _, _, h, h1, h2 = self._support(nu)
            zero = np.zeros(z.shape[:-1] + (2, 2))
            return dot(N, z) - h, N, dot(T, z) - h1, zero, T, -dot(N, z) - h2
        rho = np.hypot(z[..., 0], z[..., 1])
        e = z / rho[..., None]
        t = perp(e)
        _, _, R, R1, R2, _ = self._polar(np.arctan2(z[..., 1], z[..., 0]))
        tt = _outer(t, t)
        Hpsi = -(_outer(e, t) + _outer(t, e)) / (rho**2)[..., None, None]
        H = (
            tt / rho[..., None, None]
            - (R2 / rho**2)[..., None, None] * tt
            - R1[..., None, None] * Hpsi
        )
        g = e - (R1 / rho)[..., None] * t
        zero = np.zeros(rho.shape)
        return rho - R, g, zero, H, np.zeros(z.shape), zero

    @_kept("coord")
    def _coord(self, qi, qj):
        """c: (value, ∇_z, ∂/∂φ, H_zz, H_zφ, H_φφ)."""
        Ao, Ap, d, z, phi = self._pose(qi, qj)
        s = self.synthesis
        if s.flat:
            nu = self._face_angle(phi)
            N = np.stack((np.cos(nu), np.sin(nu)), axis=-1)
            T = perp(N)
            theta, turns, h, h1, _ = self._support(nu)
            H = s.integral(self._tables, theta, turns)
            zero = np.zeros(z.shape[:-1] + (2, 2))
            return -(dot(T, z) + H), -T, dot(N, z) - h, zero, N, dot(T, z) - h1
        rho = np.hypot(z[..., 0], z[..., 1])
        e = z / rho[..., None]
        t = perp(e)
        psi_u = np.arctan2(d[..., 1], d[..., 0]) - qi[..., 2]  # carries the cam's turns
        theta, turns, R, R1, R2, R3 = self._polar(psi_u)
        S = s.integral(self._tables, theta, turns)
        S1 = np.hypot(R, R1)
        S2 = R1 * (R + R2) / S1
        S3 = (R2 * (R + R2) + R1 * (R1 + R3)) / S1 - R1 * (R + R2) * S2 / S1**2
        m, m1 = R1 / S1, (R2 * S1 - R1 * S2) / S1**2
        m2 = (R3 * S1 - R1 * S3) / S1**2 - 2 * m1 * S2 / S1
        Phi = rho - R
        gpsi = t / rho[..., None]
        gphi = e - (R1 / rho)[..., None] * t
        Hpsi = -(_outer(e, t) + _outer(t, e)) / (rho**2)[..., None, None]
        tt = _outer(t, t)
        HPhi = (
            tt / rho[..., None, None]
            - (R2 / rho**2)[..., None, None] * tt
            - R1[..., None, None] * Hpsi
        )
        a = S1 + m1 * Phi
        g = a[..., None] * gpsi + m[..., None] * gphi
        H = (
            (S2 + m2 * Phi)[..., None, None] * _outer(gpsi, gpsi)
            + a[..., None, None] * Hpsi
            + m1[..., None, None] * (_outer(gpsi, gphi) + _outer(gphi, gpsi))
            + m[..., None, None] * HPhi
        )
        r = s.radius
        zero = np.zeros(rho.shape)
        return S + m * Phi - r * phi, g, zero - r, H, np.zeros(z.shape), zero

    def _rows(self, qi, qj, gz, gphi):
        """(∂F/∂q_i, ∂F/∂q_j), each (..., 3), from F's gradient in (z, φ)."""
        Ao, Ap, d, z, phi = self._pose(qi, qj)
        G = turn(qi, gz)
        jj = np.concatenate((G, (dot(G, perp(Ap)) + gphi)[..., None]), axis=-1)
        ti = dot(gz, -perp(z) - perp(np.broadcast_to(self.o, z.shape))) - gphi
        ji = np.concatenate((-G, ti[..., None]), axis=-1)
        return ji, jj

    def _second(self, qi, qj, vi, vj, parts):
        """The velocity-product part of F̈: g·z̈_v + żᵀHż."""
        _, gz, gphi, Hzz, Hzp, Hpp = parts
        Ao, Ap, d, z, phi = self._pose(qi, qj)
        wi, wj = vi[..., 2], vj[..., 2]
        dd = vj[..., :2] + wj[..., None] * perp(Ap) - vi[..., :2] - wi[..., None] * perp(Ao)
        ddv = -(wj**2)[..., None] * Ap + (wi**2)[..., None] * Ao
        dl = turn_back(qi, dd)
        zd = dl - wi[..., None] * perp(z)
        zddv = turn_back(qi, ddv) - wi[..., None] * (perp(dl) + perp(zd))
        pd = wj - wi
        quad = np.einsum("...a,...ab,...b->...", zd, Hzz, zd) + 2 * pd * dot(Hzp, zd) + Hpp * pd**2
        return dot(gz, zddv) + quad

    # -- the contract ---------------------------------------------------------------
    def residual(self, qi, qj):
        return self._phi(qi, qj)[0][..., None]

    def jacobian(self, qi, qj):
        _, gz, gphi, *_ = self._phi(qi, qj)
        ji, jj = self._rows(qi, qj, gz, gphi)
        return ji[..., None, :], jj[..., None, :]

    def acceleration_rhs(self, qi, qj, vi, vj):
        return -self._second(qi, qj, vi, vj, self._phi(qi, qj))[..., None]

    @_kept("normal")
    def _normal(self, qi, qj):
        """|∇_z Φ| (1 for a flat face) and ∇_z Φ in global axes."""
        gz = self._phi(qi, qj)[1]
        return np.hypot(gz[..., 0], gz[..., 1]), turn(qi, gz)

    def reaction(self, lam, qi, qj):
        size, G = self._normal(qi, qj)
        f = lam[..., 0]
        return {"F": f * size, "Fx": f * G[..., 0], "Fy": f * G[..., 1]}

    def coordinate(self, qi, qj):
        return self._coord(qi, qj)[0]

    def motion_direction(self, qi, qj):
        _, gz, gphi, *_ = self._coord(qi, qj)
        return self._rows(qi, qj, gz, gphi)

    def coordinate_bias(self, qi, qj, vi, vj):
        return self._second(qi, qj, vi, vj, self._coord(qi, qj))

    def effort_force(self, effort, qi, qj):
        _, gz, *_ = self._coord(qi, qj)
        G = turn(qi, gz)
        return {"Fx": effort * G[..., 0], "Fy": effort * G[..., 1]}

    # -- friction: f |F| along the tangent ---------------------------------------------
    @property
    def has_friction(self) -> bool:
        return self.f > 0.0

    def friction_magnitude(self, lam, qi, qj):
        return self.f * np.abs(lam[..., 0]) * self._normal(qi, qj)[0]

    def friction_kinks(self, lam, qi, qj):
        return lam[..., :1]

    def motion_breaks(self, qi, qj):
        """sin(θ − b) for the law's breaks b (θ the contact's cam angle): through zero at
        every segment end (and half a turn on, a harmless extra cut)."""
        b = np.unique(np.mod(self.synthesis.law.breaks, 2 * math.pi))
        return np.sin(self._contact(qi, qj)[0][..., None] - b)

    def friction_gradient(self, lam, qi, qj):
        return (self.f * np.sign(lam[..., 0]) * self._normal(qi, qj)[0])[..., None]

    def friction_constants(self) -> tuple:
        return (self.f,)

    def shape_constants(self) -> tuple:
        return (self.o, self.p, self.face, self.synthesis)  # the profile's tables: scalars

    # -- what the outputs ask ----------------------------------------------------------
    def _contact(self, qi, qj):
        """(θ, contact point X, unit normal n, follower point, all in the cam's frame)."""
        Ao, Ap, d, z, phi = self._pose(qi, qj)
        s = self.synthesis
        if s.flat:
            nu = self._face_angle(phi)
            N = np.stack((np.cos(nu), np.sin(nu)), axis=-1)
            theta, _, h, h1, _ = self._support(nu)
            return theta, h[..., None] * N + h1[..., None] * perp(N), N, z
        gz = self._phi(qi, qj)[1]
        n = gz / np.hypot(gz[..., 0], gz[..., 1])[..., None]
        theta = s.invert(self._tables, np.arctan2(z[..., 1], z[..., 0]))[0]
        return theta, z - s.radius * n, n, z

    def instant_centre(self, qi, qj):
        """Only the common normal at the contact: the centre lies on it, where Kennedy's
        theorem puts it (the relative velocity at the contact is along the tangent)."""
        theta, X, n, z = self._contact(qi, qj)
        return Pole(qi[..., :2] + turn(qi, self.o) + turn(qi, X), along=turn(qi, n))

    def relative_motion(self, qi, qj, vi, vj, ai, aj, labels):
        """The equivalent lower pairs' terms at the contact (``_camrelative.py``): a knife's
        or roller's point along the pitch curve, a flat face's centre of curvature along
        the face."""
        return cam_motion(self, qi, qj, vi, vj, ai, aj, labels)

    def anchors(self):
        i, j = self.links
        return (Anchor(i, self.names[0], self.o), Anchor(j, self.names[1], self.p))

    def glyph(self, qi, qj):
        """The contact point; the profile (and pitch curve) on the cam, the roller or face."""
        i, j = self.links
        theta, X, n, z = self._contact(qi, qj)
        c, sn = np.cos(qi[..., 2]), np.sin(qi[..., 2])
        rot = np.stack((np.stack((c, -sn), -1), np.stack((sn, c), -1)), -2)  # (..., 2, 2)
        base = qi[..., :2] + turn(qi, self.o)
        point = base + turn(qi, X)
        curves = tuple(
            Curve(i, base[..., None, :] + np.einsum("...ab,nb->...na", rot, pts))
            for pts in self.synthesis.outline
        )
        P = qj[..., :2] + turn(qj, self.p)
        s = self.synthesis
        if s.flat:
            T = turn(qi, perp(n))
            return Glyph(point=point, curves=curves, lines=(Line(j, P, T),))
        circles = (Circle(j, P, s.radius),) if s.radius else ()
        return Glyph(point=point, curves=curves, circles=circles)

    def label(self):
        return self.name

    def describe(self, tr=None):
        tr = tr or (lambda text, **values: text.format(**values))
        s = self.synthesis
        i, j = self.links
        follower = {
            "knife": tr("knife-edge"),
            "roller": tr("roller r = {r} mm", r=f"{s.radius * 1e3:.4g}"),
        }.get(s.follower, tr("flat-faced"))
        where = tr(
            "cam {i} (centre {c}, base radius {rb} mm, turning {sense}), {motion} {follower} "
            "follower {j} at {p}",
            i=i,
            c=self.names[0],
            rb=f"{s.base * 1e3:.4g}",
            sense="ccw" if s.sigma > 0 else "cw",
            motion=tr("oscillating" if s.pivot is not None else "translating"),
            follower=follower,
            j=j,
            p=self.names[1],
        )
        return {
            "where": where,
            "friction": tr("f = {f}", f=f"{self.f:.4g}") if self.f else tr("none"),
        }

    def columns(self, qi, qj, lam=None):
        s = self.synthesis
        theta, X, n, z = self._contact(qi, qj)
        lift = s.law.value(theta)
        unit = ("m", "m/rad", "m/rad^2", "m/rad^3")
        if s.pivot is not None:
            unit = ("rad", "1", "1/rad", "1/rad^2")
        # the velocity of the follower's point (a roller's centre, a face's contact point)
        # in the frame, turned into the cam's frame
        Xf = rotate(s.sigma * theta, X if s.flat else z)
        if s.pivot is None:
            m = np.broadcast_to(np.asarray(s.direction, float), Xf.shape)
        else:
            m = s.kappa * perp(Xf - np.asarray(s.pivot, float))
        m = rotate(-s.sigma * theta, m)
        alpha = s.sigma * np.arctan2(m[..., 0] * n[..., 1] - m[..., 1] * n[..., 0], dot(m, n))
        out = {
            "cam_angle": ("deg", np.degrees(np.mod(theta, 2 * math.pi))),
            "lift": (unit[0], lift[0]),
            "lift_d1": (unit[1], lift[1]),
            "lift_d2": (unit[2], lift[2]),
            "lift_d3": (unit[3], lift[3]),
            "pressure_angle": ("deg", np.degrees(alpha)),
            "curvature_radius": ("m", s.curvature(theta)),
        }
        if lam is not None:
            out["status"] = ("1", (lam[..., 0] < 0).astype(float))
        return out

    def warnings(self, lam, qi, qj):
        return _camphase.warnings(self, lam, qi, qj)
