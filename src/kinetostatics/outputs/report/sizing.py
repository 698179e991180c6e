"""The sizing chapter: the bearings' load and life, the plain bearings' p, v and pv, the
pins' stresses, the links' internal forces, stresses and fatigue safety factors, and the
envelopes of N and M along each link (docs/sizing.md).  It formats the sizing stage's
record (:class:`~kinetostatics.sizing.records.Sizing`), passed by its caller."""

from __future__ import annotations

import numpy as np

from ..lang import tr
from ..plotting.style import CURVE_COLORS, DPI, _figure, _grow_to_fit, _rc
from .blocks import _Heading, _List, _Para, _Table

__all__ = ["sizing_blocks", "envelopes"]

FORMULAS = (
    "rolling bearings (ISO 281): P = (∫|F|^p·|ω_rel|dt / ∫|ω_rel|dt)^(1/p), p = 3 (ball), "
    "10/3 (roller); L10 = (C/P)^p·10⁶ rev; L10h = L10/(3600·n), n = ∫|ω_rel|dt/(2π·T); an "
    "oscillating joint turns 2φ per cycle for a swing φ (the equivalent-speed rule)",
    "plain bearings: p = |F|/(d·b), v = |ω_rel|·d/2, pv",
    "pins: τ = |F|/(k·πd²/4) for k shear planes; the eyes' pressure |F|/(d·w)",
    "links: N, V, M along the axis from the first pin, the inertia distributed along a "
    "uniform link, lumped at the centre of mass of another; σ = |N|/A + |M|/Z",
    "fatigue at the critical section: Goodman 1/n = σ_a/S_e + σ_m/S_ut, Soderberg "
    "1/n = σ_a/S_e + σ_m/S_y (n = S_e/σ_a for a compressive mean); yield n = S_y/σ",
)


def _g(v, digits: int = 4, scale: float = 1.0) -> str:
    return "–" if v is None or not np.isfinite(v) else f"{v * scale:.{digits}g}"


def _kind(kind: str, T) -> str:
    return T("ball bearing") if kind == "ball" else T("roller bearing")


def _bearing_tables(sizing, T) -> list:
    out = []
    rolling = [b for b in sizing.bearings if b.kind != "plain"]
    if rolling:
        rows = [
            [b.joint, _kind(b.kind, T), _g(b.C, 5, 1e-3), _g(b.peak_force, 5), _g(b.P, 5),
             T(b.motion) + ("" if b.motion == "rotating" else f" ({_g(b.swing)}°)"),
             _g(b.speed), _g(b.life[0] if b.life else None, 4, 1e-6),
             _g(b.life[1] if b.life else None)]
            for b in rolling
        ]  # fmt: skip
        head = [T("joint"), T("type"), "C (kN)", T("peak |F| (N)"), "P (N)", T("motion"),
                "n (rev/s)", "L10 (10⁶ rev)", "L10h (h)"]  # fmt: skip
        out.append(_Table(head, rows, T("Rolling bearings: equivalent load and rating life")))
    plain = [b for b in sizing.bearings if b.kind == "plain"]
    if plain:
        rows = []
        for b in plain:
            p, v, pv = (b.plain[k] for k in ("p", "v", "pv"))
            rows.append(
                [b.joint, _g(b.peak_force, 5), _g(p[1], 4, 1e-6), _g(p[2], 4, 1e-6),
                 _g(p[3], 4, 1e-6), _g(v[1]), _g(v[3]), _g(pv[1], 4, 1e-6), _g(pv[3], 4, 1e-6)]
            )  # fmt: skip
        head = [T("joint"), T("peak |F| (N)"), T("peak p (MPa)"), T("mean p (MPa)"),
                "p_max (MPa)", T("peak v (m/s)"), "v_max (m/s)", T("peak pv (MPa·m/s)"),
                "pv_max (MPa·m/s)"]  # fmt: skip
        out.append(_Table(head, rows, T("Plain bearings: pressure, sliding speed and pv")))
    return out


def _pin_table(sizing, T) -> list:
    if not sizing.pins:
        return []
    rows = [
        [p.joint, _g(p.diameter, 4, 1e3), str(p.planes), _g(p.peak_shear, 4, 1e-6),
         _g(p.peak_eye_pressure, 4, 1e-6)]
        for p in sizing.pins
    ]  # fmt: skip
    head = [T("joint"), "d (mm)", T("shear planes"), T("peak τ (MPa)"),
            T("peak pressure on the eyes (MPa)")]  # fmt: skip
    return [_Table(head, rows, T("Pins: shear stress and bearing pressure"))]


def _link_table(sizing, T) -> list:
    if not sizing.links:
        return []
    rows = []
    for x in sizing.links:
        f = x.factors
        rows.append(
            [x.link, T(x.shape), _g(x.area, 4, 1e6), _g(x.modulus, 5, 1e9),
             _g(np.abs(x.N).max(), 5), _g(np.abs(x.V).max(), 5), _g(np.abs(x.M).max()),
             _g(x.peak_stress, 4, 1e-6), _g(x.stations[x.critical], 4, 1e3),
             _g(x.cycle[0], 4, 1e-6), _g(x.cycle[1], 4, 1e-6), _g(f["goodman"]),
             _g(f["soderberg"]), _g(f["yield"])]
        )  # fmt: skip
    head = [T("link"), T("section"), "A (mm²)", "Z (mm³)", "|N| (N)", "|V| (N)", "|M| (N·m)",
            "σ (MPa)", T("at (mm)"), "σ_m (MPa)", "σ_a (MPa)", "n Goodman", "n Soderberg",
            T("n yield")]  # fmt: skip
    return [_Table(head, rows, T("Links: peaks over the cycle and safety factors"))]


def envelopes(sizing, *, dpi: float = DPI, lang: str = "en"):
    """The largest and least N (kN) and M (N·m) over the cycle at each station of each link
    (mm from its first pin); None without links."""
    if not sizing.links:
        return None
    T = lambda s, **k: tr(s, lang, **k)  # noqa: E731
    with _rc(lang):
        fig = _figure(160, 90, dpi)
        axes = fig.subplots(1, 2)
        for k, x in enumerate(sizing.links):
            c, s = CURVE_COLORS[k % len(CURVE_COLORS)], x.stations * 1e3
            for ax, arr, scale in ((axes[0], x.N, 1e-3), (axes[1], x.M, 1.0)):
                ax.fill_between(s, arr.min(axis=0) * scale, arr.max(axis=0) * scale,
                                color=c, alpha=0.25, lw=0)  # fmt: skip
                ax.plot(s, arr.max(axis=0) * scale, color=c, label=x.link)
                ax.plot(s, arr.min(axis=0) * scale, color=c)
                ax.axvline(s[x.critical], color=c, lw=0.6, ls="--")
        axes[0].set_ylabel(T("axial force N (kN)"))
        axes[1].set_ylabel(T("bending moment M (N·m)"))
        for ax in axes:
            ax.set_xlabel(T("station from the first pin (mm)"))
            ax.axhline(0, color="black", lw=0.6)
        axes[0].legend()
        fig.subplots_adjust(left=0.1, right=0.98, bottom=0.15, top=0.95, wspace=0.35)
        _grow_to_fit(fig)
    return fig


def sizing_blocks(sizing, image, lang: str = "en", number: int = 20, dpi: float = DPI) -> list:
    """Blocks of chapter ``number`` from the sizing record; ``image(fig, name, caption)``
    saves a figure as a block."""
    T = lambda s, **k: tr(s, lang, **k)  # noqa: E731
    blocks: list = [
        _Heading(2, T("{n}. Sizing: bearings, pins and links", n=number)),
        _Para(
            T(
                "From the reactions of the frictionless solution over the cycle: the peaks are "
                "the largest over the analysed positions and the points between them where the "
                "cycle's integral samples the motion; the means and the bearing life are exact "
                "integrals over the cycle. Stresses in MPa."
            )
        ),
        _List([T(f) for f in FORMULAS]),
        *_bearing_tables(sizing, T),
        *_pin_table(sizing, T),
        *_link_table(sizing, T),
    ]
    fig = envelopes(sizing, dpi=dpi, lang=lang)
    if fig is not None:
        caption = T("Axial force and bending moment along the links: their range over the "
                    "cycle at each station; dashed: the critical section")  # fmt: skip
        blocks.append(image(fig, "sizing_envelopes", caption))
    if sizing.warnings:
        blocks += [_Para(T("Warnings:")), _List(list(sizing.warnings))]
    return blocks
