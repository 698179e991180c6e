r"""The cam's design: the follower law's diagrams, the pressure angle, the curvature and the
least base radius of each cam pair of a model, as frozen records (docs/methods.md).

For each joint whose ``profile_design()`` answers (a ``cam`` pair; the per-type closed
forms are ``joints/_camdesign.py``'s), :func:`cam_design` samples over the cam angle φ:

* the law s(φ), s′ = ds/dφ and s″ = d²s/dφ² (the s–φ, v–φ and a–φ diagrams per unit cam
  speed: at a constant speed ω the follower's velocity is ω s′ and its acceleration ω² s″);
* the pressure angle α(φ) and its largest magnitude, located on every segment of the law
  and refined by golden-section search between the samples around the largest;
* the least radius of curvature ρ_min of the pitch curve's convex part (the roller centre's
  path), and so the roller radius limit r_r < ρ_min that avoids undercut (the profile
  itself for a flat face, whose ρ_min must stay positive);
* the least base radius r_b,min for the allowable pressure angle [α] (the caller's, else
  the cam joint's ``design: {pressure_angle_max}``, else the textbook's 30°): in closed form for a
  translating knife or roller follower (the largest over φ of the per-angle bound, refined
  as above), by bisection on r_b with the closed form α(φ; r_b) for an oscillating
  follower (knife, roller or flat face); none for a translating flat face (α ≡ 0);
* whether the file's base radius satisfies [α];
* the pitch curve and the working profile as points in the cam's frame, for a drawing.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

import numpy as np

from ..analysis.results import Result
from ..base.arguments import real_number
from ..model import Model

__all__ = ["CamDesign", "cam_design", "DEFAULT_ALLOWED"]

GOLDEN = (math.sqrt(5.0) - 1.0) / 2.0
STEPS = 80  # golden-section steps: the bracket shrinks by 0.618⁸⁰ ≈ 2e-17
BISECT = 200  # bisection steps on the base radius at most
LOW = 1e-9  # [α] holds this close (relative) to the lowest placement: it bounds nothing
TOL = 1e-14  # bisection stops when the bracket is this small relative to the base radius


@dataclass(frozen=True)
class CamDesign:
    """The design of one cam pair (SI; angles in degrees; per unit cam speed).

    ``angle`` φ (deg) and ``lift``, ``lift_d1``, ``lift_d2``: s, ds/dφ, d²s/dφ² in
    ``lift_units``; ``pressure_angle`` α(φ) (deg) at the file's base radius.  ``peak`` the
    largest |α| (deg) and ``peak_at`` its φ; ``curvature_min`` ρ_min (m) of the convex pitch
    curve (the profile for a flat face) and ``curvature_at``; ``roller_limit`` the roller
    radius that would undercut (None for a flat face); ``base_radius_min`` the least base
    radius for ``allowed`` [α] (None where [α] does not bound it) and ``method`` how it was
    found; ``allowed_from`` where [α] came from (``file``: the joint's ``design:``;
    ``default``: the textbook's 30°; ``caller``: the argument); ``satisfied`` whether the
    file's base radius keeps |α| ≤ [α]; ``pitch_curve``
    (None for a flat face) and ``profile``, ``(360, 2)`` points (m) in the cam's frame at
    the cam angles 0°, 1°, … (what a drawing of the cam draws)."""

    joint: str
    follower: str
    motion: str
    lift_units: tuple[str, str, str]
    base_radius: float
    roller_radius: float
    allowed: float
    allowed_from: str
    angle: np.ndarray
    lift: np.ndarray
    lift_d1: np.ndarray
    lift_d2: np.ndarray
    pressure_angle: np.ndarray
    peak: float
    peak_at: float
    curvature_min: float
    curvature_at: float
    roller_limit: float | None
    base_radius_min: float | None
    method: str
    satisfied: bool
    pitch_curve: np.ndarray | None
    profile: np.ndarray

    def to_dict(self) -> dict[str, Any]:
        """The record as JSON-safe values (methods.json's ``cam_design.<joint>``)."""
        out: dict[str, Any] = {}
        for name in self.__dataclass_fields__:
            v = getattr(self, name)
            if isinstance(v, np.ndarray):
                v = v.tolist()
            elif isinstance(v, tuple):
                v = list(v)
            elif isinstance(v, (float, np.floating)):
                v = float(v) if math.isfinite(v) else None
            out[name] = v
        return out


def _golden(f: Callable[[np.ndarray], np.ndarray], lo: float, hi: float) -> tuple[float, float]:
    """(max f, where) on [lo, hi] of a unimodal f, by golden-section search."""
    a, b = lo, hi
    c, d = b - GOLDEN * (b - a), a + GOLDEN * (b - a)
    fc, fd = float(f(np.array([c]))[0]), float(f(np.array([d]))[0])
    for _ in range(STEPS):
        if b - a <= 1e-15 * max(1.0, abs(b)):
            break
        if fc >= fd:
            b, d, fd = d, c, fc
            c = b - GOLDEN * (b - a)
            fc = float(f(np.array([c]))[0])
        else:
            a, c, fc = c, d, fd
            d = a + GOLDEN * (b - a)
            fd = float(f(np.array([d]))[0])
    return (fc, c) if fc >= fd else (fd, d)


def _peak(f: Callable[[np.ndarray], np.ndarray], grid: np.ndarray) -> tuple[float, float]:
    """(max f, where) over the cam angles: the largest sample, refined between its
    neighbours.  NaN samples count as the largest (a follower that cannot be placed)."""
    v = f(grid)
    if np.isnan(v).any():
        k = int(np.nonzero(np.isnan(v))[0][0])
        return math.inf, float(grid[k])
    k = int(np.argmax(v))
    last = len(grid) - 1
    brackets = [(grid[max(k - 1, 0)], grid[min(k + 1, last)])]
    if k in (0, last):  # 0° and 360° are one cam angle: refine on both sides of it
        brackets = [(grid[0], grid[1]), (grid[last - 1], grid[last])]
    best, at = float(v[k]), float(grid[k])
    for lo, hi in brackets:
        value, where = _golden(f, float(lo), float(hi))
        if value > best:
            best, at = value, where
    return best, float(np.mod(at, 2 * math.pi))


def _largest_alpha(chart, grid: np.ndarray, base: float | None) -> tuple[float, float]:
    return _peak(lambda th: np.abs(chart.pressure_angle(th, base)), grid)


def _curvature(chart, grid: np.ndarray) -> tuple[float, float]:
    """(ρ_min, where) of the convex part (ρ > 0): the least positive radius of curvature."""

    def minus(th):
        rho = chart.pitch_radius(th)
        return np.where(rho > 0, -rho, -math.inf)

    value, at = _peak(minus, grid)
    return -value, at


def _bisect(chart, grid: np.ndarray, allowed: float) -> tuple[float | None, str]:
    """(the least base radius whose largest |α| stays within ``allowed``, how it was found):
    by bisection between the lowest placement and the file's base radius (or the first of
    its doublings that satisfies [α]); None where no base radius in reach satisfies [α] or
    every one down to the lowest placement does."""
    lo, top = chart.base_range()

    def ok(base: float) -> bool:
        return _largest_alpha(chart, grid, base)[0] <= allowed

    hi = chart.base
    while not ok(hi):
        lo, hi = hi, 2.0 * hi
        if hi >= top:
            return None, "bisection: no base radius within the follower's reach satisfies [α]"
    if ok(lo + LOW * (hi - lo)):
        return None, (
            f"bisection: [α] bounds no base radius (every one down to {lo * 1e3:.4g} mm, "
            "where the follower can no longer be placed, keeps it)"
        )
    for _ in range(BISECT):
        if hi - lo <= TOL * hi:
            break
        mid = 0.5 * (lo + hi)
        lo, hi = (lo, mid) if ok(mid) else (mid, hi)
    return hi, "bisection"


def _least_base(chart, grid: np.ndarray, allowed: float) -> tuple[float | None, str]:
    """(r_b,min, how it was found)."""
    bound = chart.least_base(grid, allowed)
    if bound is not None:
        value, _ = _peak(lambda th: chart.least_base(th, allowed), grid)
        return max(value, 0.0), "closed form"
    if chart.base_range() is None:
        return None, "none: the pressure angle of a translating flat face is 0"
    return _bisect(chart, grid, allowed)


def _design(name: str, chart, allowed_deg: float, source: str, samples: int) -> CamDesign:
    allowed = math.radians(allowed_deg)
    grid = chart.grid
    phi = np.linspace(0.0, 2.0 * math.pi, samples + 1)
    s, s1, s2 = chart.law(phi)
    peak, peak_at = _largest_alpha(chart, grid, None)
    rho, rho_at = _curvature(chart, grid)
    base_min, method = _least_base(chart, grid, allowed)
    pitch, profile = chart.curves()
    return CamDesign(
        joint=name,
        follower=chart.follower,
        motion=chart.motion,
        lift_units=chart.lift_units,
        base_radius=chart.base,
        roller_radius=chart.roller,
        allowed=allowed_deg,
        allowed_from=source,
        angle=np.degrees(phi),
        lift=s,
        lift_d1=s1,
        lift_d2=s2,
        pressure_angle=np.degrees(chart.pressure_angle(phi)),
        peak=math.degrees(peak),
        peak_at=math.degrees(peak_at),
        curvature_min=rho,
        curvature_at=math.degrees(rho_at),
        roller_limit=None if chart.follower == "flat" else rho,
        base_radius_min=base_min,
        method=method,
        satisfied=bool(peak <= allowed),
        pitch_curve=pitch,
        profile=profile,
    )


DEFAULT_ALLOWED = 30.0
"""The textbook's allowable pressure angle (deg) of a translating follower's rise, taken
where neither the caller nor the file gives one."""


def cam_design(
    model: Model | Result, *, pressure_angle_max: float | None = None, samples: int = 360
) -> tuple[CamDesign, ...]:
    """The design of each cam pair of a model (or of a result's model).

    Parameters
    ----------
    model : Model or Result
        The mechanism; a result stands for the model it analysed.
    pressure_angle_max : float, optional
        The allowable pressure angle [α] in degrees (0 < [α] < 90; the textbook's 30° for a
        translating follower's rise, 35°–45° for an oscillating one), for every cam;
        default: each cam joint's ``design: {pressure_angle_max}``, else 30°.
    samples : int
        The curves are sampled at ``samples + 1`` cam angles from 0° to 360°; the extremes
        are found on every segment of the law whatever this is.

    Returns
    -------
    tuple of CamDesign
        One record per cam pair, in the model's order of joints (empty without one).
    """
    if isinstance(model, Result):
        model = model.system.model
    allowed = None
    if pressure_angle_max is not None:
        allowed = real_number(
            "pressure_angle_max", pressure_angle_max, low=0.0, high=90.0, strict_low=True,
            strict_high=True, why="the allowable pressure angle in degrees",
        )  # fmt: skip
    count = real_number("samples", samples, low=1.0, why="cam angles sampled per turn")
    if count != int(count):
        raise ValueError(f"samples = {samples!r}: expected a whole number")
    out = []
    for joint in model.joints:
        chart = joint.profile_design()
        if chart is None:
            continue
        if allowed is not None:
            value, source = allowed, "caller"
        elif chart.allowed is not None:
            value, source = math.degrees(chart.allowed), "file"
        else:
            value, source = DEFAULT_ALLOWED, "default"
        out.append(_design(joint.name, chart, value, source, int(count)))
    return tuple(out)
