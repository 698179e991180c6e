"""Every number and figure of docs/clearance.md (the swing mechanism with clearance).

    python docs/scripts/clearance_values.py            # print (a1, a2: ~1 min; b: ~15 min)
    python docs/scripts/clearance_values.py --write    # and replace the block in docs/clearance.md

Runs are cached in docs/scripts/.clearance_cache.npz (delete it to recompute).
"""

from __future__ import annotations

import sys
from dataclasses import replace
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT / "src"))

import kinetostatics as ks  # noqa: E402
from kinetostatics.clearance import ideal, motion_over_time, two_force_member, with_clearance  # noqa: E402
from kinetostatics.contact import ContactLaw, simulate_contact  # noqa: E402
from kinetostatics.dynamics import simulate  # noqa: E402

SWING = ROOT / "mechanisms" / "ammunition_swing.yaml"
CACHE = Path(__file__).with_name(".clearance_cache.npz")
BEGIN, END = "<!-- clearance_values: begin -->", "<!-- clearance_values: end -->"
SIZES = (0.0, 0.5e-3, 1e-3)
T_A1, T_B = 0.8, 0.1             # simulated spans: model a1, model b (its cost: docs)
LAW = ContactLaw(journal_radius=0.02, restitution=0.9)


def a1_run(e: float, t):
    model = with_clearance(ks.load(SWING), size=e)
    sim = simulate(model, T_A1, rtol=1e-9)
    return motion_over_time(sim, "arm", t)


def b_run(e: float, t, until=T_B, law=LAW, rtol=1e-5):
    model = with_clearance(ks.load(SWING), size=e, kind="contact", contact=law)
    run = simulate_contact(model, until, method="RK45", rtol=rtol)
    r = motion_over_time(run, "arm", t)
    r["impacts"] = np.array([len(run.impacts)])
    r["nfev"] = np.array([run.nfev])
    return r


def runs() -> dict:
    if CACHE.exists():
        return dict(np.load(CACHE))
    out = {"t_a1": np.linspace(0.0, T_A1, 801), "t_b": np.linspace(0.0, T_B, 1001)}
    for e in SIZES:
        for k, v in a1_run(e, out["t_a1"]).items():
            out[f"a1_{e * 1e3:g}_{k}"] = v
    for e in SIZES[1:]:
        for k, v in b_run(e, out["t_b"]).items():
            out[f"b_{e * 1e3:g}_{k}"] = v
    np.savez(CACHE, **out)
    return out


def settle(t, alpha, ref, band):
    """Last time |alpha − ref| exceeds ``band`` (0 if never)."""
    bad = np.nonzero(np.abs(alpha - ref) > band)[0]
    return float(t[bad[-1]]) if bad.size else 0.0


def figures(r: dict) -> None:
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    for key, label, conv in (("alpha", "arm angular acceleration (rad/s²)", 1.0),
                             ("omega", "arm angular velocity (rad/s)", 1.0),
                             ("theta", "arm angle turned (°)", np.degrees(1.0))):
        fig, ax = plt.subplots(figsize=(7, 4), dpi=100)
        for e, style in zip(SIZES, ("k-", "b--", "r:")):
            y = r[f"a1_{e * 1e3:g}_{key}"]
            y = (y - y[0]) * conv if key == "theta" else y * conv
            ax.plot(r["t_a1"], y, style, label=f"(a1) e = {e * 1e3:g} mm")
        for e, style in zip(SIZES[1:], ("c-", "m-")):
            y = r[f"b_{e * 1e3:g}_{key}"]
            y = (y - y[0]) * conv if key == "theta" else y * conv
            ax.plot(r["t_b"], y, style, lw=0.7, label=f"(b) contact, e = {e * 1e3:g} mm (0–0.1 s)")
        ax.set_xlabel("time (s)")
        ax.set_ylabel(label)
        ax.grid(True, alpha=0.3)
        ax.legend(fontsize=8)
        fig.tight_layout()
        fig.savefig(ROOT / "docs" / "img" / f"swing_clearance_{key}.png")
        plt.close(fig)


def text(r: dict) -> str:
    t, tb = r["t_a1"], r["t_b"]
    ref = {k: r[f"a1_0_{k}"] for k in ("theta", "omega", "alpha")}
    refb = {k: np.interp(tb, t, ref[k]) for k in ref}
    lines = ["### Model (a1): prescribed clearance-link rotation, 0–0.8 s", "",
             "| e (mm) | arm turn at 0.8 s (°) | max \\|Δθ\\| (°) | max \\|Δω\\| (rad/s) | "
             "max \\|Δα\\| (rad/s²) | max \\|Δα\\| in 0–0.1 s | energy injected by the "
             "clearance drivers (J) | their peak power (W) |", "|---|---|---|---|---|---|---|---|"]
    for e in SIZES:
        p = f"a1_{e * 1e3:g}_"
        th = r[p + "theta"] - r[p + "theta"][0]
        power = sum(r[k] for k in r if k.startswith(p) and k.endswith(".power"))
        energy = float(np.trapezoid(power, t)) if hasattr(np, "trapezoid") else float(np.trapz(power, t))
        early = t <= 0.1
        lines.append(
            f"| {e * 1e3:g} | {np.degrees(th[-1]):.3f} | "
            f"{np.degrees(np.max(np.abs(r[p + 'theta'] - ref['theta']))):.3f} | "
            f"{np.max(np.abs(r[p + 'omega'] - ref['omega'])):.4f} | "
            f"{np.max(np.abs(r[p + 'alpha'] - ref['alpha'])):.4f} | "
            f"{np.max(np.abs(r[p + 'alpha'] - ref['alpha'])[early]):.4f} | {energy:.3f} | "
            f"{np.max(np.abs(power)):.2f} |")
    lines += ["", "### Model (b): contact–impact (Lankarani–Nikravesh), 0–0.1 s", "",
              "| e (mm) | Hertz K (N/m^1.5) | impacts | RHS evaluations | α(0) (rad/s²) | "
              "max \\|Δα\\| (rad/s²) | \\|Δα\\| > 10 % of α_ideal until (s) | "
              "Δθ at 0.1 s (°) | Δω at 0.1 s (rad/s) |", "|---|---|---|---|---|---|---|---|---|"]
    for e in SIZES[1:]:
        p = f"b_{e * 1e3:g}_"
        da = r[p + "alpha"] - refb["alpha"]
        lines.append(
            f"| {e * 1e3:g} | {LAW.for_clearance(e).k:.3e} | {int(r[p + 'impacts'][0])} | "
            f"{int(r[p + 'nfev'][0])} | {r[p + 'alpha'][0]:.3f} | {np.max(np.abs(da)):.3f} | "
            f"{settle(tb, r[p + 'alpha'], refb['alpha'], 0.1 * np.abs(refb['alpha'])):.4f} | "
            f"{np.degrees(r[p + 'theta'][-1] - refb['theta'][-1]):.5f} | "
            f"{r[p + 'omega'][-1] - refb['omega'][-1]:.5f} |")
    lines += ["", f"Ideal (e = 0) arm at 0.1 s: α = {refb['alpha'][-1]:.4f} rad/s², "
              f"ω = {refb['omega'][-1]:.4f} rad/s."]
    lines += ["", "### Model (a2): two-force member on the slider-crank (kinetostatics)", "",
              "| e (mm) | max \\|ΔF_A\\| (N) | max \\|Δ torque\\| (N·m) | ΔF / e (N/mm) | "
              "max clearance-link couple (N·m) | iterations |", "|---|---|---|---|---|---|"]
    sc = ks.load(ROOT / "mechanisms" / "slider_crank.yaml")
    pos = np.radians(np.arange(0, 360, 30))
    for e in (1e-3, 1e-4, 1e-5):
        a2 = two_force_member(sc, {"A": e, "B": e}, positions=pos)
        dF = np.hypot(a2.column("A.Fx") - a2.ideal["A.Fx"], a2.column("A.Fy") - a2.ideal["A.Fy"])
        dT = np.abs(a2.column("motor.torque") - a2.ideal["motor.torque"])
        couple = max(np.max(np.abs(a2.column(f"{k}_turn.torque"))) for k in "AB")
        lines.append(f"| {e * 1e3:g} | {np.max(dF):.4g} | {np.max(dT):.4g} | "
                     f"{np.max(dF) / (e * 1e3):.4g} | {couple:.1e} | {int(a2.iterations.max())} |")
    return "\n".join(lines)


def main() -> None:
    r = runs()
    figures(r)
    block = text(r)
    print(block)
    if "--write" in sys.argv:
        doc = ROOT / "docs" / "clearance.md"
        s = doc.read_text(encoding="utf-8")
        a, b = s.index(BEGIN) + len(BEGIN), s.index(END)
        doc.write_text(s[:a] + "\n" + block + "\n" + s[b:], encoding="utf-8")


if __name__ == "__main__":
    main()
