"""The mechanism drawn at one position: frame, links, labels and the loads
(free-body view) (:func:`draw_mechanism`)."""

from __future__ import annotations

from collections.abc import Iterable
from dataclasses import dataclass

import numpy as np

from ...base.geometry import perp
from ...kinetics.forces import activity, point_state
from ...kinetics.kinds import LOAD_KINDS
from ..labels import reaction_symbol
from ..lang import tr
from .elements import draw_elements
from .rows import _angular, _driver, _position_title, link_numbers, row_at
from .scene import MechanismGeometry, _joint_point, _Scene, _to_global, scene_guides
from .style import (
    DPI,
    FORCE_COLORS,
    MIN_AXES_MM,
    MU,
    ROUND_OFF,
    _add,
    _arrow,
    _dodge,
    _fit_sheet,
    _fmt_scale,
    _hatch_line,
    _inside_axes,
    _label_offset,
    _layout,
    _moment_arc,
    _Paper,
    _rc,
    _sub,
    nice_scale,
)


# -- loads at one position (free-body view) --------------------------------------
@dataclass(frozen=True)
class _Arrow:
    kind: str  # reaction, inertia, gravity, external, effort
    label: str
    at: np.ndarray  # (2,) m
    force: np.ndarray | None  # (2,) N, or None for a couple
    moment: float = 0.0  # N·m (couples)


def _loads_at(result, row: int, *, friction: bool = False) -> list[_Arrow]:
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
        out.append(_Arrow("reaction", reaction_symbol(j.links, nums), at, F))
    g = np.asarray(model.gravity, float)
    for k, n in enumerate(system.links):
        lk = model.link(n)
        S = _to_global(result, n, np.zeros(2), row)
        if lk.mass > 0:
            a = result.qdd[row, 3 * k : 3 * k + 2]
            out.append(_Arrow("inertia", f"F_I{nums[n]}", S, -lk.mass * a))
            if np.any(g):
                out.append(_Arrow("gravity", f"G{nums[n]}", S, lk.mass * g))
        if lk.inertia > 0:
            out.append(
                _Arrow(
                    "inertia", f"M_I{nums[n]}", S, None, -lk.inertia * result.qdd[row, 3 * k + 2]
                )
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
        pos = point_state(q, qd, None, k, p)[0]
        force, couple = LOAD_KINDS[load.kind].applied(system, load, q, qd, value, ref)
        if couple is not None:  # the signed couple on its link
            out.append(_Arrow("external", load.name, pos[0], None, float(np.ravel(couple)[0])))
            continue
        out.append(_Arrow("external", load.name, pos[0], np.asarray(force, float).ravel()))
    for d in system.motion_drivers:
        joint = model.joint(d.driver.balance_at) if d.driver.balance_at else d.joint
        word = "torque" if joint.angular else "force"
        e = (
            float(result[f"{d.name}.{word}{suffix}"][row])
            if f"{d.name}.{word}{suffix}" in result.columns
            else float(result[f"{d.name}.{word}"][row])
        )
        at = _joint_point(result, joint, row)
        if joint.angular and at is not None:
            # the balancing torque M_b (平衡力矩), named by its driver where there are several
            name = "M_b" if len(system.motion_drivers) == 1 else f"M_b {d.name}"
            out.append(_Arrow("effort", name, at, None, e))
    return out


def _draw_static(ax, scene: _Scene, paper: _Paper, lang: str = "en"):
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
    for ref, pts in scene.paths.items():
        arts += ax.plot(
            pts[:, 0] * 1e3, pts[:, 1] * 1e3, color="#777777", lw=0.8, ls=(0, (3, 2)), zorder=1
        )
        end = pts[int(np.argmax(np.hypot(*(pts * 1e3 - centre).T)))] * 1e3
        right = end[0] > centre[0]
        arts.append(
            ax.annotate(
                tr("path of {ref}", lang, ref=ref),
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


def _draw_moving(
    ax,
    scene: _Scene,
    geo: MechanismGeometry,
    paper: _Paper,
    *,
    labels=True,
    forces: list[_Arrow] | None = None,
    mu_f: float | None = None,
    l_ref: float = 1.0,
):
    """Links, blocks, pins, labels and (optionally) forces at one position."""
    k = paper.k
    arts = _draw_links(ax, scene, geo)
    if scene.model.elements:
        arts += draw_elements(ax, scene.model, geo, 0.025 * float(np.max(scene.system.l_ref)))
    arts += _draw_pins(ax, scene, geo, k)
    if labels:
        arts += _draw_labels(ax, scene, geo, k)
    if forces:
        arts += _draw_loads(ax, forces, mu_f, k, l_ref)
    return arts


def _draw_links(ax, scene: _Scene, geo: MechanismGeometry):
    """The links' outlines (bars, plates), the sliding blocks and the pitch lines."""
    from matplotlib.patches import Circle
    from matplotlib.patches import Polygon as MPoly

    arts = []
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
        elif kind == "curve":  # a cam's profile: drawn solid, closed when it is
            P = np.concatenate((p, p[:1])) if q else p
            arts += ax.plot(P[:, 0] * 1e3, P[:, 1] * 1e3, color=c, lw=1.4, zorder=4)
        else:
            arts += ax.plot(
                [p[0] * 1e3, q[0] * 1e3],
                [p[1] * 1e3, q[1] * 1e3],
                color=c,
                lw=1.0,
                ls="-.",
                zorder=4,
            )
    return arts


def _draw_pins(ax, scene: _Scene, geo: MechanismGeometry, k: float):
    """The pins, and the centre-of-mass marks where no pin already stands."""
    from matplotlib.patches import Circle

    arts = []
    model = scene.model
    r = 1.5 * k
    for j in model.joints:
        if j.pin:
            c = geo.joints[j.name] * 1e3
            arts.append(_add(ax, Circle(c, r, fc="white", ec="black", lw=1.0, zorder=7)))
    pins = [geo.joints[j.name] for j in model.joints if j.pin]
    for S in geo.com.values():
        if any(np.hypot(*(S - pin)) * 1e3 < 1.5 * k for pin in pins):
            continue  # a pin already marks the spot
        from matplotlib.patches import Wedge

        c = S * 1e3
        arts.append(_add(ax, Circle(c, 1.1 * k, fc="white", ec="black", lw=0.7, zorder=8)))
        arts.append(_add(ax, Wedge(c, 1.1 * k, 0, 90, fc="black", ec="none", zorder=8)))
        arts.append(_add(ax, Wedge(c, 1.1 * k, 180, 270, fc="black", ec="none", zorder=8)))
    return arts


def _draw_labels(ax, scene: _Scene, geo: MechanismGeometry, k: float):
    """The point names (one label per spot, clear of blocks) and the link numbers."""
    arts = []
    centre = 0.5 * (scene.lo + scene.hi) * 1e3
    for p, names, clearance in _label_spots(scene, geo, k):
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
        arts.append(_link_number(ax, scene, n, pos))
    for b in geo.blocks:
        if b.link in geo.outlines and len(geo.outlines[b.link]) >= 2:
            continue
        pos = b.centre * 1e3 + (b.height * 1e3 / 2 + 2.4 * k) * perp(b.direction) * -1
        arts.append(_link_number(ax, scene, b.link, pos))
    return arts


def _label_spots(scene: _Scene, geo: MechanismGeometry, k: float) -> list[list]:
    """The labelled spots, mm: [position, names, clearance] (joints, then link points)."""
    model = scene.model
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
        put(geo.joints[j.name] * 1e3, j.label(), block_at.get(j.name, 0.0))
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
    return placed


def _link_number(ax, scene: _Scene, n: str, pos):
    """Link ``n``'s number in a circle at ``pos`` (mm)."""
    return ax.text(
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


def _draw_loads(ax, forces: list[_Arrow], mu_f: float | None, k: float, l_ref: float = 1.0):
    """The loads: forces as arrows to the scale ``mu_f`` (N/mm), couples as arcs.  A force
    or couple below round-off (1e-9 of the largest force, or of the largest couple or
    force × l_ref) is not drawn: it is zero to the scale."""
    arts = []
    f_max = max([float(np.hypot(*a.force)) for a in forces if a.force is not None] + [0.0])
    m_max = max([abs(a.moment) for a in forces if a.force is None] + [f_max * l_ref])
    for a in forces:
        c = FORCE_COLORS[a.kind]
        at = a.at * 1e3
        if a.force is None:
            if not abs(a.moment) > ROUND_OFF * m_max:
                continue
            arts.append(_moment_arc(ax, at, 5.5 * k, a.moment, c))
            t = ax.text(
                at[0] + 6.5 * k,
                at[1] + 5.0 * k,
                f"{_sub(a.label)} {a.moment:+.3g} N·m",
                fontsize=6.5,
                color=c,
                zorder=10,
            )
            t.set_gid("load-label")
            arts.append(t)
            continue
        mag = float(np.hypot(*a.force))
        if not mag > ROUND_OFF * f_max:
            continue
        vec = a.force / mu_f * k  # paper mm -> data mm
        arts.append(_arrow(ax, at, vec, c, lw=1.2))
        tip = at + vec
        right = vec[0] >= 0
        t = ax.text(
            tip[0],
            tip[1],
            f" {_sub(a.label)} " if right else f"{_sub(a.label)} ",
            fontsize=6.5,
            color=c,
            zorder=10,
            ha="left" if right else "right",
            va="bottom" if vec[1] >= 0 else "top",
        )
        t.set_gid("load-label")
        arts.append(t)
    return arts


def _force_scale(arrows: list[_Arrow], target_mm: float = 28.0) -> float:
    mags = [float(np.hypot(*a.force)) for a in arrows if a.force is not None]
    m = max(mags + [1e-9])
    return nice_scale(m / target_mm)


def _drawing_sheet(result, paths, max_size_mm, dpi, forces, loads=None):
    """The scene, its paper scale, an empty sheet in mm that holds it (drawing,
    animation) and the force scale μ_F of ``loads`` (None without): the drawing area
    grows to hold every force arrow of ``loads``, and is at least MIN_AXES_MM."""
    scene = _Scene(result, paths)
    span = scene.hi - scene.lo
    mu_l = nice_scale(max(span[0] / max_size_mm[0], span[1] / max_size_mm[1]) * 1e3) / 1e3
    paper = _Paper(mu_l)
    lo, hi = scene.lo * 1e3, scene.hi * 1e3
    mu_f = None
    if loads:
        mu_f = _force_scale(loads)
        ends = [a.at * 1e3 + a.force / mu_f * paper.k for a in loads if a.force is not None]
        ends += [a.at * 1e3 for a in loads]
        if ends:
            ends = np.asarray(ends)
            margin = 3.0 * paper.k
            lo = np.minimum(lo, ends.min(axis=0) - margin)
            hi = np.maximum(hi, ends.max(axis=0) + margin)
    fig, ax = _layout(
        (lo[0], hi[0]),
        (lo[1], hi[1]),
        paper.k,
        dpi=dpi,
        top=14.0 if forces else 11.0,
        min_mm=MIN_AXES_MM,
    )
    ax.grid(False)
    ax.set_xlabel("x, mm")
    ax.set_ylabel("y, mm")
    return scene, paper, fig, ax, mu_f


def _sheet_title(result, scene, paper, mu_f, row=None, friction=False, lang="en") -> str:
    """The title: the position, then the scales, then (with forces) what the labels mean."""
    head = scene.model.name + (f": {_position_title(result, row, lang)}" if row is not None else "")
    scales = f"{MU['l']} = {_fmt_scale(paper.mu_l)} m/mm"
    if mu_f is not None:
        scales += f",  {MU['F']} = {_fmt_scale(mu_f)} N/mm"
    lines = [head, scales]
    if mu_f is not None:
        lines.append(
            tr("F_Rij: link i on link j at the joint; F_I, M_I: inertia; G: weight", lang)
            + (tr(" (with friction)", lang) if friction else "")
        )
    return "\n".join(lines)


def draw_mechanism(  # noqa: PLR0913  the public keywords (docs/pictures.md)
    result,
    position: float | None = None,
    *,
    row: int | None = None,
    forces: bool = False,
    friction: bool = False,
    paths: Iterable[str] = (),
    labels: bool = True,
    dpi: float = DPI,
    lang: str = "en",
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
        reactions (force of link i on link j, drawn at the joint, ``F_Rij`` with
        the picture's link numbers), d'Alembert inertia forces and couples
        (``F_Ii``, ``M_Ii``), weights (``Gi``), active external loads and the
        driving torque.  ``friction`` uses the consistent friction solution.
    paths : names ``"link.point"`` whose paths over the analysed rows are traced.

    Returns
    -------
    matplotlib.figure.Figure
        Axes in mm; printed at 100 %, 1 mm of paper is μ_l m (in the title).
    """
    k = row if row is not None else row_at(result, position)
    with _rc(lang):
        arrows = _loads_at(result, k, friction=friction) if forces else None
        scene, paper, fig, ax, mu_f = _drawing_sheet(
            result, paths, max_size_mm, dpi, forces, arrows
        )
        static = _draw_static(ax, scene, paper, lang)
        geo = scene.geometry(k)
        arts = _draw_moving(
            ax, scene, geo, paper, labels=labels, forces=arrows, mu_f=mu_f, l_ref=_l_ref(scene)
        )
        ax.set_title(
            _sheet_title(result, scene, paper, mu_f, k, friction, lang), loc="left", fontsize=8.5
        )
        _settle(fig, ax, static + arts)
    return fig


def _l_ref(scene) -> float:
    return float(np.max(scene.hi - scene.lo))


def _settle(fig, ax, arts) -> None:
    """Labels of the loads clear of each other and of the point labels, everything
    inside the axes, the sheet sized around it all."""
    from matplotlib.text import Text

    texts = [a for a in arts if isinstance(a, Text)]
    movable = [t for t in texts if t.get_gid() == "load-label"]
    fixed = [t for t in texts if t.get_gid() != "load-label"]
    if movable:
        _dodge(fig, ax, movable, fixed)
    inside = texts + [a for a in arts if type(a).__name__ == "FancyArrowPatch"]
    _inside_axes(fig, ax, inside)
    _fit_sheet(fig, ax)
