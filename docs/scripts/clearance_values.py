"""Every number and figure of docs/clearance.md (the swing mechanism with clearance).

    python docs/scripts/clearance_values.py            # print (a1, a2: ~1 min; b: see below)
    python docs/scripts/clearance_values.py --write    # and replace the block in docs/clearance.md
    python docs/scripts/clearance_values.py --run b 0.5   # one run into the cache (kind, e in mm)

Each run is cached in docs/scripts/.clearance_cache/ (delete it to recompute); the two
contact runs over 0.8 s take ~10–20 min each (run them in parallel with --run).
"""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT / "src"))

import kinetostatics as ks  # noqa: E402
from kinetostatics.dynamics import simulate  # noqa: E402
from kinetostatics.dynamics.clearance import motion_over_time, two_force_member, with_clearance  # noqa: E402
from kinetostatics.dynamics.contact import ContactLaw, simulate_contact  # noqa: E402

SWING = ROOT / "mechanisms" / "ammunition_swing.yaml"
CACHE = Path(__file__).with_name(".clearance_cache")  # one .npz per run (git-ignored)
BEGIN, END = "<!-- clearance_values: begin -->", "<!-- clearance_values: end -->"
SIZES = (0.0, 0.5e-3, 1e-3)
T_END = 0.8  # simulated span of both models (s)
T = np.linspace(0.0, T_END, 801)  # samples: 1 ms (model a1, smooth)
T_FINE = np.linspace(0.0, T_END, 8001)  # 0.1 ms: model b (the contact rings at ~1 kHz)
LAW = ContactLaw(journal_radius=0.02, restitution=0.9)
B_METHOD, B_RTOL = "BDF", 1e-5  # the contact runs' integrator (docs: speed against error)


def a1_run(e: float, t=T):
    model = with_clearance(ks.load(SWING), size=e)
    sim = simulate(model, T_END, rtol=1e-9)
    return motion_over_time(sim, "arm", t)


def b_run(e: float, t=T_FINE, until=T_END, law=LAW, method=B_METHOD, rtol=B_RTOL):
    import time

    model = with_clearance(ks.load(SWING), size=e, kind="contact", contact=law)
    wall = time.perf_counter()
    run = simulate_contact(model, until, method=method, rtol=rtol)
    wall = time.perf_counter() - wall
    r = motion_over_time(run, "arm", t[t <= until])
    r["impacts"] = np.array([len(run.impacts)])
    r["separations"] = np.array([len(run.separations)])
    r["nfev"] = np.array([run.nfev])
    r["wall"] = np.array([wall])
    return r


def _cached(kind: str, e: float) -> dict:
    """One run (kind a1 or b, clearance e in m), computed once and kept in CACHE."""
    path = CACHE / f"{kind}_{e * 1e3:g}mm.npz"
    if path.exists():
        return dict(np.load(path))
    r = (a1_run if kind == "a1" else b_run)(e)
    CACHE.mkdir(exist_ok=True)
    np.savez(path, **r)
    return r


def runs() -> dict:
    """All runs: keys ``<a1|b>_<e in mm>_<quantity>``, times ``a1_t``, ``b_t``; ``b_0_*``
    is the ideal joint (a1 at e = 0, smooth) interpolated to model b's times."""
    out = {"a1_t": T, "b_t": T_FINE}
    for kind, sizes in (("a1", SIZES), ("b", SIZES[1:])):
        for e in sizes:
            for k, v in _cached(kind, e).items():
                out[f"{kind}_{e * 1e3:g}_{k}"] = v
    for k in ("theta", "omega", "alpha"):
        out[f"b_0_{k}"] = np.interp(T_FINE, T, out[f"a1_0_{k}"])
    return out


BANDS = (0.05, 0.01)  # settling bands: fractions of the ideal run's max |α|
QUIET = 0.1  # s: "settled" needs the last QUIET s inside the band


def settle(t, alpha, ref, band):
    """The first sample time after the last one at which |alpha − ref| exceeds ``band``
    (0 if never)."""
    bad = np.nonzero(np.abs(alpha - ref) > band)[0]
    return float(t[min(bad[-1] + 1, len(t) - 1)]) if bad.size else 0.0


def first_quiet(t, alpha, ref, band, quiet=QUIET) -> str:
    """The first time from which |alpha − ref| stays within ``band`` for ``quiet`` s."""
    ok = np.abs(alpha - ref) <= band
    n = int(round(quiet / (t[1] - t[0])))
    run = np.convolve(ok.astype(int), np.ones(n + 1, int), "valid") == n + 1
    k = np.nonzero(run)[0]
    return f"{t[k[0]]:.3f}" if k.size else "never"


def ringing(t, d) -> float:
    """Dominant frequency (Hz, above 20 Hz) of ``d`` over 0.1 s to the end, a cubic
    trend removed."""
    sel = t >= 0.1
    x = d[sel] - np.polyval(np.polyfit(t[sel], d[sel], 3), t[sel])
    f = np.fft.rfftfreq(x.size, t[1] - t[0])
    high = f > 20.0
    return float(f[high][np.argmax(np.abs(np.fft.rfft(x))[high])])


def settling_text(t, alpha, ref, band) -> str:
    ts = settle(t, alpha, ref, band)
    if ts == 0.0:
        return "never outside the band"
    return f"{ts:.4f}" if ts <= t[-1] - QUIET else "not settled"


START = {"a1": 0.1, "b": 0.01}  # s: the zoom on the start of each model
STYLES = {0.0: ("k", "-", 1.6), 0.5e-3: ("tab:blue", "--", 1.2), 1e-3: ("tab:red", ":", 1.4)}
QUANTITIES = (
    ("alpha", "arm angular acceleration ε5 (rad/s²)", 1.0),
    ("omega", "arm angular velocity ω5 (rad/s)", 1.0),
    ("theta", "arm angle turned θ − θ(0) (°)", np.degrees(1.0)),
)


def _curve(r, kind, e, key, conv):
    y = r[f"{kind}_{e * 1e3:g}_{key}"]
    return (y - y[0]) * conv if key == "theta" else y * conv


def figures(r: dict) -> None:
    """docs/img/clearance_<alpha|omega|theta>.png: per quantity, model (a1) (left) and
    model (b) (right), e = 0 (ideal joint), 0.5 and 1 mm, 0–0.8 s; below, the difference
    from the ideal joint; for the acceleration also the start, 0–0.1 s."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    for key, label, conv in QUANTITIES:
        panels = ["curves", "difference"] + (["start"] if key == "alpha" else [])
        fig, axes = plt.subplots(
            len(panels), 2, figsize=(11, 3.3 * len(panels)), dpi=100, squeeze=False
        )
        for col, (kind, title) in enumerate(
            (
                ("a1", "(a1) prescribed clearance-link rotation"),
                ("b", "(b) contact–impact, Hertz K"),
            )
        ):
            ideal, t = _curve(r, kind, 0.0, key, conv), r[f"{kind}_t"]
            for row, panel in enumerate(panels):
                ax = axes[row, col]
                for e in SIZES:
                    if panel == "difference" and e == 0:
                        continue
                    c, ls, lw = STYLES[e]
                    y = _curve(r, kind, e, key, conv)
                    ax.plot(
                        t,
                        y - ideal if panel == "difference" else y,
                        color=c,
                        ls=ls,
                        lw=lw if kind == "a1" or panel == "start" else 0.6 * lw,
                        label="e = 0 (ideal joint)" if e == 0 else f"e = {e * 1e3:g} mm",
                    )
                name = {
                    "curves": title,
                    "difference": f"{title}: minus the ideal joint",
                    "start": "",
                }[panel]
                if name:
                    ax.set_title(name, fontsize=9)
                if panel == "start":
                    ax.set_xlim(0, START[kind])
                    ax.set_title(f"{title}: start, 0–{START[kind]:g} s", fontsize=9)
                if panel == "difference" and kind == "b":  # the start-up jolt: off scale
                    late = t >= 0.01
                    d = np.array([_curve(r, kind, e, key, conv) - ideal for e in SIZES[1:]])
                    top = 1.5 * np.max(np.abs(d[:, late]))
                    ax.set_ylim(-top, top)
                    if np.max(np.abs(d)) > top:
                        ax.text(
                            0.02,
                            0.04,
                            f"off scale in 0–10 ms: {np.min(d):.3g} to "
                            f"{np.max(d):.3g} (the unloaded start)",
                            fontsize=8,
                            transform=ax.transAxes,
                        )
                ax.set_xlabel("time t (s)")
                ax.set_ylabel(label if panel != "difference" else "Δ " + label, fontsize=9)
                ax.grid(True, alpha=0.3)
                ax.legend(fontsize=8)
            if key == "alpha":  # the same scale for both models' curves
                lo, hi = ideal.min(), ideal.max()
                axes[0, col].set_ylim(lo - 0.5 * (hi - lo), hi + 0.5 * (hi - lo))
        fig.tight_layout()
        fig.savefig(ROOT / "docs" / "img" / f"clearance_{key}.png")
        plt.close(fig)


def convergence_text() -> str:
    """Model (b) → ideal joint on the crank-rod-slider of tests/dynamics/test_contact_convergence.py
    (the same runs as the tests)."""
    sys.path.insert(0, str(ROOT))
    from tests.dynamics.test_contact_convergence import (
        CRANK_ROD_SLIDER,
        PUSH,
        T,
        deviation,
        penetration,
    )

    model = ks.loads(CRANK_ROD_SLIDER)
    lines = [
        "### Model (b) → the ideal joint: crank-rod-slider"
        " (tests/dynamics/test_contact_convergence.py)",
        "",
        f"Crank at 60 rpm prescribed, {PUSH:g} N on the slider, clearance at B, 0–{T:g} s; "
        "slider deviations from the closed-form ideal.",
        "",
        "| e (µm) | K (N/m^1.5) | e + (F/K)^(2/3) (µm) | settled Δx (µm) | max \\|Δx\\| (µm) | "
        "max \\|Δv\\| (mm/s) | max \\|Δa\\| (m/s²) |",
        "|---|---|---|---|---|---|---|",
    ]
    for e, k in (
        (1e-6, 1e8),
        (1e-6, 1e9),
        (1e-6, 1e10),
        (1e-3, 1e10),
        (2.5e-4, 1e10),
        (6.25e-5, 1e10),
    ):
        d = deviation(model, e, k)
        lines.append(
            f"| {e * 1e6:g} | {k:.0e} | {(e + penetration(k)) * 1e6:.2f} | "
            f"{-d['settled'] * 1e6:.2f} | {d['dx'] * 1e6:.2f} | {d['dv'] * 1e3:.2f} | "
            f"{d['da']:.1f} |"
        )
    return "\n".join(lines)


def text(r: dict) -> str:
    ref = {k: r[f"a1_0_{k}"] for k in ("theta", "omega", "alpha")}
    bands = [b * np.max(np.abs(ref["alpha"])) for b in BANDS]
    lines = [
        f"Ideal joint (e = 0): the arm turns {np.degrees(ref['theta'][-1] - ref['theta'][0]):.2f}° "
        f"in 0.8 s (calibration, tested); ε5 from {ref['alpha'][0]:.3f} to "
        f"{ref['alpha'][-1]:.3f} rad/s², max |ε5| = {np.max(np.abs(ref['alpha'])):.3f} rad/s²; "
        f"ω5(0.8 s) = {ref['omega'][-1]:.3f} rad/s.",
        "",
        "Settling: the last time |Δε5| = |ε5 − ε5,ideal| exceeds a band of "
        + " or ".join(f"{b:.0%}" for b in BANDS)
        + " of the ideal run's max |ε5| ("
        + " or ".join(f"{b:.3f}" for b in bands)
        + ' rad/s²); "not settled" if it '
        f"still does within the last {QUIET:g} s.",
        "",
        "| model | e (mm) | arm turn at 0.8 s (°) | Δ turn at 0.8 s (°) | max \\|Δω\\| (rad/s) | "
        "max \\|Δε5\\| 0–0.1 s (rad/s²) | max \\|Δε5\\| 0.4–0.8 s (rad/s²) | "
        + " | ".join(f"settles by, {b:.0%} band (s)" for b in BANDS)
        + f" | first {QUIET:g} s inside the {BANDS[-1]:.0%} band from (s) | ringing (Hz) "
        "| impacts / separations | RHS evaluations, wall (s) |",
        "|---|---|---|---|---|---|---|---|---|---|---|---|---|",
    ]
    for kind in ("a1", "b"):
        for e in SIZES[1:]:
            p, t = f"{kind}_{e * 1e3:g}_", r[f"{kind}_t"]
            ref = {k: r[f"{kind}_0_{k}"] for k in ("theta", "omega", "alpha")}
            early, late = t <= 0.1, t >= 0.4
            th = r[p + "theta"] - r[p + "theta"][0]
            da = np.abs(r[p + "alpha"] - ref["alpha"])
            extra = (
                ("–", "–")
                if kind == "a1"
                else (
                    f"{int(r[p + 'impacts'][0])} / {int(r[p + 'separations'][0])}",
                    f"{int(r[p + 'nfev'][0])}, {float(r[p + 'wall'][0]):.0f}",
                )
            )
            lines.append(
                f"| {kind} | {e * 1e3:g} | {np.degrees(th[-1]):.3f} | "
                f"{np.degrees(th[-1] - (ref['theta'][-1] - ref['theta'][0])):.4f} | "
                f"{np.max(np.abs(r[p + 'omega'] - ref['omega'])):.4f} | {np.max(da[early]):.3f} | "
                f"{np.max(da[late]):.3f} | "
                + " | ".join(settling_text(t, r[p + "alpha"], ref["alpha"], b) for b in bands)
                + f" | {first_quiet(t, r[p + 'alpha'], ref['alpha'], bands[-1])} | "
                + (f"{ringing(t, r[p + 'alpha'] - ref['alpha']):.0f}" if kind == "b" else "–")
                + " | "
                f"{extra[0]} | {extra[1]} |"
            )
    edges = np.arange(0.0, T_END + 1e-9, 0.1)
    lines += [
        "",
        "Envelope of the disturbance: max |Δε5| (rad/s²) in each 0.1 s.",
        "",
        "| model | e (mm) | "
        + " | ".join(f"{a:.1f}–{b:.1f}" for a, b in zip(edges[:-1], edges[1:]))
        + " |",
        "|---|---|" + "---|" * (len(edges) - 1),
    ]
    for kind in ("a1", "b"):
        t = r[f"{kind}_t"]
        for e in SIZES[1:]:
            da = np.abs(r[f"{kind}_{e * 1e3:g}_alpha"] - r[f"{kind}_0_alpha"])
            cells = [np.max(da[(t >= a) & (t <= b)]) for a, b in zip(edges[:-1], edges[1:])]
            lines.append(
                f"| {kind} | {e * 1e3:g} | " + " | ".join(f"{c:.3f}" for c in cells) + " |"
            )
    lines += [
        "",
        "Model (a1): energy injected by the clearance drivers (their power integrated "
        "over 0–0.8 s).",
        "",
        "| e (mm) | clearance drivers' energy (J) | their peak power (W) |",
        "|---|---|---|",
    ]
    t = r["a1_t"]
    for e in SIZES[1:]:
        p = f"a1_{e * 1e3:g}_"
        power = sum(r[k] for k in r if k.startswith(p) and k.endswith(".power"))
        energy = float(np.sum(0.5 * (power[1:] + power[:-1]) * np.diff(t)))
        lines.append(f"| {e * 1e3:g} | {energy:.3f} | {np.max(np.abs(power)):.2f} |")
    lines += [
        "",
        f"Model (b): Hertz K = {LAW.for_clearance(0.5e-3).k:.3e} N/m^1.5 (e = 0.5 mm), "
        f"{LAW.for_clearance(1e-3).k:.3e} N/m^1.5 (e = 1 mm); {B_METHOD}, rtol {B_RTOL:g}, "
        "the analytic contact Jacobian.",
    ]
    lines += ["", convergence_text()]
    lines += [
        "",
        "### Model (a2): two-force member on the slider-crank (kinetostatics)",
        "",
        "| e (mm) | max \\|ΔF_A\\| (N) | max \\|Δ torque\\| (N·m) | ΔF / e (N/mm) | "
        "max clearance-link couple (N·m) | iterations |",
        "|---|---|---|---|---|---|",
    ]
    sc = ks.load(ROOT / "mechanisms" / "slider_crank.yaml")
    pos = np.radians(np.arange(0, 360, 30))
    for e in (1e-3, 1e-4, 1e-5):
        a2 = two_force_member(sc, {"A": e, "B": e}, positions=pos)
        dF = np.hypot(a2.column("A.Fx") - a2.ideal["A.Fx"], a2.column("A.Fy") - a2.ideal["A.Fy"])
        dT = np.abs(a2.column("motor.torque") - a2.ideal["motor.torque"])
        couple = max(np.max(np.abs(a2.column(f"{k}_turn.torque"))) for k in "AB")
        lines.append(
            f"| {e * 1e3:g} | {np.max(dF):.4g} | {np.max(dT):.4g} | "
            f"{np.max(dF) / (e * 1e3):.4g} | {couple:.1e} | {int(a2.iterations.max())} |"
        )
    return "\n".join(lines)


def main() -> None:
    if "--run" in sys.argv:  # one run into the cache (to run several in parallel)
        kind, e = sys.argv[sys.argv.index("--run") + 1 :][:2]
        _cached(kind, float(e) * 1e-3)
        return
    r = runs()
    figures(r)
    block = text(r)
    print(block)
    if "--write" in sys.argv:
        write_block(BEGIN, END, block)


def write_block(begin: str, end: str, block: str, doc=ROOT / "docs" / "clearance.md") -> None:
    """Replace the text between the markers ``begin`` and ``end`` of ``doc``."""
    s = doc.read_text(encoding="utf-8")
    a, b = s.index(begin) + len(begin), s.index(end)
    doc.write_text(s[:a] + "\n" + block + "\n" + s[b:], encoding="utf-8")


if __name__ == "__main__":
    main()
