"""Every number of docs/sizing.md's worked example: mechanisms/slider_crank_sized.yaml
through the sizing stage, each formula written out with its numbers.

    python docs/scripts/sizing_example.py            # print the block
    python docs/scripts/sizing_example.py --write    # and replace the block in docs/sizing.md
"""

from __future__ import annotations

import math
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT / "src"))

import kinetostatics as ks  # noqa: E402
from kinetostatics.sizing import sizing_stage  # noqa: E402

FILE = ROOT / "mechanisms" / "slider_crank_sized.yaml"
BEGIN, END = "<!-- sizing_example: begin -->", "<!-- sizing_example: end -->"


def _bearings(sizing) -> list[str]:
    out = []
    for b in sizing.bearings:
        head = f"- **{b.joint}** ({b.kind}, links {b.links[0]}–{b.links[1]}, {b.motion}"
        head += f", swing {b.swing:.4g}°)" if b.motion == "oscillating" else ")"
        if b.kind == "plain":
            p, v, pv = (b.plain[k] for k in ("p", "v", "pv"))
            out += [
                f"{head}: peak |F| = {b.peak_force:.5g} N; p = |F|/(d·b) peaks at "
                f"{p[1] / 1e6:.4g} MPa (mean {p[2] / 1e6:.4g}, limit {p[3] / 1e6:.4g}); "
                f"v = |ω_rel|·d/2 peaks at {v[1]:.4g} m/s (limit {v[3]:.4g}); pv peaks at "
                f"{pv[1] / 1e6:.4g} MPa·m/s (limit {pv[3] / 1e6:.4g})."
            ]
            continue
        life, hours = b.life
        out += [
            f"{head}: peak |F| = {b.peak_force:.5g} N; mean speed n = ∫|ω_rel|dt/(2π·T) = "
            f"{b.speed:.5g} rev/s; P = (∫|F|^p|ω_rel|dt / ∫|ω_rel|dt)^(1/p) = {b.P:.5g} N "
            f"(p = {b.exponent:.4g}); L10 = (C/P)^p·10⁶ = ({b.C:.5g}/{b.P:.5g})^{b.exponent:.4g}"
            f"·10⁶ = {life:.4g} rev = {hours:.4g} h."
        ]
    return out


def _pins(sizing) -> list[str]:
    out = []
    for p in sizing.pins:
        area = math.pi * p.diameter**2 / 4
        out.append(
            f"- **{p.joint}** (d = {p.diameter * 1e3:g} mm, {p.planes} shear plane"
            f"{'s' if p.planes > 1 else ''}): τ = |F|/({p.planes}·πd²/4) peaks at "
            f"{p.peak_shear / 1e6:.4g} MPa (|F| = {p.peak_shear * p.planes * area:.5g} N); "
            f"the eyes' pressure |F|/(d·w) at {p.peak_eye_pressure / 1e6:.4g} MPa."
        )
    return out


def _links(sizing) -> list[str]:
    out = []
    for x in sizing.links:
        f = x.factors
        where = f"at {x.peak_angle:.4g}°" if x.peak_angle is not None else "between two rows"
        m, a = x.cycle
        line = (
            f"- **{x.link}** ({x.shape}, A = {x.area * 1e6:.4g} mm², Z = {x.modulus * 1e9:.5g} "
            f"mm³, L = {x.stations[-1] * 1e3:.4g} mm from {x.pins[0]}): peaks |N| = "
            f"{abs(x.N).max():.5g} N, |V| = {abs(x.V).max():.5g} N, |M| = "
            f"{abs(x.M).max():.4g} N·m; the largest σ = |N|/A + |M|/Z = "
            f"{x.peak_stress / 1e6:.4g} MPa at {x.stations[x.critical] * 1e3:.4g} mm from "
            f"{x.pins[0]}, {where}; there σ_m = {m / 1e6:.4g} MPa, σ_a = {a / 1e6:.4g} MPa"
        )
        if f["goodman"] is not None and m > 0:
            line += (
                f"; Goodman n = 1/(σ_a/S_e + σ_m/S_ut) = {f['goodman']:.4g}, Soderberg "
                f"{f['soderberg']:.4g}, against yield S_y/σ = {f['yield']:.4g}."
            )
        elif f["goodman"] is not None:
            line += (
                f"; a compressive mean: Goodman and Soderberg n = S_e/σ_a = {f['goodman']:.4g}, "
                f"against yield S_y/σ = {f['yield']:.4g}."
            )
        out.append(line)
    return out


def block() -> str:
    result = ks.analyze(ks.load(FILE))
    sizing = sizing_stage(result)
    lines = ["Bearings:", "", *_bearings(sizing), "", "Pins:", "", *_pins(sizing), ""]
    lines += ["Links:", "", *_links(sizing), ""]
    least = sizing.least()
    n, link = least["safety_factor"]
    h, joint = least["L10_hours"]
    lines += [
        "`kinetostatics run` prints:",
        "",
        "```text",
        f"sizing: {len(sizing.bearings)} bearings, {len(sizing.pins)} pins, "
        f"{len(sizing.links)} links; least safety factor {n:.3g} (Goodman, link {link}); "
        f"shortest bearing life L10 {h:.4g} h (joint {joint})",
        "```",
    ]
    return "\n".join(lines)


if __name__ == "__main__":
    text = block()
    print(text)
    if "--write" in sys.argv:
        doc = ROOT / "docs" / "sizing.md"
        old = doc.read_text(encoding="utf-8")
        i, j = old.index(BEGIN) + len(BEGIN), old.index(END)
        doc.write_text(old[:i] + "\n" + text + "\n" + old[j:], encoding="utf-8")
