"""The flywheel chapter's pictures from a :class:`~kinetostatics.dynamics.flywheel.FlywheelDesign`:
the equivalent driving and resisting moments on the crank over the cycle
(:func:`equivalent_moments`) and the energy diagram ΔW–φ (:func:`energy_diagram`).

Both take the design's own curve (the balancing moment M_b on the crank in the sense of
motion, at the nominal speed, over φ from position 1) and the constant driving moment
M_d = its cycle mean, so the areas and the swing are the design's numbers."""

from __future__ import annotations

import numpy as np

from ..lang import tr
from .curves import _mark
from .style import CURVE_COLORS, DPI, EVENT_COLOR, _figure, _grow_to_fit, _rc


def energy_data(design) -> dict[str, np.ndarray]:
    """φ (deg, travel from position 1, closed at 360), M_b, M_d and ΔW(φ) = ∫₀^φ (M_d − M_b) dφ
    (J) of a flywheel design."""
    c = design.curve
    phi = np.append(c["travel"], 2 * np.pi + c["travel"][0])
    mb = np.append(c["moment"], c["moment"][0])
    md = np.full_like(mb, design.mean_torque)
    dw = np.concatenate(([0.0], np.cumsum(0.5 * np.diff(phi) * ((md - mb)[1:] + (md - mb)[:-1]))))
    return {"phi": np.degrees(phi), "resisting": mb, "driving": md, "energy": dw}


def _xlabel(result, lang):
    d = result.system.motion_drivers[0]
    sense = tr("clockwise" if d.driver.motion.speed < 0 else "counter-clockwise", lang)
    start = np.degrees(result.system.model.analysis.start) % 360.0
    return tr(
        "rotation φ of {name} from position 1 (φ₁ = {start}°, {sense}), deg",
        lang,
        name=d.name,
        start=f"{start:.4g}",
        sense=sense,
    )


def equivalent_moments(design, result, *, dpi: float = DPI, lang: str = "en"):
    """The equivalent resisting moment M_b(φ) (the balancing moment on the crank, link
    inertia at the nominal speed included) and the constant equivalent driving moment
    M_d over one cycle; the areas between them (surplus +, deficit −) shaded."""
    e = energy_data(design)
    x, mb, md = e["phi"], e["resisting"], e["driving"]
    with _rc(lang):
        fig = _figure(165, 95, dpi)
        ax = fig.add_subplot()
        ax.fill_between(
            x,
            mb,
            md,
            where=md >= mb,
            color=CURVE_COLORS[2],
            alpha=0.18,
            lw=0,
            interpolate=True,
            label=tr("surplus work (M_d > M_r)", lang),
        )
        ax.fill_between(
            x,
            mb,
            md,
            where=md < mb,
            color=EVENT_COLOR,
            alpha=0.15,
            lw=0,
            interpolate=True,
            label=tr("deficit work (M_d < M_r)", lang),
        )
        ax.plot(
            x,
            mb,
            color=CURVE_COLORS[0],
            label=tr("equivalent resisting moment M_r (balancing moment)", lang),
        )
        ax.plot(
            x,
            md,
            color=CURVE_COLORS[3],
            ls="--",
            label=tr(
                "equivalent driving moment M_d = {m} N·m (cycle mean)",
                lang,
                m=f"{design.mean_torque:.4g}",
            ),
        )
        ax.axhline(0, color="black", lw=0.5)
        _mark(ax, result, lang=lang)
        ax.set_xlabel(_xlabel(result, lang))
        ax.set_ylabel(tr("moment on the crank, N·m (sense of motion +)", lang))
        fig.suptitle(
            tr(
                "{name}: equivalent driving and resisting moments",
                lang,
                name=result.system.model.name,
            ),
            x=0.02,
            ha="left",
            fontsize=9.5,
        )
        ax.legend(loc="upper center", bbox_to_anchor=(0.5, -0.16), ncol=2)
        fig.subplots_adjust(left=0.1, right=0.97, top=0.81, bottom=0.34)
    _grow_to_fit(fig)
    return fig


def energy_diagram(design, result, *, dpi: float = DPI, lang: str = "en"):
    """ΔW(φ) = ∫ (M_d − M_r) dφ over one cycle, its maximum and minimum marked (where the
    kinetic energy is largest, E_max, and smallest, E_min) and the maximum energy swing
    ΔW_max = E_max − E_min that sizes the flywheel."""
    e = energy_data(design)
    x, w = e["phi"], e["energy"]
    k_max, k_min = int(np.argmax(w)), int(np.argmin(w))
    with _rc(lang):
        fig = _figure(165, 95, dpi)
        ax = fig.add_subplot()
        ax.plot(x, w, color=CURVE_COLORS[0], label=tr("ΔW(φ) = ∫(M_d − M_r) dφ", lang))
        ax.axhline(0, color="black", lw=0.5)
        # the extremes of ΔW(φ) = E(φ) − E(φ₁) are where the kinetic energy E is largest
        # and smallest; the swing between them, ΔW_max = E_max − E_min, sizes the flywheel
        for k, word in ((k_max, "max"), (k_min, "min")):
            ax.plot([x[k]], [w[k]], "o", color=CURVE_COLORS[3], ms=4)
            ax.annotate(
                tr(
                    "E_{word}: ΔW = {w} J (φ = {phi}°)",
                    lang,
                    word=word,
                    w=f"{w[k]:.4g}",
                    phi=f"{x[k]:.1f}",
                ),
                (x[k], w[k]),
                xytext=(0, 6 if word == "max" else -6),
                textcoords="offset points",
                ha="center" if 40 < x[k] < 320 else ("left" if x[k] <= 40 else "right"),
                va="bottom" if word == "max" else "top",
                fontsize=7,
            )
        ax.plot(
            [],
            [],
            " ",
            label=tr(
                "maximum energy swing ΔW_max = E_max − E_min = {s} J",
                lang,
                s=f"{design.energy_swing:.5g}",
            ),
        )
        _mark(ax, result, lang=lang)
        lo, hi = float(np.min(w)), float(np.max(w))
        pad = 0.18 * max(hi - lo, 1e-12)
        ax.set_ylim(lo - pad, hi + pad)
        ax.set_xlabel(_xlabel(result, lang))
        ax.set_ylabel(tr("ΔW, J", lang))
        fig.suptitle(
            tr("{name}: energy diagram ΔW–φ", lang, name=result.system.model.name),
            x=0.02,
            ha="left",
            fontsize=9.5,
        )
        ax.legend(loc="upper center", bbox_to_anchor=(0.5, -0.16), ncol=2)
        fig.subplots_adjust(left=0.1, right=0.97, top=0.81, bottom=0.3)
    _grow_to_fit(fig)
    return fig
