"""One consistent look: matplotlib on first use, the figure and rc style, drawing
scales, paper layout and the drawing primitives (hatched lines, arrows, arcs,
labels)."""

from __future__ import annotations

import math
import re

import numpy as np

from ...errors import KinetostaticsError


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
ELEMENT_COLOR = "#7f8c8d"  # springs and dampers
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
