"""Velocity and acceleration polygons: the data (:func:`polygon`) and the figure."""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ...base.geometry import perp, rotate

# The graphical method is defined for R and P pairs (a pin merges two points, a
# slider adds a coincident point and the ṡu / Coriolis chain), so it names them.
from ...joints import Prismatic, Revolute
from ...kinetics.forces import point_state
from ..lang import tr
from .curves import _joint_coordinate
from .rows import _position_title, link_numbers, row_at
from .scene import _poses, _to_global
from .style import (
    A4_TEXT_MM,
    DPI,
    LINK_COLORS,
    MM,
    MU,
    ROUND_OFF,
    PictureError,
    _arrow,
    _figure,
    _fit_sheet,
    _fmt_scale,
    _lay_out,
    _layout,
    _rc,
    _renderer,
    _tex,
    nice_scale,
)


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


_REST = "@rest"  # the union-find key of the points at rest


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
    polygon's closure is a check of the results.  Other pairs (gear, rack) add no
    node or chain of their own: their links' points are still chained link by
    link, which is all the polygon of a geared linkage needs.
    """
    if kind not in ("velocity", "acceleration"):
        raise PictureError(f"polygon kind must be 'velocity' or 'acceleration', not '{kind}'")
    acc = kind == "acceleration"
    pts = _link_points(result, row, acc)
    uf, joint_name_of = _merged_points(result, pts)
    coincident = _coincident_points(result, row, acc, pts, uf)
    nodes, label_of, fixed = _nodes(result, pts, uf, joint_name_of)
    chains = _link_chains(result, row, acc, pts, label_of)
    chains += _slider_chains(result, row, acc, coincident, label_of)
    return Polygon(kind, row, nodes, tuple(chains), fixed, "m/s²" if acc else "m/s")


def _link_points(result, row: int, acc: bool) -> dict:
    """The moving links' named points: (link, name) -> (position, velocity or acceleration)."""
    system, model = result.system, result.system.model
    q, qd, qdd = result.q[row], result.qd[row], result.qdd[row]
    pts: dict[tuple[str, str], tuple[np.ndarray, np.ndarray]] = {}
    for k, n in enumerate(system.links):
        for pname, p in model.link(n).points.items():
            pos, vel, a = point_state(q, qd, qdd, k, np.asarray(p, float))
            pts[(n, pname)] = (pos, a if acc else vel)
    return pts


def _merged_points(result, pts: dict) -> tuple[_UnionFind, dict]:
    """The points that are one node: coincident points of a link, the two points of a
    revolute (a point on the frame joins the rest key); and the joint naming each point."""
    system, model = result.system, result.system.model
    ground = model.ground.name
    l_ref = system.l_ref
    uf = _UnionFind()
    uf.find(_REST)
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
            a_key = _REST if j.links[0] == ground else a_key
            b_key = _REST if j.links[1] == ground else b_key
            uf.union(a_key, b_key)
            for key in (a_key, b_key):
                if key != _REST:
                    joint_name_of.setdefault(key, j.name)
    return uf, joint_name_of


def _coincident_points(result, row: int, acc: bool, pts: dict, uf: _UnionFind) -> dict:
    """Per prismatic joint, (i key, j key): the point of link i that coincides with the
    sliding point of link j (added to ``pts`` as ``(i, "@joint")``) and that point."""
    system, model = result.system, result.system.model
    ground = model.ground.name
    q, qd, qdd = result.q[row], result.qd[row], result.qdd[row]
    coincident: dict[str, tuple] = {}  # prismatic joint -> (i key, j key)
    for j in model.joints:
        if not isinstance(j, Prismatic):
            continue
        i_link, j_link = j.links
        j_key = (j_link, j.point_name) if j_link != ground else _REST
        if i_link == ground:
            i_key = _REST
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
    return coincident


def _nodes(result, pts: dict, uf: _UnionFind, joint_name_of: dict):
    """The labelled nodes, the label of every point key (``"p"`` at rest) and the refs
    at the pole."""
    system, model = result.system, result.system.model
    nums = link_numbers(system)
    groups: dict = {}
    for key in list(pts) + [_REST]:
        groups.setdefault(uf.find(key), []).append(key)
    rest_root = uf.find(_REST)

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
    fixed = tuple(f"{k[0]}.{k[1]}" for k in groups[rest_root] if k != _REST)
    for k in groups[rest_root]:
        label_of[k] = "p"
    return nodes, label_of, fixed


def _link_chains(result, row: int, acc: bool, pts: dict, label_of: dict) -> list:
    """Per moving link in solve order, the chains from its base node to its other nodes."""
    system = result.system
    ground = system.model.ground.name
    qd, qdd = result.qd[row], result.qdd[row]
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
            if np.hypot(*d) < 1e-9 * system.l_ref:
                continue
            sub = (lab + (base if base != "p" else "")).upper()
            if acc:
                comps = (("an_" + sub, -(w**2) * d), ("at_" + sub, alpha * perp(d)))
            else:
                comps = (("v_" + sub, w * perp(d)),)
            chains.append(PolygonChain(base, lab, n, comps))
        solved.add(n)
    return chains


def _slider_chains(result, row: int, acc: bool, coincident: dict, label_of: dict) -> list:
    """Per prismatic joint, the chain from link i's coincident point to the sliding point."""
    system, model = result.system, result.system.model
    ground = model.ground.name
    qd = result.qd[row]
    chains = []
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
    return chains


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


def _zero(v: float, scale: float) -> str:
    """4 significant digits; round-off (≤ 1e-9 of the polygon's largest vector) as 0."""
    return "0" if abs(v) <= ROUND_OFF * scale else f"{v:.4g}"


def polygon_figure(
    result,
    kind: str = "velocity",
    position: float | None = None,
    *,
    row: int | None = None,
    dpi: float = DPI,
    lang: str = "en",
    max_size_mm: float = 105.0,
    fit_mm: tuple[float, float] | None = A4_TEXT_MM,
):
    """The velocity or acceleration polygon at one position, to a stated scale.

    Absolute vectors from the pole p (p′ for accelerations) to the lettered
    points; relative vectors (thin; dashed components end at the intermediate
    points n (normal) and k (Coriolis)) that close it.  Axes in m/s or m/s²;
    printed at 100 %, 1 mm of paper is μ_v (μ_a) as stated.  The magnitudes
    and directions of all vectors are listed beside it.  The scale is a round one
    (:func:`.style.nice_scale`) drawing the polygon about ``max_size_mm`` across, or
    the next coarser round one while the sheet is larger than ``fit_mm`` (width,
    height; by default the text area of an A4 page, so that the report prints it
    at 100 %).
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
    span = float(max(np.max(allp.max(axis=0) - allp.min(axis=0)), 1e-12))
    colors = {n: LINK_COLORS[i % len(LINK_COLORS)] for i, n in enumerate(result.system.links)}
    sym = "a" if acc else "v"
    # the list of vectors
    rest = sorted({r.split(".")[1] for r in poly.fixed})
    big = max([float(np.hypot(*nd.vector)) for nd in poly.nodes.values()] + [0.0])
    size = lambda v: _zero(float(np.hypot(*v)), big)  # noqa: E731
    T = lambda s, **k: tr(s, lang, **k)  # noqa: E731
    lines = [
        T("pole {p}: points at rest", p=_tex("p" + prime))
        + (T(" ({names})", names=", ".join(rest)) if rest else "")
    ]
    for lab, nd in poly.nodes.items():
        pts = ", ".join(
            T("{link} at {point}", link=r.split("@")[0], point=r.split("@")[1]) if "@" in r else r
            for r in nd.refs
        )
        lines.append(
            f"{_tex('p' + prime)}{_tex(lab + prime)}: {sym}({pts}) = {size(nd.vector)} {poly.unit}"
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
                or T("pivot")
            )
            direction = T(_DIRECTION[kind_name], r=f"{end}{start}", b=start, j=ch.link)
            owner = ch.link if joint is None else f"{ch.link}, {T(joint.kind)}"
            lines.append(
                f"${head}_{{\\mathrm{{{sub}}}}}$ = {size(v)} {poly.unit}, {direction} ({owner})"
            )
    # the scale: the round value that draws the polygon about max_size_mm across, or the
    # next coarser ones of the series until the sheet fits fit_mm (printed at 100 %, the
    # scale holds on paper: a report never reduces it to an odd one)
    mu, list_mm = nice_scale(span / max_size_mm), None
    for k in range(12):
        if fit_mm is not None and k < 11:  # a scale whose sheet cannot fit is not drawn
            list_mm = _text_width_mm(lines, dpi, lang) if list_mm is None else list_mm
            if _too_large(allp, span, mu, len(lines), list_mm, fit_mm):
                mu = nice_scale(mu * 1.01)
                continue
        fig = _polygon_sheet(result, poly, chains, lines, allp, span, mu, colors, nums, dpi, lang)
        if fit_mm is not None:
            _lay_out(fig)  # its size is the question: laid out now, not when saved (crop.py)
        W, H = fig.get_size_inches() / MM
        if fit_mm is None or (W <= fit_mm[0] and H <= fit_mm[1]):
            break
        mu = nice_scale(mu * 1.01)  # the next value of the series
    return fig


LIST_MM = 66.0  # the sheet's margin right of the axes' (6 mm) for the list of vectors
LIST_AT_MM = 64.0  # the list's left edge, from the sheet's right edge: 8 mm right of the axes


def _extent(allp: np.ndarray, span: float, mu: float, n_lines: int):
    """The axes' data limits (lo, hi) at the scale ``mu`` and their least size in mm."""
    pad = 0.1 * span + 7 * mu
    return (
        allp.min(axis=0) - pad,
        allp.max(axis=0) + pad,
        (60.0, max(60.0, 3.35 * n_lines + 8 - 24.0)),
    )


def _text_width_mm(lines: list[str], dpi: float, lang: str) -> float:
    """The width of the list of vectors as the sheet sets and measures it, mm."""
    with _rc(lang):
        fig = _figure(100.0, 100.0, dpi)
        text = fig.text(0, 0, "\n".join(lines), fontsize=6.2, linespacing=1.5, va="top")
        return text.get_window_extent(_renderer(fig)).width / fig.dpi / MM


def _too_large(allp, span: float, mu: float, n_lines: int, list_mm: float, fit_mm) -> bool:
    """Whether the polygon's sheet at ``mu`` is larger than ``fit_mm`` whatever its texts:
    laid out around everything drawn (2 mm margins), it holds at least the axes' box and,
    ``LIST_MM - LIST_AT_MM + 6`` mm right of it, the list of vectors (0.5 mm to spare)."""
    lo, hi, least = _extent(allp, span, mu, n_lines)
    w, h = np.maximum((hi - lo) / mu, least)
    width = w + (6.0 + LIST_MM - LIST_AT_MM) + list_mm + 2 * 2.0 - 0.5
    return width > fit_mm[0] or h + 2 * 2.0 - 0.5 > fit_mm[1]


def _polygon_sheet(result, poly, chains, lines, allp, span, mu, colors, nums, dpi, lang):  # noqa: PLR0913  the polygon's drawing data
    """The polygon's sheet at the scale ``mu`` (data units per paper mm)."""
    acc = poly.kind == "acceleration"
    prime = "'" if acc else ""
    sym = "a" if acc else "v"
    kind = poly.kind
    k = poly.row
    model = result.system.model
    scale_ref = max([float(np.hypot(*nd.vector)) for nd in poly.nodes.values()] + [1e-300])
    T = lambda s, **k: tr(s, lang, **k)  # noqa: E731
    lo, hi, least = _extent(allp, span, mu, len(lines))
    with _rc(lang):
        fig, ax = _layout(
            (lo[0], hi[0]), (lo[1], hi[1]), mu, extra_right=LIST_MM, dpi=dpi, min_mm=least, top=14.0
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
            f"{model.name}: {tr(kind + ' polygon', lang)}, {_position_title(result, k, lang)}\n"
            f"{mu_name} = {_fmt_scale(mu)} ({poly.unit})/mm;  "
            + T("links: {links}", links=", ".join(f"{v} {n}" for n, v in nums.items()))
        )
        ax.set_title(title, loc="left", fontsize=8)
        W, H = fig.get_figwidth() / MM, fig.get_figheight() / MM
        x0, y0, w, h = ax.get_position().bounds
        ax.text(  # the legend in the right margin, tied to the axes so the sheet fits it
            (1 - LIST_AT_MM / W - x0) / w,
            (1 - 15.0 / H - y0) / h,
            "\n".join(lines),
            va="top",
            ha="left",
            fontsize=6.2,
            linespacing=1.5,
            transform=ax.transAxes,
            clip_on=False,
        )
        _fit_sheet(fig, ax)
    return fig
