"""Polar diagrams of the joint loads in link-fixed frames."""

from __future__ import annotations

import itertools
import math
from collections.abc import Sequence

import numpy as np

from ...base.geometry import rotate
from ...errors import did_you_mean
from ..labels import reaction_symbol
from ..lang import tr
from .rows import _sorted, course_positions, link_numbers
from .scene import _poses
from .style import CURVE_COLORS, DPI, EVENT_COLOR, PictureError, _figure, _grow_to_fit, _rc


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


def _course_marks(ax, marks) -> None:
    """The course positions on a polar diagram: a grey ray from the origin to each
    point, the point, and its label 2 pt up and right of it (events in their colour):
    one collection of rays, one line per run of points of a colour, plain texts (a line,
    a line and an annotation per position cost a tenth of making and saving the picture)."""
    from matplotlib.collections import LineCollection
    from matplotlib.transforms import offset_copy

    if not marks:
        return
    tips = np.array([p for _, p in marks], dtype=float)
    rays = np.zeros((len(marks), 2, 2))
    rays[:, 1] = tips
    ax.add_collection(
        LineCollection(rays, colors="#aaaaaa", linewidths=0.5, zorder=0, capstyle="projecting")
    )
    colors = [EVENT_COLOR if "′" in lab else "black" for lab, _ in marks]
    start = 0
    for color, run in itertools.groupby(colors):  # drawn in the course's order
        stop = start + len(list(run))
        ax.plot(tips[start:stop, 0], tips[start:stop, 1], "o", ms=2.5, color=color)
        start = stop
    shifted = offset_copy(ax.transData, fig=ax.figure, x=2, y=2, units="points")
    for (lab, p), color in zip(marks, colors):
        if np.isfinite(p).all():  # no load there (self-locked, singular): no label
            ax.text(p[0], p[1], lab, transform=shifted, fontsize=6, color=color)


def polar_diagrams(
    result,
    joints: Sequence[str] | None = None,
    *,
    friction: bool = False,
    dpi: float = DPI,
    lang: str = "en",
):
    """Polar diagrams: the tip of each joint's load vector in a link-fixed frame
    over the cycle (for sizing bearings), with the course positions numbered.
    Default: every pin joint (``pin``: the revolutes)."""
    model = result.system.model
    if joints is None:
        joints = [j.name for j in model.joints if j.pin]
    joints = list(joints)
    if not joints:
        raise PictureError("no joint to draw a polar diagram of")
    nums = link_numbers(result.system)
    course = course_positions(result)
    n = len(joints)
    cols = min(3, n)
    rows = math.ceil(n / cols)
    _, order, _ = _sorted(result)
    with _rc(lang):
        fig = _figure(60 * cols + 8, 62 * rows + 14, dpi)
        for m, name in enumerate(joints):
            ax = fig.add_subplot(rows, cols, m + 1)
            link, _, F = link_frame_loads(result, name, friction=friction)
            F = F[order]
            closed = np.vstack((F, F[:1])) if result.full_cycle else F
            ax.plot(closed[:, 0], closed[:, 1], color=CURVE_COLORS[0], lw=1.2)
            ax.plot([0], [0], "+", color="black", ms=7, mew=1.0)
            inv = np.empty_like(order)
            inv[order] = np.arange(len(order))
            _course_marks(ax, [(lab, F[inv[k]]) for lab, k in course])
            mag = np.hypot(F[:, 0], F[:, 1])
            if not np.isfinite(mag).any():  # friction solution self-locked throughout
                ax.text(
                    0.5,
                    0.5,
                    tr("no values:\nself-locking at\nevery position", lang),
                    transform=ax.transAxes,
                    ha="center",
                    va="center",
                    fontsize=7,
                )
                title = tr("{joint}: no consistent friction solution", lang, joint=name)
                ax.set_title(title, fontsize=7.5)
                continue
            kmax = int(np.nanargmax(mag))
            ax.plot([0, F[kmax, 0]], [0, F[kmax, 1]], color=CURVE_COLORS[3], lw=1.0)
            lim = 1.12 * float(np.nanmax(mag)) if np.nanmax(mag) > 0 else 1.0
            ax.set_xlim(-lim, lim)
            ax.set_ylim(-lim, lim)
            ax.set_aspect("equal", adjustable="box")
            j = model.joint(name)
            i_link, j_link = j.links if link == j.links[1] else j.links[::-1]
            ax.set_title(
                f"{name}: {reaction_symbol(j.links, nums)}, "
                + tr("{i} on {j}", lang, i=i_link, j=j_link)
                + "\n"
                + tr(
                    "in the frame of {link}; max {peak} N",
                    lang,
                    link=link,
                    peak=f"{mag[kmax]:.4g}",
                ),
                fontsize=7.5,
            )
            ax.set_xlabel(tr("F along {link} x, N", lang, link=link), fontsize=7)
            ax.set_ylabel(tr("F along {link} y, N", lang, link=link), fontsize=7)
            ax.tick_params(labelsize=6.5)
        fig.suptitle(
            tr("{model}: polar diagrams of the joint loads", lang, model=model.name)
            + (tr(" (with friction)", lang) if friction else "")
            + tr(" — numbers: course positions", lang),
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
    _grow_to_fit(fig)
    return fig
