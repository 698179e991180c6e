"""Positions: the closed-form fast path against the general Newton path, the
Newton tolerance and the continuation (prediction) step.

``kinetostatics.kinematics.positions`` solves all positions in closed form when every
group is a closed-form dyad (fast path); otherwise it runs the general path:
a continuation over the cycle with driver steps ≤ ``COARSE_STEP`` (30°) and a
second-order predictor, then one batched Newton per group over all requested
positions from a cubic Hermite prediction, converged to ``TOL`` (1e-12,
relative to L_ref and 1 rad).  Here the general path is forced by disabling
the closed forms (``kinetostatics.kinematics.dyads.closed_form`` → None), and ``TOL`` and
``COARSE_STEP`` are varied.

Iterations: *batch* = Newton iterations of the final batch per position (summed
over the groups; mean / max); *all* = every Newton iteration of the solve
(continuation, batch, fallback) per position.  Errors against the closed form
of tests/oracles/slider_crank_closed_form.py: pose = max |Δx|, |Δy| / L_ref and
|Δθ| (rad); q̇, q̈ as in tests/benchmarks/accuracy_derivatives.py (from the exact
Jacobian solve at the computed positions).  For the slotting machine the
reference is the fast path.

    python tests/benchmarks/accuracy_positions.py [--quick] [--update]
"""

from __future__ import annotations

import accuracy_common as ac
import numpy as np
from accuracy_common import Table, e, ms

from kinetostatics.kinematics import newton, positions
from kinetostatics.kinematics.derivatives import derivatives
from kinetostatics.kinematics.positions import solve_positions
from kinetostatics.kinematics.schedule import sample_times, schedule

TOLS = (1e-4, 1e-6, 1e-8, 1e-10, 1e-12, 1e-14)
STEPS_DEG = (5, 10, 30, 60, 90, 120)
TIMES = ("360 [ms]", "36,000 [ms]")


class Counter:
    """Counts every Newton iteration of ``group_newton`` (kinematics.newton) while active."""

    def __enter__(self):
        self.total, saved = 0, newton.group_newton

        def counting(*args, **kw):
            q, ok, it = saved(*args, **kw)
            self.total += int(np.sum(it))
            return q, ok, it

        self.patch = ac.knobs(group_newton=counting)
        self.patch.__enter__()
        return self

    def __exit__(self, *exc):
        self.patch.__exit__(*exc)


def oracle(name: str):
    from tests.oracles import slider_crank_closed_form as cf

    if name == "slider_crank":
        return cf.SliderCrank()
    if name == "tests/hard/slider_crank_edge.yaml":
        return cf.SliderCrank(a=0.1, b=0.1201, e=-0.02, r1=0.05, r2=0.06)
    return None


def measure(name: str, general: bool, timing: bool, ref=None, **knobs):
    """One row: (iterations, errors, times, solution)."""
    import contextlib

    with ac.general_path() if general else contextlib.nullcontext(), ac.knobs(**knobs):
        system = ac.system(name)
        sched = schedule(system)
        runs = {}
        for n in (360, 36_000):
            phi = np.arange(n) * 2 * np.pi / n
            t, _ = sample_times(
                system, sched, system.model.analysis.start + np.sign(sched.speed[0]) * phi
            )
            runs[n] = (t, phi)
        t, phi = runs[360]
        solve_positions(system, t, sched)  # start pose cached, as in every run
        with Counter() as count:
            sol = solve_positions(system, t, sched)
        _, psi_d, psi_dd = sched(t)
        qd, qdd, _ = derivatives(system, sol.q, psi_d, psi_dd)
        p = oracle(name)
        if p is not None:
            q_ref, qd_ref, qdd_ref = ac.slider_crank_state(p, phi)
        else:  # its own reference (errors 0)
            q_ref, qd_ref, qdd_ref = ref if ref is not None else (sol.q, qd, qdd)
        errs = (
            ac.pose_error(system, sol.q, q_ref),
            ac.column_error(qd, qd_ref),
            ac.column_error(qdd, qdd_ref),
        )
        times = [None, None]
        if timing:
            times = [
                ac.best_of(
                    lambda n=n: solve_positions(system, runs[n][0], sched),
                    repeat=None if n == 360 else 3,
                )
                for n in (360, 36_000)
            ]
    iters = (
        float(np.mean(sol.iterations)),
        int(np.max(sol.iterations)),
        count.total / len(t),
        sol.fallback,
    )
    return iters, errs, times, (sol.q, qd, qdd)


def row(tab, label, tol, step, iters, errs, times):
    tab.add(
        label,
        tol,
        step,
        f"{iters[0]:.2f} / {iters[1]}",
        f"{iters[2]:.2f}",
        iters[3],
        *(e(x) for x in errs),
        *(ms(x) for x in times),
    )


def header():
    return Table(
        [
            "path",
            "TOL",
            "coarse step",
            "batch iterations",
            "all iterations",
            "fallback",
            "pose error",
            "q̇ error",
            "q̈ error",
            *TIMES,
        ],
        timing=set(TIMES),
    )


def build(timing: bool = True):
    blocks, points = {}, {}
    # slider-crank: fast path, then the general path over TOL and over the coarse step
    tab = header()
    fast = measure("slider_crank", False, timing)
    row(tab, "fast (closed form)", "—", "—", *fast[:3])
    pts_tol = []
    for tol in TOLS:
        m = measure("slider_crank", True, timing, TOL=tol)
        row(tab, "general (Newton)", f"{tol:.0e}", "30°", *m[:3])
        pts_tol.append((tol, *m[:3]))
    pts_step = []
    for deg in STEPS_DEG:
        if deg == 30:
            m = next(p[1:] for p in pts_tol if p[0] == positions.TOL)
            pts_step.append((deg, *m))
            continue
        m = measure("slider_crank", True, timing, COARSE_STEP=np.radians(deg))
        row(tab, "general (Newton)", "1e-12", f"{deg}°", *m[:3])
        pts_step.append((deg, *m[:3]))
    blocks["positions-slider_crank"] = tab.markdown()
    points["tol"] = (fast, pts_tol)
    points["step"] = pts_step
    # hard case and a mechanism without an independent oracle
    tab = header()
    for name, label in (
        ("tests/hard/slider_crank_edge.yaml", "slider-crank at the edge of assembly"),
        ("slotting_machine", "slotting machine (reference: fast path)"),
    ):
        f = measure(name, False, timing)
        ref = f[3] if oracle(name) is None else None
        row(tab, f"{label}: fast", "—", "—", *f[:3])
        g = measure(name, True, timing, ref=ref)
        row(tab, f"{label}: general", "1e-12", "30°", *g[:3])
    blocks["positions-others"] = tab.markdown()

    def plot():
        import matplotlib.pyplot as plt

        fast, pts = points["tol"]
        fig, axes = plt.subplots(1, 3, figsize=(15, 4.3))
        tol = [p[0] for p in pts]
        for k, label in enumerate(("pose", "q̇", "q̈")):
            axes[0].loglog(
                tol,
                [max(p[2][k], 1e-17) for p in pts],
                "o-",
                color=f"C{k}",
                label=f"general: {label}",
            )
            axes[0].axhline(
                max(fast[1][k], 1e-17), ls=":", color=f"C{k}", label=f"fast path: {label}"
            )
        axes[0].set_xlabel("Newton tolerance TOL (× L_ref for lengths, rad)")
        axes[0].set_ylabel("relative error against the closed form")
        axes[0].set_title("slider-crank, 360 positions: error against TOL", fontsize=10)
        axes[0].legend(fontsize=7)
        axes[0].grid(True, which="both", alpha=0.3)

        def cost(ax, x, times, iters, xlabel, title, logx=True):
            (ax.loglog if logx else ax.semilogy)(
                x,
                [t * 1e3 for t in times],
                "o-",
                color="C0",
                label="general path (Newton), 360 positions",
            )
            ax.axhline(fast[2][0] * 1e3, ls=":", color="k", label="fast path (closed-form dyads)")
            ax.set_xlabel(xlabel)
            ax.set_ylabel("positions stage, 360 positions [ms] (log)")
            ax.set_title(title, fontsize=10)
            ax.grid(True, which="both", alpha=0.3)
            tw = ax.twinx()
            tw.plot(x, iters, "s--", color="C3", label="Newton iterations per position (all)")
            tw.set_ylabel("Newton iterations per position", color="C3")
            tw.set_ylim(0, max(iters) * 1.2)
            h1, l1 = ax.get_legend_handles_labels()
            h2, l2 = tw.get_legend_handles_labels()
            ax.legend(h1 + h2, l1 + l2, fontsize=7, loc="lower left")

        cost(
            axes[1],
            tol,
            [p[3][0] for p in pts],
            [p[1][2] for p in pts],
            "Newton tolerance TOL",
            "cost against TOL (coarse step 30°)",
        )
        steps = points["step"]
        cost(
            axes[2],
            [p[0] for p in steps],
            [p[3][0] for p in steps],
            [p[1][2] for p in steps],
            "prediction (coarse continuation) step [deg]",
            "cost against the prediction step (TOL 1e-12)",
            logx=False,
        )
        return ac.save_figure(fig, "accuracy_positions.png")

    return blocks, (plot if timing else None)


if __name__ == "__main__":
    ac.main(build)
