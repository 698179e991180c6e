r"""The follower motion law of a ``cam`` pair: the lift s(θ) over the cam angle θ.

A law is a list of segments covering one turn (``rise``, ``dwell``, ``return``),
each rise or return following a normalised curve y(u) over u = (θ − θ₀)/β ∈ [0, 1]
(y(0) = 0, y(1) = 1), or a periodic table of lifts.  The derivatives with respect
to θ are exact (``d1`` … ``d3``: ds/dθ, d²s/dθ², d³s/dθ³ — the cam's geometric
velocity, acceleration and jerk; at a constant cam speed ω the follower's are
ω s', ω² s'' and ω³ s''').

    harmonic     y = (1 − cos πu)/2                 (s'' jumps at the ends)
    cycloidal    y = u − sin(2πu)/(2π)               (s'' continuous, s''' jumps)
    polynomial   y = 10u³ − 15u⁴ + 6u⁵              (3-4-5: s'' continuous)
    polynomial7  y = 35u⁴ − 84u⁵ + 70u⁶ − 20u⁷       (4-5-6-7: s''' continuous)

A rise of h over β gives s = s₀ + h y(u), s' = h y'/β, s'' = h y''/β², s''' = h y'''/β³;
a return s = s₀ − h y(u).  The lift starts at 0 at θ = 0 and the segments must
end where they began (as much return as rise, spans adding to 360°).

A table (``angle``, ``lift``) is interpolated by a periodic quintic spline (C⁴:
exact and continuous derivatives up to the jerk).  These are the cam's own laws
(in the cam angle); the time laws of a driver are ``model/motion.py``, a layer
above the joints.
"""

from __future__ import annotations

import bisect
import math
from dataclasses import dataclass, field

import numpy as np

from ..base.keys import NUMBER, Keys, enum, list_of, one_of

__all__ = ["CamLaw", "Segment", "CURVES", "LAW_SHAPE", "read_law"]

TWO_PI = 2.0 * math.pi
PI = math.pi
SNAP = 1e-12  # rad: angles this close to a segment's end are at it
SMALL = 8  # up to this many angles are evaluated one by one, in Python floats


def _harmonic(u, m=np):
    s, c = m.sin(PI * u), m.cos(PI * u)
    return 0.5 * (1.0 - c), 0.5 * PI * s, 0.5 * PI**2 * c, -0.5 * PI**3 * s


def _cycloidal(u, m=np):
    s, c = m.sin(TWO_PI * u), m.cos(TWO_PI * u)
    return u - s / TWO_PI, 1.0 - c, TWO_PI * s, TWO_PI**2 * c


def _poly(coef):
    p = np.polynomial.Polynomial(coef)
    ds = [tuple(float(c) for c in p.deriv(n).coef) for n in range(4)]

    def horner(c, u):  # NumPy's polyval, also on a Python float
        out = c[-1]
        for ck in c[-2::-1]:
            out = ck + out * u
        return out

    return lambda u, m=np: tuple(horner(c, u) for c in ds)


# y(u) and its derivatives y', y'', y''' of each curve: on an array (sin and cos of NumPy),
# or on a Python float with ``m=math``
CURVES = {
    "harmonic": _harmonic,
    "cycloidal": _cycloidal,
    "polynomial": _poly([0, 0, 0, 10, -15, 6]),
    "polynomial7": _poly([0, 0, 0, 0, 35, -84, 70, -20]),
}
KINDS = ("rise", "dwell", "return")


def _moving(kind: str) -> Keys:
    return Keys({kind: NUMBER, "over": NUMBER, "law": enum(CURVES)}, (kind, "over"))


LAW_SHAPE = one_of(  # ``motion:`` of a cam joint, for the JSON Schema
    list_of(one_of(_moving("rise"), Keys({"dwell": NUMBER}, ("dwell",)), _moving("return"))),
    Keys({"angle": list_of(NUMBER), "lift": list_of(NUMBER)}, ("angle", "lift")),
)


@dataclass(frozen=True)
class Segment:
    """One part of the turn: ``kind`` rise/dwell/return, ``lift`` h (m or rad, 0 for a
    dwell), ``span`` β (rad), ``curve`` a name of :data:`CURVES` ('' for a dwell)."""

    kind: str
    lift: float
    span: float
    curve: str = ""


@dataclass(frozen=True)
class CamLaw:
    """The lift s(θ) over one turn: ``segments``, or a table (``angles``, ``lifts``)."""

    segments: tuple[Segment, ...] = ()
    angles: tuple[float, ...] = ()
    lifts: tuple[float, ...] = ()
    _spline: object = field(default=None, init=False, repr=False, compare=False)
    _pieces: tuple = field(default=(), init=False, repr=False, compare=False)
    _edges: object = field(default=None, init=False, repr=False, compare=False)
    _edge_list: list = field(default=None, init=False, repr=False, compare=False)

    def __post_init__(self):
        if self.angles:
            from scipy.interpolate import make_interp_spline

            x = np.append(np.asarray(self.angles, float), self.angles[0] + TWO_PI)
            y = np.append(np.asarray(self.lifts, float), self.lifts[0])
            object.__setattr__(self, "_spline", make_interp_spline(x, y, k=5, bc_type="periodic"))
            return
        # each segment as (start θ₀, span β, signed lift ±h, lift at its start, curve or '')
        pieces, base = [], 0.0
        edges = self.breaks
        for k, seg in enumerate(self.segments):
            if seg.kind == "dwell":
                pieces.append((float(edges[k]), seg.span, 0.0, base, ""))
                continue
            h = seg.lift if seg.kind == "rise" else -seg.lift
            pieces.append((float(edges[k]), seg.span, h, base, seg.curve))
            base += h
        object.__setattr__(self, "_pieces", tuple(pieces))
        object.__setattr__(self, "_edges", edges)
        object.__setattr__(self, "_edge_list", edges.tolist())

    @property
    def breaks(self) -> np.ndarray:
        """The angles in [0, 2π] where a derivative may jump (segment ends, table knots)."""
        if self.angles:
            a = np.mod(np.asarray(self.angles, float), TWO_PI)
            return np.unique(np.concatenate(([0.0, TWO_PI], a)))
        return np.concatenate(([0.0], np.cumsum([s.span for s in self.segments])))

    def where(self, theta: float, angular: bool) -> str:
        """`` in motion[k] (rise 2 mm over 0.1°)``: the segment at cam angle ``theta``
        (rad) for a message, its lift in mm or degrees (``angular``); '' for a table."""
        if not self.segments:
            return ""
        th = float(np.mod(theta, TWO_PI))
        k = np.searchsorted(self.breaks, th, side="right") - 1
        k = int(np.clip(k, 0, len(self.segments) - 1))
        seg = self.segments[k]
        span = f"{math.degrees(seg.span):.4g}°"
        if seg.kind == "dwell":
            return f" in motion[{k}] (dwell {span})"
        lift = f"{math.degrees(seg.lift):.4g}°" if angular else f"{seg.lift * 1e3:.4g} mm"
        return f" in motion[{k}] ({seg.kind} {lift} over {span})"

    def value(self, theta):
        """(s, s', s'', s''') at cam angles ``theta`` (rad, any turn).

        At a segment's end a derivative may jump: an angle within :data:`SNAP` of an end
        takes the segment that starts there (360° − 1e-14 is 0°), whichever side round-off
        put it.  Each angle is evaluated on its own segment only: up to :data:`SMALL`
        angles one by one in Python floats, more grouped by segment."""
        th = np.mod(np.asarray(theta, dtype=float), TWO_PI)
        if self._spline is not None:
            x0 = self.angles[0]
            x = x0 + np.mod(th - x0, TWO_PI)
            return tuple(self._spline(x, nu=k) for k in range(4))
        if 0 < th.size <= SMALL:
            rows = np.array([self._at(x) for x in th.ravel().tolist()], dtype=float)
            return tuple(np.ascontiguousarray(rows.T).reshape((4,) + th.shape))
        th = np.where(th > TWO_PI - SNAP, th - TWO_PI, th)
        index = np.searchsorted(self._edges, th + SNAP, side="right") - 1
        index = np.clip(index, 0, len(self._pieces) - 1)
        out = [np.zeros(th.shape) for _ in range(4)]
        for k, (start, span, h, base, curve) in enumerate(self._pieces):
            m = index == k
            if not m.any():
                continue
            if not curve:
                out[0][m] = base
                continue
            y = CURVES[curve]((th[m] - start) / span)
            out[0][m] = h * y[0] + base
            for n in range(1, 4):
                out[n][m] = h * y[n] / span**n
        return tuple(out)

    def _at(self, th: float) -> tuple[float, float, float, float]:
        """:meth:`value` at one angle in [0, 2π), in Python floats."""
        if th > TWO_PI - SNAP:
            th -= TWO_PI
        k = bisect.bisect_right(self._edge_list, th + SNAP) - 1
        start, span, h, base, curve = self._pieces[min(max(k, 0), len(self._pieces) - 1)]
        if not curve:
            return base, 0.0, 0.0, 0.0
        y = CURVES[curve]((th - start) / span, math)
        return h * y[0] + base, h * y[1] / span, h * y[2] / span**2, h * y[3] / span**3

    def to_spec(self):
        if self.angles:
            return {"angle": list(self.angles), "lift": list(self.lifts)}
        out = []
        for s in self.segments:
            if s.kind == "dwell":
                out.append({"dwell": s.span})
            else:
                out.append({s.kind: s.lift, "over": s.span, "law": s.curve})
        return out


def read_law(entry, lift_kind: str) -> CamLaw | None:
    """``motion:`` of a cam joint: a list of segments, or ``{angle: [...], lift: [...]}``."""
    if entry.is_mapping:
        if not entry.check_keys(required=("angle", "lift")):
            return None
        angles = [e.number("angle") for e in (entry["angle"].seq() or [])]
        lifts = [e.number(lift_kind) for e in (entry["lift"].seq() or [])]
        if None in angles or None in lifts or not angles:
            return None
        if len(angles) != len(lifts):
            entry["lift"].error(f"expected {len(angles)} lifts (one per angle), got {len(lifts)}")
            return None
        a = np.asarray(angles)
        if len(a) < 6 or np.any(np.diff(a) <= 0) or a[-1] - a[0] >= TWO_PI:
            entry["angle"].error(
                "a table needs at least 6 increasing cam angles within one turn "
                "(the first is not repeated at its end)"
            )
            return None
        return CamLaw(angles=tuple(angles), lifts=tuple(lifts))
    items = entry.seq()
    if items is None:
        return None
    segments, rise, total = [], 0.0, 0.0
    for e in items:
        seg = _segment(e, lift_kind)
        if seg is None:
            return None
        segments.append(seg)
        rise += seg.lift if seg.kind == "rise" else -seg.lift if seg.kind == "return" else 0.0
        total += seg.span
        if rise < -1e-12 * max(abs(s.lift) for s in segments):
            e.error("the follower would return below where it started (its lowest position)")
            return None
    scale = max((s.lift for s in segments), default=0.0)
    if abs(total - TWO_PI) > 1e-9 or abs(rise) > 1e-9 * max(scale, 1e-300) or scale == 0.0:
        entry.error(
            f"the segments must cover one turn (theirs: {math.degrees(total):.6g}°) and "
            f"return as much as they rise (net lift {rise:.6g} in SI units), with some lift"
        )
        return None
    return CamLaw(segments=tuple(segments))


def _segment(e, lift_kind: str) -> Segment | None:
    if not e.mapping():
        return None
    kind = [k for k in KINDS if e.get(k) is not None]
    if len(kind) != 1:
        e.error("a segment has one of rise, dwell or return")
        return None
    kind = kind[0]
    if kind == "dwell":
        if not e.check_keys(required=("dwell",)):
            return None
        span = e["dwell"].number("angle", minimum=0.0, strict=True)
        return None if span is None else Segment("dwell", 0.0, span)
    if not e.check_keys(required=(kind, "over"), optional=("law",)):
        return None
    lift = e[kind].number(lift_kind, minimum=0.0, strict=True)
    span = e["over"].number("angle", minimum=0.0, strict=True)
    curve = e["law"].text() if e.get("law") is not None else "cycloidal"
    if curve is not None and curve not in CURVES:
        e["law"].error(f"law must be one of {', '.join(CURVES)}, got '{curve}'")
        return None
    if lift is None or span is None or curve is None:
        return None
    return Segment(kind, lift, span, curve)
