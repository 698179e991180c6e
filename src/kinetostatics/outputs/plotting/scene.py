"""Geometry of the drawing: link poses, joint points, pitch circles and lines,
outlines, blocks and guides (:class:`MechanismGeometry`, :func:`mechanism_geometry`)."""

from __future__ import annotations

import math
from collections.abc import Iterable
from dataclasses import dataclass

import numpy as np

from ...base.geometry import perp, rotate
from ...errors import did_you_mean
from .rows import link_numbers
from .style import LINK_COLORS, PictureError


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


def _pose(result, link: str, rows=slice(None)) -> np.ndarray:
    """q = (x, y, θ) ``(..., 3)`` of a link over rows; zeros for the frame."""
    system = result.system
    q = result.q[rows]
    if link == system.model.ground.name:
        return np.zeros(q.shape[:-1] + (3,))
    k = system.link_index(link)
    return q[..., 3 * k : 3 * k + 3]


def _glyph(result, joint, rows=slice(None)):
    """What the joint draws (:class:`~kinetostatics.joints.Glyph`) over rows."""
    i_link, j_link = joint.links
    return joint.glyph(_pose(result, i_link, rows), _pose(result, j_link, rows))


def _joint_point(result, joint, rows=slice(None)):
    """Global position where a joint's reaction acts: the pin of a revolute, the
    sliding point of a prismatic pair, the pitch point of a gear or rack pair;
    ``None`` for a joint type that draws none."""
    return _glyph(result, joint, rows).point


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
    # | ("curve", joint, link, points (n, 2), closed): a cam's profile


class _Scene:
    """Everything about a drawing that does not change with the position."""

    def __init__(self, result, paths: Iterable[str] = ()):
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
        glyphs = {j.name: _glyph(result, j) for j in model.joints}  # over all rows
        self.guides_local = []  # (joint, a, u, s_min, s_max, half)
        for j in model.joints:
            g = glyphs[j.name]
            if g.block is None:
                continue
            given = g.block.length
            L = given if given else 0.12 * l_ref
            h = min(0.6 * L, 0.08 * l_ref) if not given else max(0.35 * L, 0.04 * l_ref)
            self.block_len[j.name], self.block_h[j.name] = L, h
            if g.guide is None:
                continue
            i_link = g.guide.link
            r_i, th_i = _poses(result, i_link)
            a = rotate(-th_i[0], g.guide.point[0] - r_i[0])  # the axis in i's frame
            u = rotate(-th_i[0], g.guide.direction[0])
            loc = rotate(-th_i, g.block.centre - r_i)  # the block's centre in i's frame
            s = (loc - a) @ u
            lo, hi = float(s.min()) - 0.6 * L, float(s.max()) + 0.6 * L
            if i_link == self.ground:
                self.guides_local.append((j.name, a, u, lo, hi, 0.5 * h + 0.004 * l_ref))
            else:
                local[i_link] += [a + lo * u, a + hi * u]
        self.wheels_local = self._wheels(result, glyphs, local, l_ref)
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
            j.name: np.asarray(a.xy, float)
            for j in model.joints
            if j.pin and self.ground in j.links
            for a in j.anchors()
            if a.at_joint and a.link == self.ground
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
        for _name, a, u, lo, hi, half in self.guides_local:
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
            elif kind == "curve":
                chunks += [np.atleast_2d(_to_global(result, link, x)) for x in p[::8]]
            else:
                chunks += [_to_global(result, link, p), _to_global(result, link, q)]
        allp = np.concatenate(chunks)
        lo, hi = allp.min(axis=0), allp.max(axis=0)
        span = max(float(np.max(hi - lo)), l_ref, 1e-9)
        pad = 0.09 * span
        self.lo, self.hi = lo - pad, hi + pad
        self.pad = pad

    @staticmethod
    def _wheels(result, glyphs, local, l_ref) -> list:
        """("circle", joint, link, centre, r) / ("line", joint, link, p0, p1) / ("curve",
        joint, link, points, closed), local to the link; a moving link's pitch line
        extends its outline (``local``)."""
        wheels = []
        model = result.system.model
        for j in model.joints:
            g = glyphs[j.name]
            for c in g.circles:
                r_k, th_k = _poses(result, c.link)
                wheels.append(
                    (
                        "circle",
                        j.name,
                        c.link,
                        rotate(-th_k[0], c.centre[0] - r_k[0]),
                        float(c.radius),
                    )
                )
            for curve in g.curves:  # a cam's profile, fixed in its link
                r_k, th_k = _poses(result, curve.link)
                pts = rotate(-th_k[0], curve.points[0] - r_k[0])
                wheels.append(("curve", j.name, curve.link, pts, curve.closed))
            for line in g.lines:
                link = line.link
                r_k, th_k = _poses(result, link)
                at = line.point if g.point is None else g.point
                P = rotate(-th_k, at - r_k)  # pitch points in link's frame
                u_loc = rotate(-th_k[0], line.direction[0])
                a_loc = rotate(-th_k[0], line.point[0] - r_k[0])
                s = (P - a_loc) @ u_loc
                reach = max((c.radius for c in g.circles), default=0.05 * l_ref)
                p0, p1 = a_loc + (s.min() - reach) * u_loc, a_loc + (s.max() + reach) * u_loc
                wheels.append(("line", j.name, link, p0, p1))
                if link in local:
                    local[link] += [p0, p1]
        return wheels

    def geometry(self, row: int) -> MechanismGeometry:
        result, model = self.result, self.model
        points = {}
        for lk in model.links:
            for name, p in lk.points.items():
                points[f"{lk.name}.{name}"] = _to_global(result, lk.name, p, row)
        glyphs = {j.name: _glyph(result, j, row) for j in model.joints}
        joints = {name: g.point for name, g in glyphs.items() if g.point is not None}
        outlines = {n: _to_global(result, n, pts, row) for n, pts in self.outline_local.items()}
        blocks = [
            _Block(
                name,
                g.block.link,
                g.block.centre,
                g.block.direction,
                self.block_len[name],
                self.block_h[name],
            )
            for name, g in glyphs.items()
            if g.block is not None
        ]
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
                q if kind != "line" else _to_global(result, link, q, row),
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


def scene_guides(scene: _Scene):
    return tuple(
        _Guide(name, a + lo * u, a + hi * u, half)
        for name, a, u, lo, hi, half in scene.guides_local
    )
