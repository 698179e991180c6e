"""Friction: what the frictionless, the approximate and the consistent driving
torque cost, and how far the first two are from the consistent one.

All friction data of a shipped file are scaled by s (friction-circle radii and
Coulomb coefficients; ``docs/scripts/friction_levels.py``).  Errors: the
largest |τ − τ_consistent| over the 360 positions relative to the largest
|τ_consistent| (positions where the consistent solution is self-locking are
skipped).  For the slider-crank the approximate torque is also compared with
the independent closed form of the source's eq. 9
(tests/oracles/slider_crank_closed_form.py).

Times: ``ks.analyze`` with ``friction=False`` and with the default (both
friction solutions), and the friction stages alone, called on one system with
the kinematics and frictionless reactions already solved: *approximate* =
``friction.setup`` + Φ_q⁻¹ + ``friction.approximate``; *consistent* =
``friction.consistent`` (fixed point, homotopy where it fails).

    python tests/benchmarks/accuracy_friction.py [--quick] [--update]
"""

from __future__ import annotations

from dataclasses import replace

import accuracy_common as ac
import numpy as np
from accuracy_common import Table, e, ms
from friction_levels import scaled

import kinetostatics as ks
from kinetostatics.analysis.pipeline import kinetics
from kinetostatics.kinematics.positions import derivatives, solve_positions
from kinetostatics.kinematics.schedule import sample_times, schedule
from kinetostatics.kinetics import friction as fr

LEVELS = (0.01, 0.1, 0.5, 1.0, 2.0, 4.0, 8.0, 16.0)
NAMES = ("slider_crank", "slotting_machine")
TIMES = ("friction=False [ms]", "full [ms]", "approximate stage [ms]", "consistent stage [ms]")


def stages(system):
    """Closures timing the approximate and the consistent friction stage."""
    sched = schedule(system)
    t, _ = sample_times(system, sched, None)
    q = solve_positions(system, t, sched).q
    psi, psi_d, psi_dd = sched(t)
    qd, qdd, lu = derivatives(system, q, psi_d, psi_dd)
    # external loads need the cycle extremes of travel conditions: take them from analyze
    res = ks.analyze(system, friction=False, events=False)
    kin = kinetics(
        system,
        q,
        qd,
        qdd,
        psi,
        lu=lu,
        extremes=res.extremes,
        ref_speed=sched.reference,
        friction=False,
    )
    q_load, x0 = kin.q_load, kin.x0

    def approximate():
        fs = fr.setup(system, q, qd, sched.reference)
        return fr.approximate(system, fs, lu.solve_transposed, q_load, x0), fs

    _, fs = approximate()
    a = np.swapaxes(lu.jac, -1, -2)
    return approximate, lambda: fr.consistent(system, fs, a, lu.solve_transposed, q_load, x0)


def build(timing: bool = True):
    from tests.oracles import slider_crank_closed_form as cf

    blocks, points = {}, {}
    for name in NAMES:
        head = ["friction × s", "frictionless τ error", "approximate τ error"]
        if name == "slider_crank":
            head.append("approximate vs eq. 9")
        head += ["status 0 / 1 / 2 / 3", *TIMES]
        tab = Table(head, timing=set(TIMES))
        pts = []
        for s in LEVELS:
            system = ks.build_system(scaled(name, s))
            driver = system.motion_drivers[0].name
            r = ks.analyze(system)
            tau, tau_a, tau_0 = (
                r[f"{driver}.torque{k}"] for k in ("_friction", "_friction_approx", "")
            )
            ok = np.isfinite(tau)
            scale = np.max(np.abs(tau[ok]))
            err0 = np.max(np.abs(tau_0 - tau)[ok]) / scale
            erra = np.max(np.abs(tau_a - tau)[ok]) / scale
            cells = [f"{s:g}", e(err0), e(erra)]
            if name == "slider_crank":
                base = cf.SliderCrank()
                p = replace(
                    base,
                    rho_O=base.rho_O * s,
                    rho_A=base.rho_A * s,
                    rho_B=base.rho_B * s,
                    f=base.f * s,
                    L_ref=system.l_ref,
                )
                eq9 = cf.friction_approx_torque_eq9(p, np.radians(r["angle"]))
                cells.append(e(np.max(np.abs(tau_a - eq9)) / np.max(np.abs(eq9))))
            counts = np.bincount(r["friction.status"].astype(int), minlength=4)
            cells.append(" / ".join(str(c) for c in counts))
            times = [None] * 4
            if timing:
                approx, cons = stages(system)
                times = [
                    ac.best_of(lambda system=system: ks.analyze(system, friction=False)),
                    ac.best_of(
                        lambda system=system: ks.analyze(system), repeat=3 if s > 8 else None
                    ),
                    ac.best_of(approx),
                    ac.best_of(cons, repeat=3 if s > 8 else None),
                ]
            tab.add(*cells, *(ms(x) for x in times))
            pts.append((s, err0, erra, *times))
        points[name] = pts
        blocks[f"friction-{name}"] = f"**{name}**, 360 positions\n\n" + tab.markdown()

    def plot():
        import matplotlib.pyplot as plt

        fig, axes = plt.subplots(1, 2, figsize=(11.5, 4.4))
        floor = 1e-8  # the consistent solution is the reference: drawn here
        for name, color in zip(NAMES, ("C0", "C3")):
            pts = points[name]
            s = [p[0] for p in pts]
            axes[0].loglog(
                s,
                [p[1] for p in pts],
                "o--",
                color=color,
                mfc="none",
                label=f"{name}: frictionless",
            )
            axes[0].loglog(s, [p[2] for p in pts], "s-", color=color, label=f"{name}: approximate")
            cost_a = [(p[3] + p[5]) / p[3] for p in pts]
            cost_f = [p[4] / p[3] for p in pts]
            ax = axes[1]
            ax.loglog(
                [1.0] * len(pts),
                [p[1] for p in pts],
                "o",
                color=color,
                mfc="none",
                label=f"{name}: frictionless (cost 1)",
            )
            ax.loglog(cost_a, [p[2] for p in pts], "s", color=color, label=f"{name}: approximate")
            ax.loglog(
                cost_f,
                [floor] * len(pts),
                "^:",
                color=color,
                label=f"{name}: consistent (the reference)",
            )
            for p, x, xf in zip(pts, cost_a, cost_f):
                if p[0] in (0.01, 1.0, 16.0):
                    ax.annotate(
                        f"s={p[0]:g}",
                        (x, p[2]),
                        fontsize=7,
                        xytext=(4, -3),
                        textcoords="offset points",
                        color=color,
                    )
                if p[0] in (1.0, 16.0):
                    ax.annotate(
                        f"s={p[0]:g}",
                        (xf, floor),
                        fontsize=7,
                        xytext=(0, 6),
                        textcoords="offset points",
                        color=color,
                        ha="center",
                    )
        axes[0].set_xlabel("friction level s (× the file's friction radii and coefficients)")
        axes[0].set_ylabel("max |τ − τ_consistent| / max |τ_consistent|")
        axes[0].set_title(
            "driving torque error against friction level (360 positions)", fontsize=10
        )
        axes[0].legend(fontsize=7)
        axes[0].grid(True, which="both", alpha=0.3)
        ax = axes[1]
        ax.set_xlabel("wall time / wall time of ks.analyze(friction=False)")
        ax.set_ylabel("max |τ − τ_consistent| / max |τ_consistent|")
        ax.set_title("error against cost (consistent: error 0, drawn at 1e-8)", fontsize=10)
        ax.legend(fontsize=7, loc="center right")
        ax.grid(True, which="both", alpha=0.3)
        return ac.save_figure(fig, "accuracy_friction.png")

    return blocks, (plot if timing else None)


if __name__ == "__main__":
    ac.main(build)
