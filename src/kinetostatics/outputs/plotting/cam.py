"""The cam chapter's pictures from the plain data of a cam design (``CamDesign.to_dict()``
of ``kinetostatics.methods.cam_design``, methods.json's ``cam_design`` entry): the
follower's s–φ, v–φ, a–φ diagrams with the pressure-angle curve (:func:`cam_diagrams`),
and the pitch curve and working profile drawn at a round scale μ_l (:func:`cam_drawing`).
The pictures draw the record's numbers; they compute no design."""

from __future__ import annotations

import numpy as np

from ..lang import tr
from .style import (
    CURVE_COLORS,
    DPI,
    EVENT_COLOR,
    MU,
    _figure,
    _fit_sheet,
    _fmt_scale,
    _grow_to_fit,
    _layout,
    _Paper,
    _rc,
    nice_scale,
)

__all__ = ["cam_diagrams", "cam_drawing"]

# the largest drawing of the cam on an A4 page (mm of paper; the legend inside it): a cam
# of up to 74 mm radius is drawn at 1 : 1
CAM_SHEET_MM = (160.0, 160.0)


def _plain(design) -> dict:
    to_dict = getattr(design, "to_dict", None)
    return to_dict() if callable(to_dict) else dict(design)


def _lift_rows(d: dict) -> list[tuple[str, np.ndarray, str]]:
    """(label, values, unit) of s, ds/dφ, d²s/dφ²: a translating follower's in mm, an
    oscillating one's in degrees."""
    s, s1, s2 = (np.asarray(d[k], dtype=float) for k in ("lift", "lift_d1", "lift_d2"))
    if d["lift_units"][0] == "m":
        return [
            ("s", 1e3 * s, "mm"),
            ("ds/dφ", 1e3 * s1, "mm/rad"),
            ("d²s/dφ²", 1e3 * s2, "mm/rad²"),
        ]
    return [
        ("ψ", np.degrees(s), "deg"),
        ("dψ/dφ", s1, "1"),
        ("d²ψ/dφ²", s2, "1/rad"),
    ]


def cam_diagrams(design, *, dpi: float = DPI, lang: str = "en"):
    """The follower's lift and its first two derivatives over the cam angle φ (per unit cam
    speed: v = ω·ds/dφ, a = ω²·d²s/dφ²) and the pressure angle α(φ) at the file's base
    radius, with ±[α] and the largest |α| marked.

    Parameters
    ----------
    design : CamDesign or dict
        One cam's design, or its ``to_dict()``.

    Returns
    -------
    matplotlib.figure.Figure
    """
    d = _plain(design)
    phi = np.asarray(d["angle"], dtype=float)
    alpha = np.asarray(d["pressure_angle"], dtype=float)
    rows = _lift_rows(d) + [("α", alpha, "deg")]
    with _rc(lang):
        fig = _figure(165, 190, dpi)
        axes = fig.subplots(len(rows), 1, sharex=True)
        for k, (ax, (label, values, unit)) in enumerate(zip(axes, rows)):
            ax.plot(phi, values, color=CURVE_COLORS[k % len(CURVE_COLORS)])
            ax.axhline(0.0, color="black", lw=0.5)
            ax.set_ylabel(f"{label}, {unit}")
        ax = axes[-1]
        allowed = float(d["allowed"])
        for sign in (1.0, -1.0):
            ax.axhline(sign * allowed, color=EVENT_COLOR, lw=0.8, ls="--")
        ax.annotate(
            f"[α] = ±{allowed:.4g}°",
            (phi[-1], allowed),
            xytext=(-2, 2),
            textcoords="offset points",
            ha="right",
            va="bottom",
            fontsize=7,
            color=EVENT_COLOR,
        )
        at = float(d["peak_at"])
        peak = float(np.interp(at, phi, alpha))
        ax.plot([at], [peak], "o", ms=4, color=CURVE_COLORS[3])
        ax.annotate(
            f"|α|max = {d['peak']:.4g}°, φ = {at:.1f}°",
            (at, peak),
            xytext=(6, -5 if peak >= 0 else 5),  # toward the axis, clear of ±[α]
            textcoords="offset points",
            ha="left" if at <= 300 else "right",
            va="top" if peak >= 0 else "bottom",
            fontsize=7,
        )
        ax.set_xlabel(tr("cam angle φ, deg", lang))
        ax.set_xlim(0.0, 360.0)
        ax.set_xticks(np.arange(0.0, 361.0, 30.0))
        axes[0].set_title(
            tr("Cam {joint}", lang, joint=d["joint"]),
            fontsize=9,
        )
        _grow_to_fit(fig)
    return fig


def cam_drawing(design, *, dpi: float = DPI, lang: str = "en"):
    """The cam in its own frame at a round scale μ_l (m of the cam per mm of paper, true
    scale printed at 100 %): the working profile, the pitch curve (a roller's), the base
    circle and the centre; at most :data:`CAM_SHEET_MM` of paper.

    Parameters
    ----------
    design : CamDesign or dict
        One cam's design, or its ``to_dict()``.

    Returns
    -------
    matplotlib.figure.Figure
        Axes in mm of the cam, the scale in the title.
    """
    d = _plain(design)
    profile = 1e3 * np.asarray(d["profile"], dtype=float)
    pitch = None if d["pitch_curve"] is None else 1e3 * np.asarray(d["pitch_curve"], float)
    pts = profile if pitch is None else np.vstack([profile, pitch])
    reach = float(np.max(np.abs(pts))) * 1.08
    mu_l = nice_scale(2.0 * reach * 1e-3 / min(CAM_SHEET_MM)) if reach > 0 else 1e-3
    paper = _Paper(mu_l)
    with _rc(lang):
        fig, ax = _layout((-reach, reach), (-reach, reach), paper.k, dpi=dpi, top=14.0)
        ax.grid(False)
        closed = np.vstack([profile, profile[:1]])
        ax.plot(*closed.T, color="black", lw=1.2, label=tr("working profile", lang))
        if pitch is not None and d["follower"] == "roller":
            loop = np.vstack([pitch, pitch[:1]])
            ax.plot(*loop.T, color=CURVE_COLORS[0], lw=0.8, ls="--", label=tr("pitch curve", lang))
        t = np.linspace(0.0, 2.0 * np.pi, 181)
        r_b = 1e3 * float(d["base_radius"])
        ax.plot(r_b * np.cos(t), r_b * np.sin(t), color="0.5", lw=0.6, ls=":",
                label=tr("base circle r_b = {r} mm", lang, r=f"{r_b:.4g}"))  # fmt: skip
        ax.plot([0.0], [0.0], "+", color="black", ms=8)
        ax.set_xlabel("x, mm")
        ax.set_ylabel("y, mm")
        ax.legend(loc="best", fontsize=6.5)
        ax.set_title(
            tr("Cam {joint}", lang, joint=d["joint"])
            + f"\n{MU['l']} = {_fmt_scale(paper.mu_l)} m/mm",
            fontsize=9,
        )
        _fit_sheet(fig, ax)
    return fig
