"""The pictures of a sensitivity and tolerance analysis (docs/sensitivity.md): the tornado
chart of one quantity (:func:`tornado_figure`: its value at each parameter's p − t and
p + t, one parameter at a time, the largest swing on top, the linearised ends marked) and
the histogram of its Monte Carlo designs (:func:`histogram_figure`: the nominal value, the
mean, the 0.135 % and 99.865 % points, the limits on it and the normal curve of the
linearised σ).

They read the records of ``batch.sensitivity`` and ``batch.tolerance`` by their
attributes only (this layer does not import the batch's)."""

from __future__ import annotations

import math

import numpy as np

from .style import CURVE_COLORS, DPI, EVENT_COLOR, _figure, _grow_to_fit, _rc

__all__ = ["tornado_figure", "histogram_figure"]

LOW_COLOR, HIGH_COLOR = CURVE_COLORS[0], CURVE_COLORS[1]


def _label(quantity: str, unit: str) -> str:
    return f"{quantity} ({unit})" if unit and unit != "1" else quantity


def _tolerance_text(t) -> str:
    return f"{t.name} {t.text}" if t.relative else f"{t.name} ±{t.half:.4g}"


def tornado_figure(sens, quantity: str, *, dpi: float = DPI):
    """The tornado chart of ``quantity`` from a ``Sensitivity`` record: for each toleranced
    parameter, a bar from the nominal value to the value at p − t and one to p + t (each
    design analysed), sorted by the swing |Q(p + t) − Q(p − t)|, the largest on top; a
    black tick at the linearised ends Q₀ ∓ (dQ/dp)·t; "failed" where a design was not
    analysed."""
    k = sens.quantities.index(quantity)
    q0, unit = sens.nominal[k], sens.units[k]
    tols = {t.name: t for t in sens.tolerances}
    ders = list(sens.of(quantity))
    swing = [abs(d.high - d.low) if math.isfinite(d.high - d.low) else math.inf for d in ders]
    order = sorted(range(len(ders)), key=lambda i: swing[i])  # smallest at the bottom
    with _rc("en"):
        fig = _figure(160, 22 + 9 * len(ders), dpi)
        ax = fig.add_subplot()
        ends, lins = [q0], []
        for y, i in enumerate(order):
            d = ders[i]
            for value, color in ((d.low, LOW_COLOR), (d.high, HIGH_COLOR)):
                if math.isfinite(value):
                    ax.barh(y, value - q0, left=q0, height=0.6, color=color, alpha=0.85)
                    ends.append(value)
            for lin in (q0 - d.linear, q0 + d.linear):
                if math.isfinite(lin):
                    ax.plot([lin, lin], [y - 0.36, y + 0.36], color="black", lw=1.0)
                    lins.append(lin)
        span = (max(ends) - min(ends)) or abs(q0) or 1.0
        ends += [v for v in lins if abs(v - q0) <= 2 * span]  # ticks near the bars shown
        span = max(ends) - min(ends) or span
        _end_labels(ax, [ders[i] for i in order], q0, span)
        ax.axvline(q0, color="black", lw=0.8)
        ax.set_yticks(range(len(order)), [_tolerance_text(tols[ders[i].parameter]) for i in order])
        ax.set_xlim(min(ends) - 0.3 * span, max(ends) + 0.3 * span)
        ax.set_ylim(-0.7, len(order) - 0.3)
        ax.grid(axis="y", visible=False)
        ax.set_xlabel(_label(quantity, unit))
        from matplotlib.lines import Line2D
        from matplotlib.patches import Patch

        handles = [
            Patch(color=LOW_COLOR, alpha=0.85, label="at p − t"),
            Patch(color=HIGH_COLOR, alpha=0.85, label="at p + t"),
            Line2D([], [], color="black", lw=1.0, label="linearised, Q₀ ∓ (dQ/dp)·t"),
        ]
        ax.legend(
            handles=handles,
            loc="upper center",
            bbox_to_anchor=(0.5, -0.18 - 0.6 / (len(ders) + 1)),
            ncol=3,
        )
        fig.suptitle(f"{quantity}: tornado chart, nominal {q0:.6g}", x=0.02, ha="left", fontsize=9)
        fig.subplots_adjust(left=0.2, right=0.97, top=0.86, bottom=0.3)
    _grow_to_fit(fig)
    return fig


def _end_labels(ax, ders, q0: float, span: float) -> None:
    """Each bar's end value beside it (bottom to top), "failed" where it was not analysed."""
    for y, d in enumerate(ders):
        for value, side in ((d.low, -1), (d.high, 1)):
            text = f"{value:.5g}" if math.isfinite(value) else "failed"
            x = value if math.isfinite(value) else q0
            if math.isfinite(value):  # a bar of no length: its low end's text to the left
                right = value > q0 if side < 0 else value >= q0
            else:
                right = side > 0
            ax.text(
                x + (0.02 if right else -0.02) * span,
                y,
                text,
                ha="left" if right else "right",
                va="center",
                fontsize=7,
                color=EVENT_COLOR if not math.isfinite(value) else "#333333",
            )


def histogram_figure(mc, quantity: str, *, limits=(), dpi: float = DPI):
    """The histogram of ``quantity`` over a ``MonteCarlo`` record's designs analysed: the
    nominal value, the mean, the 0.135 % and 99.865 % points (±3σ of a normal), each limit
    ``(value, op)`` on it (red, dashed), and the normal curve of the linearised σ about the
    nominal value where it is known."""
    sp = next(s for s in mc.spreads if s.quantity == quantity)
    with _rc("en"):
        fig = _figure(150, 95, dpi)
        ax = fig.add_subplot()
        if sp.n:
            edges, counts = np.asarray(sp.edges), np.asarray(sp.counts)
            ax.stairs(counts, edges, fill=True, color=CURVE_COLORS[0], alpha=0.55, label="designs")
            width = float(np.mean(np.diff(edges))) if len(edges) > 1 else 1.0
            if math.isfinite(sp.linear_sd) and sp.linear_sd > 0:
                x = np.linspace(edges[0], edges[-1], 200)
                pdf = np.exp(-0.5 * ((x - sp.nominal) / sp.linear_sd) ** 2) / (
                    sp.linear_sd * math.sqrt(2 * math.pi)
                )
                ax.plot(x, pdf * sp.n * width, color="black", lw=1.0, label="normal, linearised σ")
            pts = dict(sp.percentiles)
            ax.axvline(sp.nominal, color=CURVE_COLORS[2], lw=1.2, label=f"nominal {sp.nominal:.5g}")
            ax.axvline(sp.mean, color=CURVE_COLORS[1], lw=1.0, ls=":", label=f"mean {sp.mean:.5g}")
            for p in (0.135, 99.865):
                ax.axvline(pts[p], color="#555555", lw=0.8, ls="-.")
            ax.plot([], [], color="#555555", lw=0.8, ls="-.", label="0.135 % and 99.865 % points")
        lo, hi = (sp.edges[0], sp.edges[-1]) if sp.n else (min(v for v, _ in limits), 0.0)
        pad = 0.08 * ((hi - lo) or abs(lo) or 1.0)
        for value, op in limits:  # drawn where it falls near the designs; else named
            near = lo - 3 * (hi - lo + pad) <= value <= hi + 3 * (hi - lo + pad)
            if near:
                ax.axvline(value, color=EVENT_COLOR, lw=1.2, ls="--")
                lo, hi = min(lo, value), max(hi, value)
            where = "" if near else (" (far to the right)" if value > hi else " (far to the left)")
            ax.plot(
                [], [], color=EVENT_COLOR, lw=1.2, ls="--", label=f"limit {op} {value:.5g}{where}"
            )
        ax.set_xlim(lo - pad, hi + pad)
        ax.set_xlabel(_label(quantity, sp.unit))
        ax.set_ylabel("designs")
        lost = f", {mc.failed} failed" if mc.failed else ""
        fig.suptitle(
            f"{quantity}: {sp.n} of {mc.samples} designs ({mc.dist}{lost}), sd {sp.sd:.4g}",
            x=0.02,
            ha="left",
            fontsize=9,
        )
        ax.legend(loc="upper center", bbox_to_anchor=(0.5, -0.16), ncol=3)
        fig.subplots_adjust(left=0.11, right=0.97, top=0.9, bottom=0.33)
    _grow_to_fit(fig)
    return fig
