"""Pictures of a :class:`~kinetostatics.results.Result`.

Every public drawing function takes a ``Result`` and returns a matplotlib
``Figure`` built without ``pyplot`` (no global state; save it with
``fig.savefig(path)``).  matplotlib is imported inside the functions that draw,
so importing this module stays light.  The numbers behind the pictures come
from data functions that tests check against the results:

- :func:`mechanism_geometry` — every point, joint, link outline, block and
  guide drawn at one position (m);
- :func:`polygon` — the velocity or acceleration polygon at one position:
  absolute vectors from the pole and the relative vectors (ω × r, ω²r, α × r,
  sliding, Coriolis) that close it;
- :func:`link_frame_loads` — a joint's reaction in a link-fixed frame (polar
  diagrams);
- :func:`course_positions` — the course-design positions 1…12 and the load
  events (1′, 8′ …) among the rows.

Figures: :func:`draw_mechanism`, :func:`motion_diagram`,
:func:`reaction_curves`, :func:`torque_curves`, :func:`efficiency_curve`,
:func:`polar_diagrams`, :func:`polygon_figure`, :func:`plot_result`; and
:func:`animate` writes a GIF (Pillow) or an MP4 (only when ffmpeg is on the
PATH).  Drawings and polygons are laid out to a true scale: printed at 100 %,
1 mm of paper is μ_l metres (μ_v m/s, μ_a m/s², μ_F N), as stated on them.

Conventions (SPEC.md, docs/theory.md): x right, y up, angles and moments
counter-clockwise positive; a joint's reaction is the force of its link i on
its link j; links are numbered 1, 2, … in the order of ``System.links`` and
the frame takes the next number, so ``F61`` is the frame (6) on the crank (1).
"""

from __future__ import annotations

import math
import re
from collections.abc import Iterable, Sequence
from dataclasses import dataclass, replace
from pathlib import Path

import numpy as np

from ._geometry import perp, rotate
from .errors import KinetostaticsError, did_you_mean
from .forces import point_state

__all__ = [
    "MechanismGeometry",
    "PictureError",
    "Polygon",
    "PolygonChain",
    "PolygonNode",
    "analyze_for_pictures",
    "animate",
    "course_positions",
    "draw_mechanism",
    "efficiency_curve",
    "link_frame_loads",
    "link_numbers",
    "mechanism_geometry",
    "motion_diagram",
    "nice_scale",
    "output_motion",
    "plot_result",
    "polar_diagrams",
    "polygon",
    "polygon_figure",
    "reaction_curves",
    "row_at",
    "torque_curves",
]


class PictureError(KinetostaticsError, ValueError):
    """A picture cannot be made as asked (unknown name, missing column, no ffmpeg …)."""


# -- one consistent look ----------------------------------------------------------
STYLE = {
    "font.size": 8.5,
    "axes.titlesize": 9.5,
    "axes.labelsize": 8.5,
    "axes.grid": True,
    "grid.color": "#d9d9d9",
    "grid.linewidth": 0.5,
    "axes.spines.top": False,
    "axes.spines.right": False,
    "legend.fontsize": 7.5,
    "legend.frameon": False,
    "lines.linewidth": 1.4,
    "xtick.labelsize": 7.5,
    "ytick.labelsize": 7.5,
    "mathtext.default": "regular",
}
LINK_COLORS = (
    "#1f5fa8",
    "#d9641e",
    "#2e8b57",
    "#8e44ad",
    "#b8860b",
    "#c0392b",
    "#16a5a5",
    "#7f7f7f",
    "#e377c2",
    "#4b5563",
)
FORCE_COLORS = {
    "reaction": "#1f5fa8",
    "inertia": "#c0392b",
    "gravity": "#6b6b6b",
    "external": "#2e8b57",
    "effort": "#8e44ad",
}
CURVE_COLORS = (
    "#1f5fa8",
    "#d9641e",
    "#2e8b57",
    "#c0392b",
    "#8e44ad",
    "#b8860b",
    "#16a5a5",
    "#7f7f7f",
    "#e377c2",
    "#4b5563",
)
EVENT_COLOR = "#c0392b"
MM = 1.0 / 25.4  # inches per mm
DPI = 110


def _mpl():
    """matplotlib pieces, imported on first use (``run`` never imports them)."""
    import matplotlib
    from matplotlib.figure import Figure

    return matplotlib, Figure


def _figure(width_mm: float, height_mm: float, dpi: float = DPI):
    _, Figure = _mpl()
    return Figure(figsize=(width_mm * MM, height_mm * MM), dpi=dpi)


def _rc():
    matplotlib, _ = _mpl()
    return matplotlib.rc_context(STYLE)


def nice_scale(x: float) -> float:
    """The smallest of 1, 2, 2.5, 4, 5 × 10^k that is ≥ ``x`` (a drawing scale).

    >>> nice_scale(0.0017), nice_scale(0.031), nice_scale(7.0)
    (0.002, 0.04, 10.0)
    """
    if not np.isfinite(x) or x <= 0:
        return 1.0
    k = math.floor(math.log10(x))
    for m in (1.0, 2.0, 2.5, 4.0, 5.0, 10.0):
        v = round(m * 10.0**k, 12 - k if k < 0 else 12)
        if v >= x * (1 - 1e-12):
            return v
    return 10.0 ** (k + 1)


def _fmt_scale(x: float) -> str:
    return f"{x:.6g}"


def _tex(label: str) -> str:
    """``a2'`` -> mathtext: upright a, subscript 2, a prime; underscores escaped."""
    m = re.match(r"^(.*?)(\d+)?('*)$", label)
    base, digits, primes = m.group(1), m.group(2) or "", m.group(3)
    base = base.replace("_", r"\_").replace(" ", r"\ ")
    out = rf"\mathrm{{{base}}}" + (f"_{{{digits}}}" if digits else "") + "'" * len(primes)
    return f"${out}$"


MU = {"l": r"$\mu_l$", "v": r"$\mu_v$", "a": r"$\mu_a$", "F": r"$\mu_F$"}


# -- rows, positions, the abscissa ----------------------------------------------
def _driver(result):
    return result.system.motion_drivers[0]


def _angular(result) -> bool:
    return bool(_driver(result).joint.angular)


def row_at(result, position: float | None = None, *, label: str | None = None) -> int:
    """Row index at a driver coordinate (deg, or mm for a prismatic driver) or at a
    course-position label (``"7"``, ``"8′"``).  Default: the first row.

    Raises :class:`PictureError` if no row is within 1e-6 of the coordinate.
    """
    if label is not None:
        for lab, k in course_positions(result):
            if lab == label.replace("'", "′"):
                return k
        raise PictureError(
            f"no course position '{label}' among the rows "
            f"(have {', '.join(lab for lab, _ in course_positions(result))})"
        )
    if position is None:
        return 0
    if _angular(result):
        d = np.abs((np.degrees(result.coordinate) - position + 180.0) % 360.0 - 180.0)
    else:
        d = np.abs(result.coordinate * 1e3 - position)
    k = int(np.argmin(d))
    if d[k] > 1e-6:
        raise PictureError(
            f"no analysed position at driver coordinate {position:g}"
            f"{'°' if _angular(result) else ' mm'} (nearest "
            f"{d[k]:.3g} away); analyse with analyze_for_pictures(model, "
            f"positions=[{position:g}])"
        )
    return k


def analyze_for_pictures(
    model,
    *,
    positions: Sequence[float] = (),
    frames: int | None = None,
    course: bool = False,
    events: bool = True,
):
    """A full-cycle analysis that also holds rows at chosen driver coordinates.

    ``positions``: driver coordinates in deg (mm for a prismatic driver) added
    to ``analysis.at`` (so loads that depend on the whole cycle, such as a
    cutting band, stay right); ``frames``: replace the grid by that many
    equally spaced positions (animations); ``course``: add the 12 course-design
    positions; ``events``: add rows where loads switch (1′, 8′).
    """
    from .analysis import analyze
    from .system import build_system

    system = build_system(model)
    a = model.analysis
    angular = system.motion_drivers[0].joint.angular if system.motion_drivers else True
    conv = math.radians if angular else (lambda v: v * 1e-3)
    grid = frames if frames is not None else a.positions
    sign = (
        math.copysign(1.0, system.motion_drivers[0].driver.motion.speed)
        if system.motion_drivers
        else 1.0
    )
    grid_coords = [a.start + sign * k * a.sweep / grid for k in range(grid)]
    extra = [conv(p) for p in positions]
    if course and angular:
        extra += [a.start + sign * k * a.sweep / 12 for k in range(12)]
    at = list(a.at)

    def present(c):
        period = 2 * math.pi if angular else math.inf
        for g in grid_coords + at:
            d = abs(c - g)
            if math.isfinite(period):
                d = abs((d + math.pi) % period - math.pi)
            if d < 1e-9:
                return True
        return False

    for c in extra:
        if not present(c):
            at.append(c)
    new = replace(model, analysis=replace(a, positions=grid, at=tuple(at), events=events))
    return analyze(new)


def _abscissa(result) -> tuple[np.ndarray, str]:
    d = _driver(result)
    if getattr(d.driver.motion, "kind", None) is not None:  # a motion law: ψ may reverse
        return np.asarray(
            result["time"], dtype=float
        ), f"time, s ({d.name}: {d.driver.motion.kind} law)"
    if d.joint.angular:
        start = math.degrees(result.system.model.analysis.start) % 360.0
        sense = "clockwise" if d.driver.motion.speed < 0 else "counter-clockwise"
        return (
            np.asarray(result["travel"], dtype=float),
            f"{d.name} rotation from {start:.4g}° ({sense}), deg",
        )
    return np.asarray(result["travel"], dtype=float) * 1e3, f"{d.name} travel, mm"


def _event_travel(result, e) -> float:
    x = abs(e.coordinate - result.coordinate[0])
    return math.degrees(x) % 360.0 if _angular(result) else x * 1e3


def course_positions(result, n: int = 12) -> list[tuple[str, int]]:
    """Course-design positions among the rows: ``[(label, row), …]`` in order of travel.

    Position k (1…n) is the row at travel (k − 1)·360°/n from the first row, in
    the sense of motion (position 1 = ``analysis.start``); each load event
    (a row added at an exact switching position) is labelled with the number of
    the position before it and a prime (1′, 8′).  Only for a full cycle of an
    angular driver; otherwise empty.
    """
    if not _angular(result) or not result.full_cycle:
        return []
    travel = np.asarray(result["travel"], dtype=float)
    out: list[tuple[float, str, int]] = []
    for k in range(n):
        idx = np.nonzero(np.abs(travel - k * 360.0 / n) < 1e-6)[0]
        if idx.size:
            out.append((k * 360.0 / n, str(k + 1), int(idx[0])))
    for e in result.events:
        idx = np.nonzero(np.abs(result.t - e.t) < 1e-9 * max(1.0, abs(e.t)))[0]
        if not idx.size:
            continue
        x = _event_travel(result, e)
        before = int(math.floor(x / (360.0 / n) + 1e-9)) + 1
        out.append((x, f"{before}′", int(idx[0])))
    out.sort(key=lambda r: r[0])
    return [(lab, k) for _, lab, k in out]


def _course_ticks(result, n: int = 12) -> list[tuple[float, str]]:
    """Travel of the course positions and events (whether or not they are rows)."""
    if not _angular(result) or not result.full_cycle:
        return []
    ticks = [(k * 360.0 / n, str(k + 1)) for k in range(n)]
    for e in result.events:
        x = _event_travel(result, e)
        ticks.append((x, f"{int(math.floor(x / (360.0 / n) + 1e-9)) + 1}′"))
    return sorted(ticks)


def _position_title(result, row: int) -> str:
    labels = [lab for lab, k in course_positions(result) if k == row]
    d = _driver(result)
    if d.joint.angular:
        coord = f"φ = {math.degrees(result.coordinate[row]) % 360.0:.2f}°"
    else:
        coord = f"s = {result.coordinate[row] * 1e3:.2f} mm"
    return f"position {labels[0]} ({coord})" if labels else coord


def link_numbers(system) -> dict[str, int]:
    """Link numbers of the pictures: moving links 1… in ``System.links`` order, the frame last."""
    nums = {name: k + 1 for k, name in enumerate(system.links)}
    nums[system.model.ground.name] = len(system.links) + 1
    return nums


# -- geometry of the drawing ----------------------------------------------------
def _poses(result, link: str, rows=slice(None)):
    """(r (..., 2), θ (...)) of a link over rows; the frame is at rest at the origin."""
    system = result.system
    if link == system.model.ground.name:
        q = result.q[rows]
        return np.zeros(q.shape[:-1] + (2,)), np.zeros(q.shape[:-1])
    k = system.link_index(link)
    q = result.q[rows]
    return q[..., 3 * k : 3 * k + 2], q[..., 3 * k + 2]


def _to_global(result, link, p, rows=slice(None)):
    r, th = _poses(result, link, rows)
    return r + rotate(th, np.asarray(p, dtype=float))


def _joint_point(result, joint, rows=slice(None)):
    """Global position where a joint's reaction acts: the pin of a revolute, the
    sliding point of a prismatic pair, the pitch point of a gear or rack pair;
    ``None`` for a joint type the pictures do not know."""
    from .joints import Prismatic, Revolute

    if isinstance(joint, Prismatic):
        return _to_global(result, joint.links[1], joint.p, rows)
    if isinstance(joint, Revolute):
        return _to_global(result, joint.links[1], joint.p_j, rows)
    wheels = _wheels(result, joint, rows)
    return None if wheels is None else wheels["pitch_point"]


def _wheels(result, joint, rows=slice(None)):
    """Pitch circles and lines of a toothed higher pair (gear: ``c_i, c_j, r_i, r_j``;
    rack: ``a, u`` on link i and ``c, r`` on link j), found by their attributes;
    ``None`` for other joint types.  Global, m."""
    i_link, j_link = joint.links
    if all(hasattr(joint, n) for n in ("c_i", "c_j", "r_i", "r_j")):
        Ci = _to_global(result, i_link, joint.c_i, rows)
        Cj = _to_global(result, j_link, joint.c_j, rows)
        D = Cj - Ci
        e = D / np.maximum(np.linalg.norm(D, axis=-1, keepdims=True), 1e-300)
        rho_i = joint.signed_radii[0] if hasattr(joint, "signed_radii") else joint.r_i
        return {
            "circles": [(i_link, Ci, float(joint.r_i)), (j_link, Cj, float(joint.r_j))],
            "lines": [],
            "pitch_point": Ci + rho_i * e,
        }
    if all(hasattr(joint, n) for n in ("a", "u", "c", "r")):
        r_i, th_i = _poses(result, i_link, rows)
        A = r_i + rotate(th_i, np.asarray(joint.a, float))
        U = rotate(th_i, np.asarray(joint.u, float))
        C = _to_global(result, j_link, joint.c, rows)
        N = perp(U)
        h = np.sum(N * (C - A), axis=-1, keepdims=True)
        return {
            "circles": [(j_link, C, float(joint.r))],
            "lines": [(i_link, A, U)],
            "pitch_point": C - h * N,
        }
    return None


def _collinear(pts: np.ndarray, tol: float) -> bool:
    if len(pts) < 3:
        return True
    c = pts - pts.mean(axis=0)
    s = np.linalg.svd(c, compute_uv=False)
    return s[1] / math.sqrt(len(pts)) <= tol


def _hull(pts: np.ndarray) -> np.ndarray:
    """Convex hull, counter-clockwise (monotone chain)."""
    p = sorted(map(tuple, np.round(pts, 12)))
    p = list(dict.fromkeys(p))
    if len(p) < 3:
        return np.array(p)

    def half(seq):
        h: list = []
        for x in seq:
            while (
                len(h) >= 2
                and (
                    (h[-1][0] - h[-2][0]) * (x[1] - h[-2][1])
                    - (h[-1][1] - h[-2][1]) * (x[0] - h[-2][0])
                )
                <= 0
            ):
                h.pop()
            h.append(x)
        return h

    lower, upper = half(p), half(reversed(p))
    return np.array(lower[:-1] + upper[:-1])


@dataclass(frozen=True)
class _Block:
    joint: str
    link: str
    centre: np.ndarray  # (2,) m
    direction: np.ndarray  # (2,) unit, along the axis
    length: float
    height: float


@dataclass(frozen=True)
class _Guide:
    joint: str
    start: np.ndarray  # (2,) m, on the axis
    end: np.ndarray
    half_width: float  # rails at ± half_width from the axis


@dataclass(frozen=True)
class MechanismGeometry:
    """What :func:`draw_mechanism` draws at one row (all in m, global axes).

    ``points["link.point"]`` every named point (frame points too);
    ``joints[name]`` the pin of each revolute and the sliding point of each
    prismatic pair; ``outlines[link]`` the polyline (bars) or polygon (plates,
    in ``plates``) of each moving link; ``blocks`` the sliders; ``guides`` the
    frame's straight guides; ``pivots`` the frame's pins; ``com[link]`` the
    centre of mass of each link with mass; ``wheels`` the pitch circles and
    pitch lines of gear and rack pairs.
    """

    row: int
    points: dict
    joints: dict
    outlines: dict
    plates: frozenset
    blocks: tuple
    guides: tuple
    pivots: dict
    com: dict
    wheels: tuple = ()  # ("circle", joint, link, centre, r) | ("line", joint, link, p0, p1)


class _Scene:
    """Everything about a drawing that does not change with the position."""

    def __init__(self, result, paths: Iterable[str] = ()):
        from .joints import Prismatic, Revolute

        self.result = result
        system = self.system = result.system
        model = self.model = system.model
        self.ground = model.ground.name
        l_ref = system.l_ref
        self.block_len = {}
        self.block_h = {}
        local: dict[str, list[np.ndarray]] = {
            n: [np.asarray(p, float) for p in model.link(n).points.values()] for n in system.links
        }
        self.guides_local = []  # (joint, a, u, s_min, s_max, half)
        for j in model.joints:
            if not isinstance(j, Prismatic):
                continue
            L = j.length if j.length else 0.12 * l_ref
            h = min(0.6 * L, 0.08 * l_ref) if not j.length else max(0.35 * L, 0.04 * l_ref)
            self.block_len[j.name], self.block_h[j.name] = L, h
            i_link, j_link = j.links
            P = _to_global(result, j_link, j.p)  # (n, 2)
            r_i, th_i = _poses(result, i_link)
            loc = rotate(-th_i, P - r_i)  # P in i's frame
            s = (loc - j.a) @ j.u
            lo, hi = float(s.min()) - 0.6 * L, float(s.max()) + 0.6 * L
            if i_link == self.ground:
                self.guides_local.append(
                    (
                        j.name,
                        np.asarray(j.a, float),
                        np.asarray(j.u, float),
                        lo,
                        hi,
                        0.5 * h + 0.004 * l_ref,
                    )
                )
            else:
                local[i_link] += [j.a + lo * j.u, j.a + hi * j.u]
        self.wheels_local = []  # ("circle", joint, link, centre, r) / ("line", joint, link, p0, p1)
        for j in model.joints:
            if isinstance(j, (Prismatic, Revolute)):
                continue
            w = _wheels(result, j)
            if w is None:
                continue
            for link, C, r in w["circles"]:
                r_k, th_k = _poses(result, link)
                self.wheels_local.append(
                    ("circle", j.name, link, rotate(-th_k[0], C[0] - r_k[0]), r)
                )
            for link, A, U in w["lines"]:
                r_k, th_k = _poses(result, link)
                P = rotate(-th_k, w["pitch_point"] - r_k)  # pitch points in link's frame
                u_loc = rotate(-th_k[0], U[0])
                a_loc = rotate(-th_k[0], A[0] - r_k[0])
                s = (P - a_loc) @ u_loc
                reach = max((r for _, _, r in w["circles"]), default=0.05 * l_ref)
                p0, p1 = a_loc + (s.min() - reach) * u_loc, a_loc + (s.max() + reach) * u_loc
                self.wheels_local.append(("line", j.name, link, p0, p1))
                if link in local:
                    local[link] += [p0, p1]
        self.outline_local: dict[str, np.ndarray] = {}
        self.plates: set[str] = set()
        for n, pts in local.items():
            pts = np.array(pts)
            if len(pts) == 0:
                continue
            if _collinear(pts, 1e-3 * l_ref):
                if len(pts) == 1 or np.ptp(pts, axis=0).max() < 1e-9 * l_ref:
                    self.outline_local[n] = pts[:1]
                    continue
                d = pts - pts.mean(axis=0)
                u = np.linalg.svd(d)[2][0]
                t = d @ u
                self.outline_local[n] = pts[[int(np.argmin(t)), int(np.argmax(t))]]
            else:
                self.outline_local[n] = _hull(pts)
                self.plates.add(n)
        self.pivots = {
            j.name: np.asarray(j.p_i if j.links[0] == self.ground else j.p_j, float)
            for j in model.joints
            if isinstance(j, Revolute) and self.ground in j.links
        }
        self.paths = {}
        for ref in paths:
            link, _, point = ref.partition(".")
            if link not in [lk.name for lk in model.links] or point not in model.link(link).points:
                names = [f"{lk.name}.{p}" for lk in model.links for p in lk.points]
                raise PictureError(f"no point '{ref}' to trace{did_you_mean(ref, names)}")
            self.paths[ref] = _to_global(result, link, model.link(link).points[point])
        self.numbers = link_numbers(system)
        self.colors = {n: LINK_COLORS[k % len(LINK_COLORS)] for k, n in enumerate(system.links)}
        # extent over the whole cycle: every point, outline, guide and path
        chunks = [np.zeros((1, 2))]
        for n, pts in self.outline_local.items():
            for p in pts:
                chunks.append(_to_global(result, n, p))
        for lk in model.links:
            for p in lk.points.values():
                chunks.append(np.atleast_2d(_to_global(result, lk.name, p)).reshape(-1, 2))
        for name, a, u, lo, hi, half in self.guides_local:
            nrm = perp(u)
            for s in (lo, hi):
                for w in (-1.5, 1.5):
                    chunks.append((a + s * u + w * half * nrm)[None])
        for pts in self.paths.values():
            chunks.append(pts)
        for kind, _, link, p, q in self.wheels_local:
            if kind == "circle":
                C = _to_global(result, link, p)
                chunks += [C - q, C + q]
            else:
                chunks += [_to_global(result, link, p), _to_global(result, link, q)]
        allp = np.concatenate(chunks)
        lo, hi = allp.min(axis=0), allp.max(axis=0)
        span = max(float(np.max(hi - lo)), l_ref, 1e-9)
        pad = 0.09 * span
        self.lo, self.hi = lo - pad, hi + pad
        self.pad = pad

    def geometry(self, row: int) -> MechanismGeometry:
        from .joints import Prismatic

        result, model = self.result, self.model
        points = {}
        for lk in model.links:
            for name, p in lk.points.items():
                points[f"{lk.name}.{name}"] = _to_global(result, lk.name, p, row)
        joints = {
            j.name: P for j in model.joints if (P := _joint_point(result, j, row)) is not None
        }
        outlines = {n: _to_global(result, n, pts, row) for n, pts in self.outline_local.items()}
        blocks = []
        for j in model.joints:
            if isinstance(j, Prismatic):
                _, th = _poses(result, j.links[0], row)
                blocks.append(
                    _Block(
                        j.name,
                        j.links[1],
                        joints[j.name],
                        rotate(th, j.u),
                        self.block_len[j.name],
                        self.block_h[j.name],
                    )
                )
        guides = tuple(
            _Guide(name, a + lo * u, a + hi * u, half)
            for name, a, u, lo, hi, half in self.guides_local
        )
        com = {}
        for n in self.system.links:
            if model.link(n).mass > 0:
                com[n] = _to_global(result, n, np.zeros(2), row)
        wheels = tuple(
            (
                kind,
                name,
                link,
                _to_global(result, link, p, row),
                q if kind == "circle" else _to_global(result, link, q, row),
            )
            for kind, name, link, p, q in self.wheels_local
        )
        return MechanismGeometry(
            row,
            points,
            joints,
            outlines,
            frozenset(self.plates),
            tuple(blocks),
            guides,
            dict(self.pivots),
            com,
            wheels,
        )


def mechanism_geometry(result, row: int = 0) -> MechanismGeometry:
    """The geometry :func:`draw_mechanism` draws at ``row`` (m, global axes)."""
    return _Scene(result).geometry(row)


# -- loads at one position (free-body view) --------------------------------------
@dataclass(frozen=True)
class _Arrow:
    kind: str  # reaction, inertia, gravity, external, effort
    label: str
    at: np.ndarray  # (2,) m
    force: np.ndarray | None  # (2,) N, or None for a couple
    moment: float = 0.0  # N·m (couples)


def _loads_at(result, row: int, *, friction: bool = False) -> list[_Arrow]:
    from .forces import activity

    system, model = result.system, result.system.model
    nums = link_numbers(system)
    out: list[_Arrow] = []
    suffix = "_friction" if friction else ""
    for j in model.joints:
        fx, fy = f"{j.name}.Fx{suffix}", f"{j.name}.Fy{suffix}"
        if fx not in result.columns:
            fx, fy = f"{j.name}.Fx", f"{j.name}.Fy"
        at = _joint_point(result, j, row)
        if at is None or fx not in result.columns:
            continue
        F = np.array([result[fx][row], result[fy][row]])
        out.append(_Arrow("reaction", f"F{nums[j.links[0]]}{nums[j.links[1]]}", at, F))
    g = np.asarray(model.gravity, float)
    for k, n in enumerate(system.links):
        lk = model.link(n)
        S = _to_global(result, n, np.zeros(2), row)
        if lk.mass > 0:
            a = result.qdd[row, 3 * k : 3 * k + 2]
            out.append(_Arrow("inertia", f"FI{nums[n]}", S, -lk.mass * a))
            if np.any(g):
                out.append(_Arrow("gravity", f"G{nums[n]}", S, lk.mass * g))
        if lk.inertia > 0:
            out.append(
                _Arrow("inertia", f"MI{nums[n]}", S, None, -lk.inertia * result.qdd[row, 3 * k + 2])
            )
    ref = abs(_driver(result).driver.motion.speed)
    q, qd = result.q[row : row + 1], result.qd[row : row + 1]
    psi = result.coordinate[row : row + 1]
    for load in model.loads:
        on = bool(activity(system, load, q, qd, psi, result.extremes, ref)[0])
        if not on:
            continue
        period = 2 * np.pi if _angular(result) else None
        value = np.asarray(load.value_at(psi, period))[0]
        k = system.link_index(load.link)
        p = model.link(load.link).points[load.point] if load.point else np.zeros(2)
        pos, vel, _ = point_state(q, qd, None, k, p)
        if load.kind == "torque":
            out.append(_Arrow("external", load.name, pos[0], None, float(value)))
            continue
        if load.kind == "force":
            F = np.asarray(value, float)
        else:
            v = float(vel[0] @ load.axis)
            F = (
                -float(value) * np.sign(v) * np.asarray(load.axis, float)
                if abs(v) > 1e-9 * ref * system.l_ref
                else np.zeros(2)
            )
        out.append(_Arrow("external", load.name, pos[0], F))
    for d_index, d in enumerate(system.motion_drivers):
        joint = model.joint(d.driver.balance_at) if d.driver.balance_at else d.joint
        word = "torque" if joint.angular else "force"
        e = (
            float(result[f"{d.name}.{word}{suffix}"][row])
            if f"{d.name}.{word}{suffix}" in result.columns
            else float(result[f"{d.name}.{word}"][row])
        )
        at = _joint_point(result, joint, row)
        if joint.angular and at is not None:
            out.append(_Arrow("effort", f"M_{d.name}", at, None, e))
    return out


# -- drawing primitives -----------------------------------------------------------
class _Paper:
    """Data (mm of the mechanism) ↔ paper (mm) for true-scale drawings."""

    def __init__(self, mu_l: float):
        self.mu_l = mu_l  # m of mechanism per mm of paper
        self.k = mu_l * 1e3  # data mm per paper mm


def _layout(
    xlim,
    ylim,
    per_mm: float,
    *,
    left=17.0,
    right=6.0,
    bottom=13.0,
    top=11.0,
    extra_right=0.0,
    dpi=DPI,
    min_mm=(40.0, 30.0),
):
    """A figure whose axes show ``xlim × ylim`` at ``per_mm`` data units per paper mm."""
    w = (xlim[1] - xlim[0]) / per_mm
    h = (ylim[1] - ylim[0]) / per_mm
    if w < min_mm[0]:
        c, half = 0.5 * (xlim[0] + xlim[1]), 0.5 * min_mm[0] * per_mm
        xlim, w = (c - half, c + half), min_mm[0]
    if h < min_mm[1]:
        c, half = 0.5 * (ylim[0] + ylim[1]), 0.5 * min_mm[1] * per_mm
        ylim, h = (c - half, c + half), min_mm[1]
    W, H = left + w + right + extra_right, bottom + h + top
    fig = _figure(W, H, dpi)
    ax = fig.add_axes([left / W, bottom / H, w / W, h / H])
    ax.set_xlim(*xlim)
    ax.set_ylim(*ylim)
    ax.set_aspect("equal", adjustable="box")
    ax.set_autoscale_on(False)
    return fig, ax


def _hatch_line(ax, a, b, side, depth, color="black", lw=0.8, n=None, zorder=2):
    """A line a–b with short hatch strokes on ``side`` (unit normal), depth in data units."""
    a, b = np.asarray(a, float), np.asarray(b, float)
    L = float(np.hypot(*(b - a)))
    artists = ax.plot(
        [a[0], b[0]], [a[1], b[1]], color=color, lw=lw, zorder=zorder, solid_capstyle="butt"
    )
    if L == 0:
        return artists
    n = n or max(3, int(L / depth * 1.2))
    u = (b - a) / L
    side = np.asarray(side, float)
    segs = []
    for t in np.linspace(0, L, n + 1)[1:]:
        p = a + t * u
        q = p + depth * side - depth * u
        segs.append([p, q])
    from matplotlib.collections import LineCollection

    lc = LineCollection(segs, colors=color, linewidths=0.6, zorder=zorder)
    ax.add_collection(lc)
    return artists + [lc]


def _arrow(ax, tail, vec, color, *, lw=1.2, head=2.2, zorder=6, ls="-"):
    """An arrow in data units; ``head`` in paper mm."""
    from matplotlib.patches import FancyArrowPatch

    tip = np.asarray(tail, float) + np.asarray(vec, float)
    pts_per_mm = 72 / 25.4
    a = FancyArrowPatch(
        tuple(tail),
        tuple(tip),
        arrowstyle=f"-|>,head_length={head * pts_per_mm:.2f},"
        f"head_width={head * pts_per_mm * 0.38:.2f}",
        color=color,
        lw=lw,
        shrinkA=0,
        shrinkB=0,
        zorder=zorder,
        linestyle=ls,
        mutation_scale=1,
    )
    _add(ax, a)
    return a


def _moment_arc(ax, centre, radius, moment, color, zorder=6):
    from matplotlib.patches import FancyArrowPatch
    from matplotlib.path import Path as MPath

    sgn = 1.0 if moment >= 0 else -1.0
    t = np.radians(np.linspace(200, 200 + sgn * 250, 30))
    pts = np.column_stack((centre[0] + radius * np.cos(t), centre[1] + radius * np.sin(t)))
    pts_per_mm = 72 / 25.4
    a = FancyArrowPatch(
        path=MPath(pts),
        arrowstyle=f"-|>,head_length={2.2 * pts_per_mm:.2f},"
        f"head_width={2.2 * pts_per_mm * 0.38:.2f}",
        color=color,
        lw=1.1,
        zorder=zorder,
        mutation_scale=1,
    )
    _add(ax, a)
    return a


def _add(ax, patch):
    """Add a patch without updating data limits (the drawings' limits are fixed)."""
    ax.add_artist(patch)
    return patch


_SUBSCRIPT = str.maketrans("0123456789", "₀₁₂₃₄₅₆₇₈₉")


def _sub(label: str) -> str:
    """Trailing digits as Unicode subscripts: ``F12`` -> ``F₁₂`` (plain text, fast)."""
    m = re.match(r"^(.*?)(\d+)$", label)
    return label if not m else m.group(1) + m.group(2).translate(_SUBSCRIPT)


def _label_offset(p, centre, dist):
    d = np.asarray(p, float) - centre
    n = float(np.hypot(*d))
    u = d / n if n > 1e-12 else np.array([0.7071, 0.7071])
    return p + dist * u


def _draw_static(ax, scene: _Scene, paper: _Paper):
    """Frame pins, guides, hatching, traced paths, the length scale."""
    arts = []
    k = paper.k
    centre = 0.5 * (scene.lo + scene.hi) * 1e3
    for p in scene.pivots.values():
        c = p * 1e3
        tri = np.array([c, c + [-3.2 * k, -5.0 * k], c + [3.2 * k, -5.0 * k]])
        from matplotlib.patches import Polygon as MPoly

        arts.append(_add(ax, MPoly(tri, closed=True, fc="white", ec="black", lw=0.9, zorder=3)))
        arts += _hatch_line(
            ax, c + [-4.6 * k, -5.0 * k], c + [4.6 * k, -5.0 * k], [0, -1], 1.6 * k, n=6, zorder=3
        )
    for g in scene_guides(scene):
        a, b = g.start * 1e3, g.end * 1e3
        u = (b - a) / max(np.hypot(*(b - a)), 1e-12)
        nrm = perp(u)
        for side in (1.0, -1.0):
            off = side * g.half_width * 1e3 * nrm
            arts += _hatch_line(ax, a + off, b + off, side * nrm, 1.6 * k, zorder=2)
    for i, (ref, pts) in enumerate(scene.paths.items()):
        arts += ax.plot(
            pts[:, 0] * 1e3, pts[:, 1] * 1e3, color="#777777", lw=0.8, ls=(0, (3, 2)), zorder=1
        )
        end = pts[int(np.argmax(np.hypot(*(pts * 1e3 - centre).T)))] * 1e3
        right = end[0] > centre[0]
        arts.append(
            ax.annotate(
                f"path of {ref}",
                end,
                xytext=(-3 if right else 3, 3),
                textcoords="offset points",
                ha="right" if right else "left",
                fontsize=6.5,
                color="#555555",
                zorder=1,
                annotation_clip=True,
            )
        )
    # the length scale: a bar of a round length near the lower left corner
    L = nice_scale(0.25 * (scene.hi[0] - scene.lo[0]) * 1e3) / 2
    x0, y0 = scene.lo[0] * 1e3 + 0.3 * scene.pad * 1e3, scene.lo[1] * 1e3 + 0.35 * scene.pad * 1e3
    arts += ax.plot([x0, x0 + L], [y0, y0], color="black", lw=2.0, solid_capstyle="butt", zorder=4)
    arts += ax.plot([x0, x0], [y0 - 0.8 * k, y0 + 0.8 * k], color="black", lw=0.8, zorder=4)
    arts += ax.plot([x0 + L, x0 + L], [y0 - 0.8 * k, y0 + 0.8 * k], color="black", lw=0.8, zorder=4)
    arts.append(
        ax.text(
            x0 + L / 2, y0 + 1.2 * k, f"{L:g} mm", ha="center", va="bottom", fontsize=7, zorder=4
        )
    )
    return arts


def scene_guides(scene: _Scene):
    return tuple(
        _Guide(name, a + lo * u, a + hi * u, half)
        for name, a, u, lo, hi, half in scene.guides_local
    )


def _draw_moving(
    ax,
    scene: _Scene,
    geo: MechanismGeometry,
    paper: _Paper,
    *,
    labels=True,
    forces: list[_Arrow] | None = None,
    mu_f: float | None = None,
    title_artist=None,
):
    """Links, blocks, pins, labels and (optionally) forces at one position."""
    from matplotlib.patches import Circle
    from matplotlib.patches import Polygon as MPoly

    from .joints import Revolute

    arts = []
    k = paper.k
    model = scene.model
    for n, pts in geo.outlines.items():
        c = scene.colors[n]
        P = pts * 1e3
        if n in geo.plates:
            arts.append(_add(ax, MPoly(P, closed=True, fc=c, alpha=0.22, ec=c, lw=1.6, zorder=4)))
        elif len(P) >= 2:
            arts += ax.plot(P[:, 0], P[:, 1], color=c, lw=3.2, solid_capstyle="round", zorder=4)
    for b in geo.blocks:
        c = scene.colors.get(b.link, "black")
        u, nrm = b.direction, perp(b.direction)
        L, h = b.length * 1e3, b.height * 1e3
        cen = b.centre * 1e3
        corners = np.array(
            [
                cen + sx * L / 2 * u + sy * h / 2 * nrm
                for sx, sy in ((-1, -1), (1, -1), (1, 1), (-1, 1))
            ]
        )
        arts.append(_add(ax, MPoly(corners, closed=True, fc="white", ec=c, lw=1.4, zorder=5)))
        arts.append(_add(ax, MPoly(corners, closed=True, fc=c, alpha=0.25, ec="none", zorder=5)))
    for kind, _, link, p, q in geo.wheels:
        c = scene.colors.get(link, "black")
        if kind == "circle":
            arts.append(
                _add(ax, Circle(p * 1e3, q * 1e3, fc="none", ec=c, lw=1.0, ls="-.", zorder=4))
            )
        else:
            arts += ax.plot(
                [p[0] * 1e3, q[0] * 1e3],
                [p[1] * 1e3, q[1] * 1e3],
                color=c,
                lw=1.0,
                ls="-.",
                zorder=4,
            )
    r = 1.5 * k
    for j in model.joints:
        if isinstance(j, Revolute):
            c = geo.joints[j.name] * 1e3
            arts.append(_add(ax, Circle(c, r, fc="white", ec="black", lw=1.0, zorder=7)))
    pins = [geo.joints[j.name] for j in model.joints if isinstance(j, Revolute)]
    for n, S in geo.com.items():
        if any(np.hypot(*(S - pin)) * 1e3 < 1.5 * k for pin in pins):
            continue  # a pin already marks the spot
        from matplotlib.patches import Wedge

        c = S * 1e3
        arts.append(_add(ax, Circle(c, 1.1 * k, fc="white", ec="black", lw=0.7, zorder=8)))
        arts.append(_add(ax, Wedge(c, 1.1 * k, 0, 90, fc="black", ec="none", zorder=8)))
        arts.append(_add(ax, Wedge(c, 1.1 * k, 180, 270, fc="black", ec="none", zorder=8)))
    if labels:
        centre = 0.5 * (scene.lo + scene.hi) * 1e3
        placed: list[list] = []  # [position, names, clearance]

        def put(p, name, clearance):
            for entry in placed:
                if np.hypot(*(entry[0] - p)) < 0.6 * k:
                    if name not in entry[1]:
                        entry[1].append(name)
                    entry[2] = max(entry[2], clearance)
                    return
            placed.append([p, [name], clearance])

        block_at = {b.joint: 0.5 * np.hypot(b.length, b.height) * 1e3 for b in geo.blocks}
        for j in model.joints:
            if j.name not in geo.joints:
                continue
            name = j.name if isinstance(j, Revolute) else getattr(j, "point_name", j.name)
            put(geo.joints[j.name] * 1e3, name, block_at.get(j.name, 0.0))
        for entry in placed:  # a block sits on a pin at the same place
            for b in geo.blocks:
                if np.hypot(*(b.centre * 1e3 - entry[0])) < 0.6 * k:
                    entry[2] = max(entry[2], block_at[b.joint])
        joint_names = {nm for entry in placed for nm in entry[1]}
        for ref, p in geo.points.items():
            link, _, pname = ref.partition(".")
            if link == scene.ground or pname in joint_names:
                continue
            put(p * 1e3, pname, 0.0)
        for p, names, clearance in placed:
            q = _label_offset(p, centre, max(4.2 * k, clearance + 2.2 * k))
            arts.append(
                ax.text(
                    q[0],
                    q[1],
                    "/".join(names),
                    ha="center",
                    va="center",
                    fontsize=8,
                    zorder=9,
                    fontweight="bold",
                    color="#222222",
                )
            )
        for n, pts in geo.outlines.items():  # link numbers at the middle of each link
            mid = pts.mean(axis=0) * 1e3
            if n in geo.plates:
                pos = mid
            elif len(pts) >= 2:
                d = (pts[-1] - pts[0]) * 1e3
                pos = mid + 2.6 * k * perp(d / max(np.hypot(*d), 1e-12))
            else:
                continue
            arts.append(
                ax.text(
                    pos[0],
                    pos[1],
                    str(scene.numbers[n]),
                    ha="center",
                    va="center",
                    fontsize=7,
                    color=scene.colors[n],
                    zorder=9,
                    bbox=dict(boxstyle="circle,pad=0.15", fc="white", ec=scene.colors[n], lw=0.6),
                )
            )
        for b in geo.blocks:
            if b.link in geo.outlines and len(geo.outlines[b.link]) >= 2:
                continue
            pos = b.centre * 1e3 + (b.height * 1e3 / 2 + 2.4 * k) * perp(b.direction) * -1
            arts.append(
                ax.text(
                    pos[0],
                    pos[1],
                    str(scene.numbers[b.link]),
                    ha="center",
                    va="center",
                    fontsize=7,
                    color=scene.colors[b.link],
                    zorder=9,
                    bbox=dict(
                        boxstyle="circle,pad=0.15", fc="white", ec=scene.colors[b.link], lw=0.6
                    ),
                )
            )
    if forces:
        for a in forces:
            c = FORCE_COLORS[a.kind]
            at = a.at * 1e3
            if a.force is None:
                if a.moment == 0:
                    continue
                arts.append(_moment_arc(ax, at, 5.5 * k, a.moment, c))
                arts.append(
                    ax.text(
                        at[0] + 6.5 * k,
                        at[1] + 5.0 * k,
                        f"{_sub(a.label)} {a.moment:+.3g} N·m",
                        fontsize=6.5,
                        color=c,
                        zorder=10,
                    )
                )
                continue
            mag = float(np.hypot(*a.force))
            if mag < 1e-12:
                continue
            vec = a.force / mu_f * k  # paper mm -> data mm
            arts.append(_arrow(ax, at, vec, c, lw=1.2))
            tip = at + vec
            arts.append(
                ax.text(
                    tip[0],
                    tip[1],
                    f" {_sub(a.label)}",
                    fontsize=6.5,
                    color=c,
                    zorder=10,
                    ha="left",
                    va="bottom",
                )
            )
    return arts


def _force_scale(arrows: list[_Arrow], target_mm: float = 28.0) -> float:
    mags = [float(np.hypot(*a.force)) for a in arrows if a.force is not None]
    m = max(mags + [1e-9])
    return nice_scale(m / target_mm)


def draw_mechanism(
    result,
    position: float | None = None,
    *,
    row: int | None = None,
    forces: bool = False,
    friction: bool = False,
    paths: Iterable[str] = (),
    labels: bool = True,
    dpi: float = DPI,
    max_size_mm=(160.0, 120.0),
):
    """The mechanism at one position, to a true scale μ_l, with a length scale.

    Parameters
    ----------
    position : float, optional
        Driver coordinate (deg, or mm for a prismatic driver) of an analysed
        row; default the first row (``row`` selects by index instead).
    forces : bool
        Draw the loads at that position to one force scale μ_F: the joint
        reactions (force of link i on link j, drawn at the joint, ``F_ij`` with
        the picture's link numbers), d'Alembert inertia forces and couples
        (``FI``, ``MI``), weights (``G``), active external loads and the
        driving torque.  ``friction`` uses the consistent friction solution.
    paths : names ``"link.point"`` whose paths over the analysed rows are traced.

    Returns
    -------
    matplotlib.figure.Figure
        Axes in mm; printed at 100 %, 1 mm of paper is μ_l m (in the title).
    """
    k = row if row is not None else row_at(result, position)
    with _rc():
        scene = _Scene(result, paths)
        span = scene.hi - scene.lo
        mu_l = nice_scale(max(span[0] / max_size_mm[0], span[1] / max_size_mm[1]) * 1e3) / 1e3
        paper = _Paper(mu_l)
        fig, ax = _layout(
            (scene.lo[0] * 1e3, scene.hi[0] * 1e3),
            (scene.lo[1] * 1e3, scene.hi[1] * 1e3),
            paper.k,
            dpi=dpi,
            top=14.0 if forces else 11.0,
        )
        ax.grid(False)
        ax.set_xlabel("x, mm")
        ax.set_ylabel("y, mm")
        _draw_static(ax, scene, paper)
        geo = scene.geometry(k)
        arrows, mu_f = None, None
        if forces:
            arrows = _loads_at(result, k, friction=friction)
            mu_f = _force_scale(arrows)
        _draw_moving(ax, scene, geo, paper, labels=labels, forces=arrows, mu_f=mu_f)
        title = f"{scene.model.name}: {_position_title(result, k)}   {MU['l']} = {_fmt_scale(mu_l)} m/mm"
        if forces:
            title += f",  {MU['F']} = {_fmt_scale(mu_f)} N/mm"
            title += "\nF_ij: link i on link j at the joint; FI, MI: inertia; G: weight" + (
                " (with friction)" if friction else ""
            )
        ax.set_title(title, loc="left", fontsize=8.5)
    return fig


# -- output motion ------------------------------------------------------------------
def _joint_coordinate(result, joint):
    """(c, ċ, c̈) of a joint's relative coordinate over all rows."""
    system = result.system
    k = system.model.joints.index(joint)
    n = len(result)
    ext = lambda a: np.concatenate((a, np.zeros((n, 3))), axis=-1)
    qe, ve, ae = ext(result.q), ext(result.qd), ext(result.qdd)
    i, j = system.ends[k]
    sl = lambda a, m: a[:, 3 * m : 3 * m + 3]
    qi, qj = sl(qe, i), sl(qe, j)
    gi, gj = joint.motion_direction(qi, qj)
    c = joint.coordinate(qi, qj)
    cd = np.sum(gi * sl(ve, i), axis=-1) + np.sum(gj * sl(ve, j), axis=-1)
    cdd = (
        np.sum(gi * sl(ae, i), axis=-1)
        + np.sum(gj * sl(ae, j), axis=-1)
        + joint.coordinate_bias(qi, qj, sl(ve, i), sl(ve, j))
    )
    return c, cd, cdd


def output_motion(result, output: str | None = None) -> dict:
    """Position, velocity and acceleration of the output, over the rows.

    ``output``: a prismatic joint (its sliding coordinate s = (P_j − A_i)·u_i,
    ṡ, s̈), a link (θ, ω, α), or ``"link.point"`` (x, y components).  Default:
    the first undriven prismatic pair on the frame (the output slider), else
    any undriven prismatic pair, else the last link solved.

    Returns ``{"name", "kind" ("slide"|"link"|"point"), "series": [(label,
    unit, values (n,) or (n, 2)) × 3]}`` in SI.
    """
    from .joints import Prismatic

    system, model = result.system, result.system.model
    driven = {d.joint.name for d in system.motion_drivers}
    if output is None:
        slides = [j for j in model.joints if isinstance(j, Prismatic) and j.name not in driven]
        on_frame = [j for j in slides if model.ground.name in j.links]
        if on_frame or slides:
            output = (on_frame or slides)[0].name
        else:
            output = system.plans[-1].group.links[-1]
    joints = {j.name: j for j in model.joints}
    if output in joints:
        j = joints[output]
        c, cd, cdd = _joint_coordinate(result, j)
        if j.angular:
            return {
                "name": output,
                "kind": "joint",
                "series": [
                    (f"relative angle of {output}", "deg", np.degrees(c)),
                    ("relative angular velocity", "rad/s", cd),
                    ("relative angular acceleration", "rad/s²", cdd),
                ],
            }
        pj = f"{j.links[1]}.{j.point_name}"
        return {
            "name": output,
            "kind": "slide",
            "series": [
                (f"s of {pj} along {output}", "mm", c * 1e3),
                ("v = ds/dt", "m/s", cd),
                ("a = d²s/dt²", "m/s²", cdd),
            ],
        }
    if output in system.links:
        return {
            "name": output,
            "kind": "link",
            "series": [
                (f"θ of {output}", "deg", result[f"{output}.theta"]),
                (f"ω of {output}", "rad/s", result[f"{output}.omega"]),
                (f"α of {output}", "rad/s²", result[f"{output}.alpha"]),
            ],
        }
    if f"{output}.x" in result.columns and output.count(".") == 1:
        xy = lambda s: np.column_stack(
            (
                result[f"{output}.{s}x" if s else f"{output}.x"],
                result[f"{output}.{s}y" if s else f"{output}.y"],
            )
        )
        return {
            "name": output,
            "kind": "point",
            "series": [
                (f"position of {output}", "mm", xy("") * 1e3),
                (f"velocity of {output}", "m/s", xy("v")),
                (f"acceleration of {output}", "m/s²", xy("a")),
            ],
        }
    names = (
        list(joints)
        + list(system.links)
        + [f"{lk.name}.{p}" for lk in model.moving_links for p in lk.points]
    )
    raise PictureError(
        f"no output '{output}' (a joint, a link or link.point){did_you_mean(output, names)}"
    )


def _active_spans(result) -> list[tuple[str, float, float]]:
    """Travel intervals where each load with ``active:`` conditions acts."""
    from .forces import activity

    system = result.system
    x, order, _ = _sorted(result)
    ref = abs(_driver(result).driver.motion.speed)
    spans = []
    for load in system.model.loads:
        if not load.active:
            continue
        on = activity(system, load, result.q, result.qd, result.coordinate, result.extremes, ref)[
            order
        ]
        ev = np.array([_is_event_row(result, int(i)) for i in order])
        k = 0
        while k < len(on):
            if not on[k]:
                k += 1
                continue
            m = k
            while m + 1 < len(on) and on[m + 1]:
                m += 1
            x0 = x[k - 1] if k > 0 and ev[k - 1] else x[k]
            x1 = x[m + 1] if m + 1 < len(on) and ev[m + 1] else x[m]
            spans.append((load.name, float(x0), float(x1)))
            k = m + 1
    return spans


def _is_event_row(result, k) -> bool:
    return any(abs(result.t[k] - e.t) < 1e-9 * max(1.0, abs(e.t)) for e in result.events)


def _mark(ax, result, *, top: bool = True, spans=None):
    """Loads' active zones shaded, events as dashed lines (labelled 1′ … in the top
    panel), course positions 1…12 on a top axis."""
    spans = _active_spans(result) if spans is None else spans
    for n, (name, x0, x1) in enumerate(spans):
        ax.axvspan(x0, x1, color=EVENT_COLOR, alpha=0.07, lw=0, zorder=0)
    ticks = _course_ticks(result)
    for xe, lab in ticks:
        if "′" in lab:
            ax.axvline(xe, color=EVENT_COLOR, lw=0.8, ls=(0, (4, 2)), zorder=1)
            if top:
                right = xe > 0.9 * 360
                ax.text(
                    xe,
                    0.97,
                    f"{lab} " if right else f" {lab}",
                    transform=ax.get_xaxis_transform(),
                    color=EVENT_COLOR,
                    fontsize=7,
                    va="top",
                    ha="right" if right else "left",
                )
    if not ticks:
        for e in result.events:
            ax.axvline(
                _event_travel(result, e), color=EVENT_COLOR, lw=0.8, ls=(0, (4, 2)), zorder=1
            )
    if top and ticks:
        sec = ax.secondary_xaxis("top")
        numbered = [(t, lab) for t, lab in ticks if "′" not in lab]
        sec.set_xticks([t for t, _ in numbered])
        sec.set_xticklabels([lab for _, lab in numbered], fontsize=6.5)
        sec.tick_params(length=2, pad=1)
        sec.set_xlabel("course positions", fontsize=6.5, labelpad=2)
    if _angular(result) and result.full_cycle:
        ax.set_xlim(0, 360)
        ax.set_xticks(np.arange(0, 361, 30))


def _event_legend(ax, result):
    if result.events:
        ax.plot(
            [],
            [],
            color=EVENT_COLOR,
            lw=0.8,
            ls=(0, (4, 2)),
            label="load switches (" + ", ".join(sorted({e.load for e in result.events})) + ")",
        )
    names = sorted({name for name, _, _ in _active_spans(result)})
    if names:
        ax.fill_between(
            [], [], color=EVENT_COLOR, alpha=0.1, lw=0, label=", ".join(names) + " acting"
        )


def _cycle_mean(result, values) -> float:
    """Mean over the driver coordinate (trapezoids over the sorted rows, closed over
    the cycle for a full cycle); NaN where a value is missing."""
    x, order, _ = _sorted(result)
    y = np.asarray(values, dtype=float)[order]
    ok = np.isfinite(y)
    if not ok.any():
        return float("nan")
    closed = bool(ok[0]) and result.full_cycle and _angular(result)
    x, y = x[ok], y[ok]
    if closed:
        x, y = np.append(x, 360.0), np.append(y, y[0])
    if len(x) < 2 or x[-1] == x[0]:
        return float(np.mean(y))
    return float(np.sum(0.5 * (y[1:] + y[:-1]) * np.diff(x)) / (x[-1] - x[0]))


def _sorted(result):
    x, label = _abscissa(result)
    order = np.argsort(x, kind="stable")
    return x[order], order, label


def motion_diagram(result, output: str | None = None, *, dpi: float = DPI):
    """The motion diagram of the output: position, velocity, acceleration over the
    driver coordinate (three panels), loads' zones and events marked, course
    positions on top.  ``output`` as in :func:`output_motion`."""
    out = output_motion(result, output)
    x, order, xlabel = _sorted(result)
    spans = _active_spans(result)
    with _rc():
        fig = _figure(165, 150, dpi)
        axes = fig.subplots(3, 1, sharex=True)
        for n, (ax, (label, unit, vals)) in enumerate(zip(axes, out["series"])):
            vals = np.asarray(vals)[order]
            if vals.ndim == 2:
                ax.plot(x, vals[:, 0], color=CURVE_COLORS[0], label="x component")
                ax.plot(x, vals[:, 1], color=CURVE_COLORS[1], label="y component")
            else:
                ax.plot(x, vals, color=CURVE_COLORS[n])
            ax.set_ylabel(f"{label.split(' of ')[0]}, {unit}")
            if n > 0:
                ax.axhline(0, color="black", lw=0.5)
            _mark(ax, result, top=(n == 0), spans=spans)
        _event_legend(axes[0], result)
        if axes[0].get_legend_handles_labels()[0]:
            axes[0].legend(loc="best", fontsize=7)
        axes[-1].set_xlabel(xlabel)
        what = {
            "slide": "output slider",
            "link": f"link {out['name']}",
            "point": f"point {out['name']}",
            "joint": f"joint {out['name']}",
        }[out["kind"]]
        fig.suptitle(
            f"{result.system.model.name}: motion diagram of the {what}"
            + (f" ({out['series'][0][0]})" if out["kind"] == "slide" else ""),
            x=0.02,
            ha="left",
            fontsize=9.5,
        )
        fig.align_ylabels(axes)
        fig.subplots_adjust(left=0.12, right=0.97, top=0.875, bottom=0.08, hspace=0.12)
    return fig


def reaction_curves(
    result, *, friction: bool = False, joints: Sequence[str] | None = None, dpi: float = DPI
):
    """Magnitude |F| of every joint's reaction over the driver coordinate (N);
    with ``friction`` the consistent friction solution dashed in the same colour."""
    model = result.system.model
    names = list(joints) if joints else [j.name for j in model.joints]
    x, order, xlabel = _sorted(result)
    nums = link_numbers(result.system)
    with _rc():
        fig = _figure(165, 95, dpi)
        ax = fig.add_subplot()
        for n, name in enumerate(names):
            if f"{name}.Fx" not in result.columns:
                raise PictureError(
                    f"no joint '{name}'{did_you_mean(name, [j.name for j in model.joints])}"
                )
            j = model.joint(name)
            c = CURVE_COLORS[n % len(CURVE_COLORS)]
            mag = np.hypot(result[f"{name}.Fx"], result[f"{name}.Fy"])[order]
            ax.plot(x, mag, color=c, label=f"{name} (F{nums[j.links[0]]}{nums[j.links[1]]})")
            if friction and f"{name}.Fx_friction" in result.columns:
                magf = np.hypot(result[f"{name}.Fx_friction"], result[f"{name}.Fy_friction"])[order]
                ax.plot(x, magf, color=c, ls="--", lw=1.0)
        if friction:
            ax.plot([], [], color="black", ls="--", lw=1.0, label="with friction (consistent)")
        _mark(ax, result)
        _event_legend(ax, result)
        ax.set_xlabel(xlabel)
        ax.set_ylabel("reaction magnitude |F|, N")
        fig.suptitle(f"{model.name}: joint reactions", x=0.02, ha="left", fontsize=9.5)
        ax.set_ylim(bottom=0)
        ax.legend(loc="upper left", bbox_to_anchor=(1.0, 1.0))
        fig.subplots_adjust(left=0.09, right=0.74, top=0.80, bottom=0.14)
    return fig


def _driver_effort(result, driver: str | None):
    system = result.system
    ds = {d.name: d for d in system.motion_drivers}
    d = ds.get(driver) if driver else system.motion_drivers[0]
    if d is None:
        raise PictureError(f"no motion driver '{driver}'{did_you_mean(driver, ds)}")
    joint = system.model.joint(d.driver.balance_at) if d.driver.balance_at else d.joint
    word, unit = ("torque", "N·m") if joint.angular else ("force", "N")
    return d, word, unit


def torque_curves(result, driver: str | None = None, *, dpi: float = DPI):
    """The driving torque (or force) without friction, with the approximate and
    with the consistent friction, on one plot; events marked; the cycle means."""
    d, word, unit = _driver_effort(result, driver)
    x, order, xlabel = _sorted(result)
    series = [
        ("", "without friction", CURVE_COLORS[0], "-"),
        (
            "_friction_approx",
            "with friction, approximate (from frictionless reactions)",
            CURVE_COLORS[1],
            "--",
        ),
        ("_friction", "with friction, consistent", CURVE_COLORS[3], "-"),
    ]
    with _rc():
        fig = _figure(165, 95, dpi)
        ax = fig.add_subplot()
        for suffix, label, c, ls in series:
            key = f"{d.name}.{word}{suffix}"
            if key not in result.columns:
                continue
            y = np.asarray(result[key])[order]
            mean = _cycle_mean(result, result[key])
            ax.plot(
                x,
                y,
                color=c,
                ls=ls,
                lw=1.6 if ls == "-" else 1.3,
                zorder=3 if ls == "-" else 4,
                label=f"{label} (cycle mean {mean:.4g} {unit})",
            )
        status = result.columns.get("friction.status")
        if status is not None and np.any(status[order] == 2):
            locked = x[status[order] == 2]
            ax.plot(locked, np.zeros_like(locked), "x", color="black", ms=4, label="self-locking")
        ax.axhline(0, color="black", lw=0.5)
        _mark(ax, result)
        _event_legend(ax, result)
        ax.set_xlabel(xlabel)
        sym = "M" if word == "torque" else "F"
        ax.set_ylabel(
            f"{sym}, {unit} (counter-clockwise +)" if word == "torque" else f"{sym}, {unit}"
        )
        fig.suptitle(
            f"{result.system.model.name}: driving {word} of {d.name}",
            x=0.02,
            ha="left",
            fontsize=9.5,
        )
        ax.legend(loc="upper center", bbox_to_anchor=(0.5, -0.16), ncol=1)
        fig.subplots_adjust(left=0.1, right=0.97, top=0.81, bottom=0.36)
    return fig


def efficiency_curve(result, driver: str | None = None, *, dpi: float = DPI):
    """Instantaneous efficiency η = M / M_friction (frictionless over consistent
    driving torque) and the cycle efficiency (ratio of the mean input powers)."""
    d, word, _ = _driver_effort(result, driver)
    key = f"{d.name}.efficiency"
    if key not in result.columns:
        raise PictureError(f"no friction in {result.system.model.name}: no efficiency to plot")
    x, order, xlabel = _sorted(result)
    eta = np.asarray(result[key])[order]
    with _rc():
        fig = _figure(165, 85, dpi)
        ax = fig.add_subplot()
        ax.plot(x, eta, color=CURVE_COLORS[2], label="η = M / M_friction (instantaneous)")
        pin = result.columns.get("power.input")
        pinf = None
        if f"{d.name}.{word}_friction" in result.columns and pin is not None:
            ok = np.isfinite(result[f"{d.name}.{word}_friction"])
            m0 = _cycle_mean(result, np.where(ok, result[f"{d.name}.{word}"], np.nan))
            m1 = _cycle_mean(result, result[f"{d.name}.{word}_friction"])
            if m1 != 0 and result.full_cycle:
                pinf = m0 / m1
                ax.axhline(
                    pinf,
                    color="black",
                    ls="--",
                    lw=0.9,
                    label=f"cycle efficiency (mean M / mean M_friction) = {pinf:.4f}",
                )
        finite = eta[np.isfinite(eta)]
        lo = max(min(float(np.percentile(finite, 2)) if finite.size else 0.0, 0.0), -1.0)
        ax.set_ylim(lo - 0.05, 1.1)
        _mark(ax, result)
        _event_legend(ax, result)
        ax.set_xlabel(xlabel)
        ax.set_ylabel("efficiency η, 1")
        fig.suptitle(
            f"{result.system.model.name}: efficiency of the drive {d.name} "
            "(axis clipped where M_friction → 0)",
            x=0.02,
            ha="left",
            fontsize=9.5,
        )
        ax.legend(loc="lower left")
        fig.subplots_adjust(left=0.1, right=0.97, top=0.79, bottom=0.15)
    return fig


def plot_result(result, *names: str, dpi: float = DPI):
    """Any columns over the driver coordinate, one panel per unit."""
    if not names:
        raise PictureError("name at least one column to plot")
    for n in names:
        result[n]  # KeyError with a suggestion
    x, order, xlabel = _sorted(result)
    units: dict[str, list[str]] = {}
    for n in names:
        units.setdefault(result.units[n], []).append(n)
    with _rc():
        fig = _figure(165, 45 + 45 * len(units), dpi)
        axes = np.atleast_1d(fig.subplots(len(units), 1, sharex=True))
        for ax, (unit, cols) in zip(axes, units.items()):
            for k, n in enumerate(cols):
                ax.plot(x, np.asarray(result[n])[order], color=CURVE_COLORS[k % 10], label=n)
            ax.set_ylabel(unit.replace("*", "·").replace("^2", "²"))
            ax.legend(loc="best")
            _mark(ax, result, top=ax is axes[0])
        axes[-1].set_xlabel(xlabel)
        fig.suptitle(result.system.model.name, x=0.02, ha="left", fontsize=9.5)
        fig.subplots_adjust(
            left=0.11, right=0.97, top=1 - 16 / (45 + 45 * len(units)), bottom=0.1, hspace=0.15
        )
    return fig


# -- polar diagrams -----------------------------------------------------------------
def link_frame_loads(result, joint: str, *, friction: bool = False) -> tuple[str, str, np.ndarray]:
    """A joint's load in a link-fixed frame, over the rows.

    The frame is that of the joint's link j (the reaction's receiver) when j
    moves, else that of link i with the force reversed.  Returns ``(link,
    description, F (n, 2))``: the force on ``link``, in N, along that link's
    local x and y axes (the axes its points are given in).
    """
    model = result.system.model
    try:
        j = model.joint(joint)
    except StopIteration:
        raise PictureError(
            f"no joint '{joint}'{did_you_mean(joint, [x.name for x in model.joints])}"
        ) from None
    sfx = "_friction" if friction and f"{joint}.Fx_friction" in result.columns else ""
    F = np.column_stack((result[f"{joint}.Fx{sfx}"], result[f"{joint}.Fy{sfx}"]))
    i_link, j_link = j.links
    if j_link != model.ground.name:
        link, desc = j_link, f"force of {i_link} on {j_link}"
    else:
        link, desc, F = i_link, f"force of {j_link} on {i_link}", -F
    _, th = _poses(result, link)
    return link, desc, rotate(-th, F)


def polar_diagrams(
    result, joints: Sequence[str] | None = None, *, friction: bool = False, dpi: float = DPI
):
    """Polar diagrams: the tip of each joint's load vector in a link-fixed frame
    over the cycle (for sizing bearings), with the course positions numbered.
    Default: every revolute joint."""
    from .joints import Revolute

    model = result.system.model
    if joints is None:
        joints = [j.name for j in model.joints if isinstance(j, Revolute)]
    joints = list(joints)
    if not joints:
        raise PictureError("no joint to draw a polar diagram of")
    nums = link_numbers(result.system)
    course = course_positions(result)
    n = len(joints)
    cols = min(3, n)
    rows = math.ceil(n / cols)
    _, order, _ = _sorted(result)
    with _rc():
        fig = _figure(60 * cols + 8, 62 * rows + 14, dpi)
        for m, name in enumerate(joints):
            ax = fig.add_subplot(rows, cols, m + 1)
            link, desc, F = link_frame_loads(result, name, friction=friction)
            F = F[order]
            closed = np.vstack((F, F[:1])) if result.full_cycle else F
            ax.plot(closed[:, 0], closed[:, 1], color=CURVE_COLORS[0], lw=1.2)
            ax.plot([0], [0], "+", color="black", ms=7, mew=1.0)
            inv = np.empty_like(order)
            inv[order] = np.arange(len(order))
            for lab, k in course:
                p = F[inv[k]]
                ax.plot([0, p[0]], [0, p[1]], color="#aaaaaa", lw=0.5, zorder=0)
                ax.plot(*p, "o", ms=2.5, color=EVENT_COLOR if "′" in lab else "black")
                ax.annotate(
                    lab,
                    p,
                    xytext=(2, 2),
                    textcoords="offset points",
                    fontsize=6,
                    color=EVENT_COLOR if "′" in lab else "black",
                )
            mag = np.hypot(F[:, 0], F[:, 1])
            if not np.isfinite(mag).any():  # friction solution self-locked throughout
                ax.text(
                    0.5,
                    0.5,
                    "no values:\nself-locking at\nevery position",
                    transform=ax.transAxes,
                    ha="center",
                    va="center",
                    fontsize=7,
                )
                ax.set_title(f"{name}: no consistent friction solution", fontsize=7.5)
                continue
            kmax = int(np.nanargmax(mag))
            ax.plot([0, F[kmax, 0]], [0, F[kmax, 1]], color=CURVE_COLORS[3], lw=1.0)
            lim = 1.12 * float(np.nanmax(mag)) if np.nanmax(mag) > 0 else 1.0
            ax.set_xlim(-lim, lim)
            ax.set_ylim(-lim, lim)
            ax.set_aspect("equal", adjustable="box")
            j = model.joint(name)
            ax.set_title(
                f"{name}: F{nums[j.links[0]]}{nums[j.links[1]]}, {desc.split(' of ')[1]}\n"
                f"in the frame of {link}; max {mag[kmax]:.4g} N",
                fontsize=7.5,
            )
            ax.set_xlabel(f"F along {link} x, N", fontsize=7)
            ax.set_ylabel(f"F along {link} y, N", fontsize=7)
            ax.tick_params(labelsize=6.5)
        fig.suptitle(
            f"{model.name}: polar diagrams of the joint loads"
            + (" (with friction)" if friction else "")
            + " — numbers: course positions",
            fontsize=9,
            x=0.02,
            ha="left",
        )
        fig.subplots_adjust(
            left=0.1,
            right=0.97,
            top=1 - 14 / (62 * rows + 14) - 0.02,
            bottom=0.08,
            wspace=0.45,
            hspace=0.55,
        )
    return fig


# -- velocity and acceleration polygons ----------------------------------------------
@dataclass(frozen=True)
class PolygonNode:
    """A point of the polygon: the tip of an absolute vector drawn from the pole."""

    label: str  # e.g. "a2" (acceleration polygons add a prime when drawn)
    refs: tuple[str, ...]  # the points it stands for, "link.point" (coincident: "bar@A")
    vector: np.ndarray  # (2,) absolute velocity (m/s) or acceleration (m/s²)


@dataclass(frozen=True)
class PolygonChain:
    """A vector equation: node ``end`` = node ``start`` + Σ components.

    ``start`` is ``"p"`` (the pole) for a link pivoted on the frame.
    Components are ``(name, vector)``: ω×r (``v_CB``), or ω²r and α×r
    (``an_CB``, ``at_CB``), the sliding velocity ``vr_A2A3`` or the Coriolis
    and relative accelerations ``ak_A2A3``, ``ar_A2A3``.
    """

    start: str
    end: str
    link: str
    components: tuple


@dataclass(frozen=True)
class Polygon:
    kind: str  # "velocity" or "acceleration"
    row: int
    nodes: dict  # label -> PolygonNode (the pole "p" is the origin)
    chains: tuple  # PolygonChain
    fixed: tuple  # refs at the pole (points at rest)
    unit: str

    def tip(self, label: str) -> np.ndarray:
        return np.zeros(2) if label == "p" else self.nodes[label].vector


class _UnionFind:
    def __init__(self):
        self.parent: dict = {}

    def find(self, x):
        self.parent.setdefault(x, x)
        while self.parent[x] != x:
            self.parent[x] = self.parent[self.parent[x]]
            x = self.parent[x]
        return x

    def union(self, a, b):
        ra, rb = self.find(a), self.find(b)
        if ra != rb:
            self.parent[rb] = ra


def polygon(result, row: int = 0, kind: str = "velocity") -> Polygon:
    """The velocity or acceleration polygon at ``row``, from the exact results.

    Nodes are the named points of the moving links (points joined by a
    revolute are one node; a prismatic pair adds the point of link i that
    coincides with the sliding point of link j).  Points at rest sit at the
    pole p.  Labels are the lower-case point names, with the link number
    (:func:`link_numbers`) appended where a name is shared (``a2``, ``a3``).
    For each moving link, in solve order, a chain goes from its base node (at
    rest, or shared with a link solved earlier) to each of its other nodes with
    the relative vector ω×r (velocities) or the normal −ω²r and tangential α×r
    components (accelerations); each prismatic pair adds the chain from link
    i's coincident point to the sliding point: ṡu, or the Coriolis 2ω_i×ṡu and
    the relative s̈u.  The relative vectors are computed from ω, α, ṡ, s̈ and
    the positions, independently of the absolute point kinematics, so the
    polygon's closure is a check of the results.
    """
    from .joints import Prismatic, Revolute

    if kind not in ("velocity", "acceleration"):
        raise PictureError(f"polygon kind must be 'velocity' or 'acceleration', not '{kind}'")
    acc = kind == "acceleration"
    system, model = result.system, result.system.model
    ground = model.ground.name
    nums = link_numbers(system)
    q, qd, qdd = result.q[row], result.qd[row], result.qdd[row]
    l_ref = system.l_ref
    # link points: (link, name) -> position, vector
    pts: dict[tuple[str, str], tuple[np.ndarray, np.ndarray]] = {}
    for k, n in enumerate(system.links):
        for pname, p in model.link(n).points.items():
            pos, vel, a = point_state(q, qd, qdd, k, np.asarray(p, float))
            pts[(n, pname)] = (pos, a if acc else vel)
    uf = _UnionFind()
    rest = "@rest"
    uf.find(rest)
    for key in pts:
        uf.find(key)
    for n in system.links:  # coincident named points of one link
        keys = [key for key in pts if key[0] == n]
        for x in range(len(keys)):
            for y in range(x + 1, len(keys)):
                if np.hypot(*(pts[keys[x]][0] - pts[keys[y]][0])) < 1e-9 * l_ref:
                    uf.union(keys[x], keys[y])
    joint_name_of: dict = {}
    for j in model.joints:
        if isinstance(j, Revolute):
            a_key, b_key = (j.links[0], j.point_names[0]), (j.links[1], j.point_names[1])
            a_key = rest if j.links[0] == ground else a_key
            b_key = rest if j.links[1] == ground else b_key
            uf.union(a_key, b_key)
            for key in (a_key, b_key):
                if key != rest:
                    joint_name_of.setdefault(key, j.name)
    coincident: dict[str, tuple] = {}  # prismatic joint -> (i key, j key)
    for j in model.joints:
        if not isinstance(j, Prismatic):
            continue
        i_link, j_link = j.links
        j_key = (j_link, j.point_name) if j_link != ground else rest
        if i_link == ground:
            i_key = rest
        else:
            k = system.link_index(i_link)
            Pj = _to_global(result, j_link, j.p, row)
            r, th = q[3 * k : 3 * k + 2], q[3 * k + 2]
            local = rotate(-th, Pj - r)
            pos, vel, a = point_state(q, qd, qdd, k, local)
            i_key = (i_link, f"@{j.name}")
            pts[i_key] = (pos, a if acc else vel)
            uf.find(i_key)
        coincident[j.name] = (i_key, j_key)
    # nodes
    groups: dict = {}
    for key in list(pts) + [rest]:
        groups.setdefault(uf.find(key), []).append(key)
    rest_root = uf.find(rest)

    def base_name(key):
        if key[1].startswith("@"):
            return model.joint(key[1][1:]).point_name
        return joint_name_of.get(key, key[1])

    node_keys = [keys for root, keys in groups.items() if root != rest_root]
    names = {}
    for keys in node_keys:
        real = [k for k in keys if not k[1].startswith("@")]
        names[id(keys)] = base_name(sorted(real or keys, key=lambda k: nums[k[0]])[0]).lower()
    counts: dict[str, int] = {}
    for keys in node_keys:
        counts[names[id(keys)]] = counts.get(names[id(keys)], 0) + 1
    nodes: dict[str, PolygonNode] = {}
    label_of: dict = {}
    for keys in sorted(node_keys, key=lambda ks: min(nums[k[0]] for k in ks)):
        label = names[id(keys)]
        if counts[label] > 1:
            label += str(max(nums[k[0]] for k in keys))
        base, m = label, 2
        while label in nodes or label == "p":
            label, m = f"{base}_{m}", m + 1
        refs = tuple(
            f"{k[0]}.{k[1]}"
            if not k[1].startswith("@")
            else f"{k[0]}@{model.joint(k[1][1:]).point_name}"
            for k in keys
        )
        nodes[label] = PolygonNode(label, refs, pts[keys[0]][1])
        for k in keys:
            label_of[k] = label
    fixed = tuple(f"{k[0]}.{k[1]}" for k in groups[rest_root] if k != rest)
    for k in groups[rest_root]:
        label_of[k] = "p"
    # chains: per moving link in solve order, from its base node
    order = [n for p in system.plans for n in p.group.links]
    solved: set[str] = {ground}
    chains = []
    for n in order:
        k = system.link_index(n)
        keys = [key for key in pts if key[0] == n]
        labels = []
        for key in keys:
            if label_of[key] not in labels:
                labels.append(label_of[key])
        if not labels:
            solved.add(n)
            continue
        shared = [
            lab
            for lab in labels
            if lab == "p"
            or any(label_of.get(key) == lab for key in pts if key[0] in solved and key[0] != n)
        ]
        base = shared[0] if shared else labels[0]
        r_base = _node_position(pts, label_of, base, n)
        w, alpha = qd[3 * k + 2], qdd[3 * k + 2]
        for lab in labels:
            if lab == base:
                continue
            d = _node_position(pts, label_of, lab, n) - r_base
            if np.hypot(*d) < 1e-9 * l_ref:
                continue
            sub = (lab + (base if base != "p" else "")).upper()
            if acc:
                comps = (("an_" + sub, -(w**2) * d), ("at_" + sub, alpha * perp(d)))
            else:
                comps = (("v_" + sub, w * perp(d)),)
            chains.append(PolygonChain(base, lab, n, comps))
        solved.add(n)
    for j in model.joints:
        if not isinstance(j, Prismatic):
            continue
        i_key, j_key = coincident[j.name]
        start, end = label_of[i_key], label_of[j_key]
        if start == end:
            continue
        _, cd, cdd = (v[row] for v in _joint_coordinate(result, j))
        _, th = _poses(result, j.links[0], row)
        U = rotate(th, np.asarray(j.u, float))
        w_i = 0.0 if j.links[0] == ground else qd[3 * system.link_index(j.links[0]) + 2]
        sub = (end + (start if start != "p" else "")).upper()
        if acc:
            comps = (("ak_" + sub, 2 * w_i * perp(cd * U)), ("ar_" + sub, cdd * U))
        else:
            comps = (("vr_" + sub, cd * U),)
        chains.append(PolygonChain(start, end, j.name, comps))
    return Polygon(kind, row, nodes, tuple(chains), fixed, "m/s²" if acc else "m/s")


def _node_position(pts, label_of, label, link):
    for key, (pos, _) in pts.items():
        if key[0] == link and label_of[key] == label:
            return pos
    for key, (pos, _) in pts.items():
        if label_of[key] == label:
            return pos
    raise KeyError(label)


def _drawn_chains(poly: Polygon, tol: float):
    """Chains worth drawing: drop components below ``tol`` and chains from the pole
    that repeat an absolute vector (a link pivoted on the frame, velocities)."""
    out = []
    for ch in poly.chains:
        comps = [(n, v) for n, v in ch.components if np.hypot(*v) > tol]
        if not comps:
            continue
        if ch.start == "p" and len(comps) == 1:
            continue
        out.append((ch, comps))
    return out


_DIRECTION = {
    "v": "⊥ {r}",
    "vr": "∥ axis of {j}",
    "an": "∥ {r}, towards {b}",
    "at": "⊥ {r}",
    "ak": "⊥ axis of {j}",
    "ar": "∥ axis of {j}",
}
_PRETTY = {"v": "v", "vr": "v", "an": "a^n", "at": "a^t", "ak": "a^k", "ar": "a^r"}


def polygon_figure(
    result,
    kind: str = "velocity",
    position: float | None = None,
    *,
    row: int | None = None,
    dpi: float = DPI,
    max_size_mm: float = 105.0,
):
    """The velocity or acceleration polygon at one position, to a stated scale.

    Absolute vectors from the pole p (p′ for accelerations) to the lettered
    points; relative vectors (thin; dashed components end at the intermediate
    points n (normal) and k (Coriolis)) that close it.  Axes in m/s or m/s²;
    printed at 100 %, 1 mm of paper is μ_v (μ_a) as stated.  The magnitudes
    and directions of all vectors are listed beside it.
    """
    k = row if row is not None else row_at(result, position)
    poly = polygon(result, k, kind)
    acc = kind == "acceleration"
    prime = "'" if acc else ""
    nums = link_numbers(result.system)
    model = result.system.model
    tips = [np.zeros(2)] + [nd.vector for nd in poly.nodes.values()]
    scale_ref = max([float(np.hypot(*t)) for t in tips] + [1e-300])
    chains = _drawn_chains(poly, 1e-9 * scale_ref)
    for ch, comps in chains:
        p = poly.tip(ch.start).copy()
        for _, v in comps:
            p = p + v
            tips.append(p.copy())
    allp = np.array(tips)
    lo, hi = allp.min(axis=0), allp.max(axis=0)
    span = float(max(np.max(hi - lo), 1e-12))
    mu = nice_scale(span / max_size_mm)
    pad = 0.1 * span + 7 * mu
    lo, hi = lo - pad, hi + pad
    colors = {n: LINK_COLORS[i % len(LINK_COLORS)] for i, n in enumerate(result.system.links)}
    sym = "a" if acc else "v"
    # the list of vectors
    rest = sorted({r.split(".")[1] for r in poly.fixed})
    lines = [
        f"pole {_tex('p' + prime)}: points at rest" + (f" ({', '.join(rest)})" if rest else "")
    ]
    for lab, nd in poly.nodes.items():
        pts = ", ".join(r.replace("@", " at ") for r in nd.refs)
        lines.append(
            f"{_tex('p' + prime)}{_tex(lab + prime)}: {sym}({pts}) = "
            f"{np.hypot(*nd.vector):.4g} {poly.unit}"
        )
    for ch, comps in chains:
        joint = model.joint(ch.link) if ch.link in [j.name for j in model.joints] else None
        for name, v in comps:
            kind_name, sub = name.split("_", 1)
            pretty = _PRETTY[kind_name]
            tex = pretty.split("^")
            head = tex[0] + (f"^{{{tex[1]}}}" if len(tex) > 1 else "")
            end = ch.end.upper()
            start = (
                ch.start.upper()
                if ch.start != "p"
                else "".join(r.split(".")[1] for r in poly.fixed if r.split(".")[0] == ch.link)[:8]
                or "pivot"
            )
            direction = _DIRECTION[kind_name].format(r=f"{end}{start}", b=start, j=ch.link)
            owner = ch.link if joint is None else f"{ch.link}, {type(joint).__name__.lower()}"
            lines.append(
                f"${head}_{{\\mathrm{{{sub}}}}}$ = {np.hypot(*v):.4g} {poly.unit}, "
                f"{direction} ({owner})"
            )
    list_mm = 3.35 * len(lines) + 8
    with _rc():
        fig, ax = _layout(
            (lo[0], hi[0]),
            (lo[1], hi[1]),
            mu,
            extra_right=66.0,
            dpi=dpi,
            min_mm=(60.0, max(60.0, list_mm - 24.0)),
            top=14.0,
        )
        ax.set_xlabel(f"{sym}_x, {poly.unit}")
        ax.set_ylabel(f"{sym}_y, {poly.unit}")
        ax.axhline(0, color="#bbbbbb", lw=0.5, zorder=0)
        ax.axvline(0, color="#bbbbbb", lw=0.5, zorder=0)
        k_mm = mu  # data units per paper mm
        labels_at: list[list] = []

        def put(p, text, color="black", size=8.5):
            for entry in labels_at:
                if np.hypot(*(entry[0] - p)) < 1.2 * k_mm:
                    entry[1].append(text)
                    return
            labels_at.append([p, [text], color, size])

        for lab, nd in poly.nodes.items():
            link = nd.refs[0].split(".")[0].split("@")[0]
            c = colors.get(link, "black")
            norm = float(np.hypot(*nd.vector))
            if norm > 1e-9 * scale_ref:
                _arrow(ax, (0.0, 0.0), nd.vector, c, lw=1.5, head=2.6)
            put(nd.vector, lab + prime)
        ax.plot([0], [0], "o", color="black", ms=2.5, zorder=8)
        for ch, comps in chains:
            p = poly.tip(ch.start).copy()
            c = colors.get(ch.link, "#555555")
            for m, (name, v) in enumerate(comps):
                last = m == len(comps) - 1
                _arrow(ax, p, v, c, lw=0.9, head=2.0, ls="-" if last else (0, (4, 1.5)))
                p = p + v
                if not last:
                    tag = ("n" if name.startswith("an") else "k") + ch.end + prime
                    ax.plot(*p, "o", ms=1.8, color=c, zorder=8)
                    if min(np.hypot(*v), np.hypot(*comps[m + 1][1])) > 2.0 * k_mm:
                        put(p.copy(), tag, c, 7)
        centre = 0.5 * (lo + hi)
        boxes = [(0.0, 0.0, 1.2, 1.2)] + [
            (e[0][0] / k_mm, e[0][1] / k_mm, 1.2, 1.2) for e in labels_at
        ]  # (x, y, half w, half h), mm
        boxes.append((-2.6, -2.6, 1.6, 1.8))  # the pole's label

        def free(x, y, hw, hh):
            return all(abs(x - bx) >= hw + bw or abs(y - by) >= hh + bh for bx, by, bw, bh in boxes)

        for p, texts, c, size in labels_at:
            text = ", ".join(_tex(t) for t in texts)
            hw = 0.5 * 0.62 * size * 0.3528 * (sum(len(t) for t in texts) + 2 * (len(texts) - 1))
            hh = 0.5 * 1.25 * size * 0.3528
            d = p - centre
            n = float(np.hypot(*d))
            out = d / n if n > 0 else np.array([0.7071, 0.7071])
            pm = p / k_mm
            spot = pm + (hw + 1.5) * out
            done = False
            for dist in (1.5, 3.0, 5.0):
                for turn in (0, 45, -45, 90, -90, 135, -135, 180):
                    a_ = math.radians(turn)
                    u = np.array(
                        [
                            out[0] * math.cos(a_) - out[1] * math.sin(a_),
                            out[0] * math.sin(a_) + out[1] * math.cos(a_),
                        ]
                    )
                    cand = pm + u * np.array([hw + dist, hh + dist])
                    if free(cand[0], cand[1], hw, hh):
                        spot, done = cand, True
                        break
                if done:
                    break
            boxes.append((spot[0], spot[1], hw, hh))
            ax.text(
                *(spot * k_mm), text, ha="center", va="center", fontsize=size, color=c, zorder=9
            )
        ax.text(
            *(np.array([-2.6, -2.6]) * k_mm),
            _tex("p" + prime),
            ha="center",
            va="center",
            fontsize=8.5,
            zorder=9,
        )
        mu_name = MU["a" if acc else "v"]
        title = (
            f"{model.name}: {kind} polygon, {_position_title(result, k)}\n"
            f"{mu_name} = {_fmt_scale(mu)} ({poly.unit})/mm;  links: "
            + ", ".join(f"{v} {n}" for n, v in nums.items())
        )
        ax.set_title(title, loc="left", fontsize=8)
        W, H = fig.get_figwidth() / MM, fig.get_figheight() / MM
        fig.text(
            1 - 64.0 / W,
            1 - 15.0 / H,
            "\n".join(lines),
            va="top",
            ha="left",
            fontsize=6.2,
            linespacing=1.5,
        )
    return fig


# -- animation ---------------------------------------------------------------------
def animate(
    result,
    path: str | Path,
    *,
    forces: bool = False,
    friction: bool = False,
    paths: Iterable[str] = (),
    fps: float = 20.0,
    dpi: float = 80.0,
    max_size_mm=(160.0, 120.0),
) -> Path:
    """Write an animation of the mechanism over the result's rows (one frame per row,
    in order of travel): ``.gif`` through Pillow, ``.mp4`` only if ffmpeg is on the
    PATH.  ``forces`` overlays the loads at one force scale for the whole cycle.
    Returns the path written.
    """
    import shutil
    import subprocess

    path = Path(path)
    suffix = path.suffix.lower()
    if suffix not in (".gif", ".mp4"):
        raise PictureError(
            f"{path}: an animation is written as .gif (or .mp4 with ffmpeg), "
            f"not '{suffix or 'no suffix'}'"
        )
    ffmpeg = shutil.which("ffmpeg") if suffix == ".mp4" else None
    if suffix == ".mp4" and ffmpeg is None:
        raise PictureError(f"{path}: writing MP4 needs ffmpeg on the PATH; write a .gif instead")
    from matplotlib.backends.backend_agg import FigureCanvasAgg

    _, order, _ = _sorted(result)
    with _rc():
        scene = _Scene(result, paths)
        span = scene.hi - scene.lo
        mu_l = nice_scale(max(span[0] / max_size_mm[0], span[1] / max_size_mm[1]) * 1e3) / 1e3
        paper = _Paper(mu_l)
        fig, ax = _layout(
            (scene.lo[0] * 1e3, scene.hi[0] * 1e3),
            (scene.lo[1] * 1e3, scene.hi[1] * 1e3),
            paper.k,
            dpi=dpi,
            top=14.0 if forces else 11.0,
        )
        ax.grid(False)
        ax.set_xlabel("x, mm")
        ax.set_ylabel("y, mm")
        mu_f = None
        loads = {}
        if forces:
            loads = {k: _loads_at(result, int(k), friction=friction) for k in order}
            mu_f = _force_scale([a for arr in loads.values() for a in arr])
        head = f"{scene.model.name}   {MU['l']} = {_fmt_scale(mu_l)} m/mm" + (
            f",  {MU['F']} = {_fmt_scale(mu_f)} N/mm" if forces else ""
        )
        ax.set_title(head + ("\n" if forces else ""), loc="left", fontsize=8.5)
        _draw_static(ax, scene, paper)
        canvas = FigureCanvasAgg(fig)
        canvas.draw()
        background = canvas.copy_from_bbox(fig.bbox)
        w, h = canvas.get_width_height()
        frames = []
        proc = None
        if ffmpeg:
            proc = subprocess.Popen(
                [
                    ffmpeg,
                    "-y",
                    "-loglevel",
                    "error",
                    "-f",
                    "rawvideo",
                    "-pix_fmt",
                    "rgba",
                    "-s",
                    f"{w}x{h}",
                    "-r",
                    f"{fps:g}",
                    "-i",
                    "-",
                    "-pix_fmt",
                    "yuv420p",
                    "-vf",
                    "pad=ceil(iw/2)*2:ceil(ih/2)*2",
                    str(path),
                ],
                stdin=subprocess.PIPE,
            )
        from PIL import Image

        palette = None
        for k in order:
            k = int(k)
            canvas.restore_region(background)
            geo = scene.geometry(k)
            arts = _draw_moving(ax, scene, geo, paper, labels=True, forces=loads.get(k), mu_f=mu_f)
            t = ax.text(
                0.99,
                0.99,
                _position_title(result, k),
                ha="right",
                va="top",
                fontsize=8,
                transform=ax.transAxes,
                zorder=11,
            )
            arts.append(t)
            for a in arts:
                ax.draw_artist(a)
            buf = np.asarray(canvas.buffer_rgba())
            if proc is not None:
                proc.stdin.write(buf.tobytes())
            else:
                img = Image.fromarray(buf[..., :3].copy())
                if palette is None:
                    palette = img.quantize(colors=128, method=Image.Quantize.MEDIANCUT)
                frames.append(img.quantize(palette=palette, dither=Image.Dither.NONE))
            for a in arts:
                a.remove()
    if proc is not None:
        proc.stdin.close()
        if proc.wait() != 0:
            raise PictureError(f"{path}: ffmpeg failed (exit {proc.returncode})")
        return path
    path.parent.mkdir(parents=True, exist_ok=True)
    frames[0].save(
        path,
        save_all=True,
        append_images=frames[1:],
        duration=int(round(1000 / fps)),
        loop=0,
        optimize=False,
        disposal=1,
    )
    return path
