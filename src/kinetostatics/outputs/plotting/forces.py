"""The free body of an Assur group and its force polygon, side by side (:func:`group_figure`).

The picture reads the plain data of one group of a force-polygons record
(``GroupPolygon.to_dict()`` of ``kinetostatics.methods.polygons``, or the record itself).
On the left the group's free body: its links as the lines joining the points where
forces act on each (its inner pairs among them), every force an arrow on its line of
action through its point (lengths in proportion to the forces), every couple an arc.
On the right the force polygon: the vectors chained tip to tail at the record's round
scale μ_F (N/mm, drawn at true scale), the known forces first (solid), the solved ones
closing it (dashed); the closure error |Σ F| is printed under it.  A reaction is
labelled ``F_Rij`` (the force of link i on link j) with the link numbers passed in, the
weight ``G_j``, the inertia force and couple ``F_Ij``, ``M_Ij``, the balancing effort
``M_b`` (``F_b``).  The labels are set apart by ``crowding.place_labels``: along each
arrow's normal, the solved forces' first, the known ones smaller; the group is named in
the picture's language from the record's ``kind`` and ``letters`` (:func:`group_title`).
"""

from __future__ import annotations

import numpy as np

from ...base.geometry import perp
from ..labels import pair
from ..lang import tr
from .crowding import Label, place_labels
from .style import (
    DPI,
    FORCE_COLORS,
    LINK_COLORS,
    MM,
    MU,
    _arrow,
    _figure,
    _fmt_scale,
    _moment_arc,
    _rc,
)

__all__ = ["group_figure", "force_label", "group_title"]

_COLOR = {
    "reaction": FORCE_COLORS["reaction"],
    "balancing": FORCE_COLORS["effort"],
    "inertia_force": FORCE_COLORS["inertia"],
    "inertia_couple": FORCE_COLORS["inertia"],
    "weight": FORCE_COLORS["gravity"],
}
PANEL_MM = (65.0, 65.0)  # each panel's drawing area: the polygon fits it at μ_F


def force_label(force: dict, numbers: dict[str, int] | None = None) -> str:
    """A force's mathtext label: ``F_R61`` of a reaction (link 6 on link 1), ``G_5``,
    ``F_I5``, ``M_I5``, ``M_b``, a load by its name; links by name without ``numbers``."""

    def n(link: str) -> str:
        return str(numbers[link]) if numbers and link in numbers else link

    kind, link = force["kind"], force["link"]
    if kind == "reaction":
        ij = pair(numbers[force["by"]], numbers[link]) if numbers else f"{force['by']},{link}"
        return rf"$F_{{R{ij}}}$"
    sub = {"weight": "G_{{{}}}", "inertia_force": "F_{{I{}}}", "inertia_couple": "M_{{I{}}}"}
    if kind in sub:
        return "$" + sub[kind].format(n(link)) + "$"
    if kind == "balancing":
        return "$M_b$" if force["name"].startswith("M_b") else "$F_b$"
    return force["name"].replace("_", " ")


def group_title(data: dict, lang: str = "en") -> str:
    """The group of a polygon record in ``lang`` from its ``kind``, ``letters`` and
    ``links`` ("RPR dyad {block, bar}", "RPR 型Ⅱ级杆组 {block, bar}"); its English
    ``label`` for a record without them."""
    kind, links = data.get("kind", ""), "{" + ", ".join(data["links"]) + "}"
    if kind == "dyad":
        return tr("{letters} dyad {links}", lang, letters=data["letters"], links=links)
    if kind == "driven":
        many = "driving links {links}" if len(data["links"]) > 1 else "driving link {links}"
        return tr(many, lang, links=links)
    if kind == "triad":
        return tr("triad {links}", lang, links=links)
    if kind:
        return tr("{n}-link group {links}", lang, n=len(data["links"]), links=links)
    return data.get("label") or data.get("group", "")


def _plain(record) -> dict:
    to_dict = getattr(record, "to_dict", None)
    return to_dict() if callable(to_dict) else dict(record)


def _free_body(ax, data: dict, numbers) -> None:
    """The group's links (lines through their forces' points, mm) and the forces on them,
    a reaction with friction beside its friction circle (dotted)."""
    from matplotlib.patches import Circle

    forces, inner = data["forces"], data.get("inner", [])
    pts = np.array([f["point"] for f in [*forces, *inner]], dtype=float) * 1e3
    lo, hi = pts.min(axis=0), pts.max(axis=0)
    size = max(float(np.max(hi - lo)), 20.0)
    for k, link in enumerate(data["links"]):
        on = [f["point"] for f in forces if f["link"] == link]
        on += [f["point"] for f in inner if link in (f["link"], f["by"])]
        own = np.array(on, dtype=float).reshape(-1, 2) * 1e3
        if not len(own):
            continue
        if len(own) > 1:
            centre = own.mean(axis=0)
            order = np.argsort(np.arctan2(own[:, 1] - centre[1], own[:, 0] - centre[0]))
            ring = own[order]
            ax.plot(*np.vstack([ring, ring[:1]]).T, color=LINK_COLORS[k % len(LINK_COLORS)],
                    lw=2.0, alpha=0.6, zorder=2)  # fmt: skip
        ax.plot(*own.T, "o", ms=3.0, mfc="white", mec="black", zorder=3)
    largest = max((np.hypot(*f["vector"]) for f in forces), default=0.0) or 1.0
    labels = []
    for f in forces:
        color = _COLOR.get(f["kind"], FORCE_COLORS["external"])
        p, v = np.array(f["point"]) * 1e3, np.array(f["vector"])
        label, primary = force_label(f, numbers), f["status"] == "solved"
        if np.any(v):
            vec = v / largest * 0.35 * size
            start = p - vec if f["status"] == "solved" else p
            _arrow(ax, start, vec, color, lw=1.1)
            labels.append(Label(label, tuple(start + 0.5 * vec), color, tuple(perp(vec)), primary))
        if f.get("friction_radius"):  # the friction circle its line is tangent to
            ax.add_patch(Circle(np.array(f["pin"]) * 1e3, f["friction_radius"] * 1e3,
                                fill=False, ec=color, lw=0.6, ls=":"))  # fmt: skip
        if f["couple"]:
            _moment_arc(ax, p, 0.06 * size, f["couple"], color)
            if not np.any(v):
                labels.append(Label(label, tuple(p), color, None, primary))
    pad = 0.45 * size
    ax.set_xlim(lo[0] - pad, hi[0] + pad)
    ax.set_ylim(lo[1] - pad, hi[1] + pad)
    ax.set_aspect("equal")
    ax.apply_aspect()  # the limits final before the labels are placed in points
    place_labels(ax, labels)
    ax.set_xlabel("x (mm)")
    ax.set_ylabel("y (mm)")


def _polygon(ax, data: dict, numbers, lang: str) -> None:
    """The force polygon at μ_F (the axes in mm of paper), its closure error under it."""
    mu = float(data["mu_F"])
    verts = np.array(data["vertices"], dtype=float) / mu
    drawn = [f for f in data["forces"] if any(f["vector"])]
    labels = []
    for f, tail, tip in zip(drawn, verts[:-1], verts[1:], strict=True):
        color = _COLOR.get(f["kind"], FORCE_COLORS["external"])
        a = _arrow(ax, tail, tip - tail, color, lw=1.3, ls="-" if f["status"] == "known" else "--")
        a.set_gid("force-polygon")
        labels.append(Label(force_label(f, numbers), tuple((tail + tip) / 2), color,
                            tuple(perp(tip - tail)), f["status"] == "solved",
                            "force-polygon-label"))  # fmt: skip
    ax.plot([0], [0], "o", ms=3.0, color="black")
    w, h = PANEL_MM
    c = (verts.min(axis=0) + verts.max(axis=0)) / 2
    ax.set_xlim(c[0] - w / 2, c[0] + w / 2)
    ax.set_ylim(c[1] - h / 2, c[1] + h / 2)
    ax.set_aspect("equal")
    ax.apply_aspect()
    place_labels(ax, labels, obstacles=False)
    ax.set_xlabel("mm")
    closure = data["closure"] or 0.0
    ax.set_title(
        tr("force polygon, {mu} = {v} N/mm", lang, mu=MU["F"], v=_fmt_scale(mu)), fontsize=8.5
    )
    text = tr(
        "closure error |ΣF| = {c} N ({r} of the largest force, {f} N)",
        lang,
        c=f"{closure:.3g}",
        r=f"{data['closure_error'] or 0.0:.2g}",
        f=f"{data['largest'] or 0.0:.4g}",
    )
    # right-aligned under the polygon: a long line runs left under the free body, not off
    # the figure's edge
    ax.annotate(text, (1, 0), xycoords="axes fraction", xytext=(0, -32),
                textcoords="offset points", fontsize=7, va="top", ha="right",
                gid="closure")  # fmt: skip


def group_figure(record, *, numbers=None, title: str = "", dpi: float = DPI, lang: str = "en"):
    """The free body of one Assur group and its force polygon, side by side.

    Parameters
    ----------
    record : GroupPolygon or dict
        One group of a :class:`~kinetostatics.methods.polygons.ForcePolygons` record at
        one position, or its ``to_dict()``.
    numbers : dict, optional
        The link numbers (``outputs.labels.link_numbers(result.system)``) for the labels
        F_Rij, G_j, …; without them links are named.
    title : str
        A title over the two panels (the position, say).

    Returns
    -------
    matplotlib.figure.Figure
        Two panels of 65 × 65 mm: the free body (mm of the mechanism) and the polygon at
        the scale μ_F printed over it (mm of paper), the closure error printed under it.
    """
    data = _plain(record)
    with _rc(lang):
        fig = _figure(2 * PANEL_MM[0] + 50, PANEL_MM[1] + 38, dpi=dpi)
        left = fig.add_axes([18 * MM / fig.get_figwidth(), 0.2, 0.4, 0.68])
        right = fig.add_axes([0.56, 0.2, 0.4, 0.68])
        _free_body(left, data, numbers)
        left.set_title(tr("free body of {group}", lang, group=group_title(data, lang)),
                       fontsize=8.5)  # fmt: skip
        _polygon(right, data, numbers, lang)
        if title:
            fig.suptitle(title, fontsize=9.5)
    return fig
