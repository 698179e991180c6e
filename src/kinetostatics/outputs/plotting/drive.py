"""The four-quadrant torque–speed picture of a drive (``drive:``): the motor's torque over its
speed through the cycle (:func:`~kinetostatics.dynamics.drive.quadrant_data`), the rated
(continuous) and peak envelopes when the ratings are given, and the quadrants named:
motoring where torque and speed have one sign, braking (the machine drives the motor) where
they differ.  Speed and torque are positive in the sense of motion of the driven shaft."""

from __future__ import annotations

import numpy as np

from ...dynamics.motor import quadrant_data
from ..lang import tr
from .style import CURVE_COLORS, DPI, EVENT_COLOR, _figure, _grow_to_fit, _rc

__all__ = ["torque_speed"]


def _limits(d) -> tuple[float, float]:
    """Half-widths of the axes (rpm, N·m): the data and the ratings, with a margin."""
    w = float(np.nanmax(np.abs(d["speed"]), initial=0.0))
    t = float(np.nanmax(np.abs(d["torque"]), initial=0.0))
    w = max(w, d["rated_speed"] or 0.0) or 1.0
    t = max(t, d["peak_torque"] or 0.0, d["rated_torque"] or 0.0) or 1.0
    return 1.25 * w, 1.3 * t


def torque_speed(result, *, dpi: float = DPI, lang: str = "en"):
    """Motor torque against motor speed over the cycle, in all four quadrants."""
    d = quadrant_data(result)
    W, T = _limits(d)
    with _rc(lang):
        fig = _figure(150, 120, dpi)
        ax = fig.add_subplot()
        ax.axhline(0, color="black", lw=0.6)
        ax.axvline(0, color="black", lw=0.6)
        for sx, sy, word in (
            (1, 1, "motoring"),
            (-1, 1, "braking"),
            (-1, -1, "motoring"),
            (1, -1, "braking"),
        ):
            ax.text(
                sx * 0.96 * W,
                sy * 0.95 * T,
                tr(word, lang),
                ha="right" if sx > 0 else "left",
                va="top" if sy > 0 else "bottom",
                fontsize=7.5,
                color="#555555",
            )
        ws = d["rated_speed"] if d["rated_speed"] is not None else 1.1 * W
        for key, style, label in (
            ("rated_torque", "-", "rated torque (continuous)"),
            ("peak_torque", "--", "peak torque"),
        ):
            tq = d[key]
            if tq is None:
                continue
            ax.plot(
                [-ws, ws, ws, -ws, -ws],
                [tq, tq, -tq, -tq, tq],
                color=EVENT_COLOR if key == "peak_torque" else CURVE_COLORS[2],
                ls=style,
                lw=1.0,
                label=tr(label, lang) + f" {tq:.4g} N·m",
            )
        if d["rated_speed"] is not None and d["rated_torque"] is None and d["peak_torque"] is None:
            for s in (-1, 1):
                ax.axvline(s * ws, color=CURVE_COLORS[2], lw=1.0)
            ax.plot([], [], color=CURVE_COLORS[2], label=tr("rated speed", lang))
        ax.plot(
            d["speed"],
            d["torque"],
            ".",
            ms=2.5,
            color=CURVE_COLORS[0],
            label=tr("motor over the cycle", lang),
        )
        ax.set_xlim(-W, W)
        ax.set_ylim(-T, T)
        ax.set_xlabel(tr("motor speed, rpm (sense of motion +)", lang))
        ax.set_ylabel(tr("motor torque, N·m (sense of motion +)", lang))
        torque = tr("with friction" if d["friction"] else "frictionless", lang)
        fig.suptitle(
            tr(
                "{name}: four-quadrant torque–speed of drive {driver} (ratio {i}, {torque})",
                lang,
                name=result.system.model.name,
                driver=d["driver"],
                i=f"{d['ratio']:g}",
                torque=torque,
            ),
            x=0.02,
            ha="left",
            fontsize=9,
        )
        ax.legend(loc="upper center", bbox_to_anchor=(0.5, -0.13), ncol=2)
        fig.subplots_adjust(left=0.12, right=0.97, top=0.9, bottom=0.24)
    _grow_to_fit(fig)
    return fig
