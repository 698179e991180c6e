"""Velocities and accelerations: exact (Jacobian) against difference quotients.

For each mechanism and each scheme — the exact solution from the constraint
Jacobian, the source text's forward differences and central differences at
driver steps h = 1e-1 … 1e-7 rad — the error of q̇ and q̈ over the 360 positions
of a cycle, and the wall time of the kinematics stage (positions + the
derivative method, stage functions called directly) and of the whole
frictionless ``ks.analyze(..., derivatives_by=...)``.

Errors: the largest over the coordinates (x, y, θ of every moving link) of
max|error| / max|reference| over the cycle (coordinates identically zero are
skipped).  Reference: the closed form (tests/oracles/slider_crank_closed_form.py)
for the slider-crank, the exact solution for the others.

    python tests/benchmarks/accuracy_derivatives.py [--quick] [--update]
"""

from __future__ import annotations

import accuracy_common as ac
import numpy as np
from accuracy_common import Table, e, ms

import kinetostatics as ks
from kinetostatics.base.blocks import BlockFactor
from kinetostatics.kinematics.differences import difference_derivatives
from kinetostatics.kinematics.positions import derivatives, solve_positions
from kinetostatics.kinematics.schedule import sample_times, schedule
from kinetostatics.structure.system import gamma, jacobian, nu

STEPS = (1e-1, 1e-2, 1e-3, 1e-4, 1e-5, 1e-6, 1e-7)
CASES = (
    ("slider_crank", "closed form"),
    ("slotting_machine", "exact solution"),
    ("stephenson_sixbar", "exact solution"),
)
N_LARGE = 36_000


def setup(name: str, n: int):
    system = ac.system(name)
    sched = schedule(system)
    start = system.model.analysis.start
    sign = np.sign(sched.speed[0])
    phi = np.arange(n) * 2 * np.pi / n
    t, _ = sample_times(system, sched, start + sign * phi)
    return system, sched, t, phi


def kinematics(system, sched, t, scheme: str, h: float | None):
    """The kinematics stage: positions, then the derivatives by ``scheme``."""

    def run():
        q = solve_positions(system, t, sched).q
        _, psi_d, psi_dd = sched(t)
        if scheme == "exact":
            qd, qdd, _ = derivatives(system, q, psi_d, psi_dd)
        else:
            qd, qdd = difference_derivatives(system, sched, t, q, scheme, h)
        return q, qd, qdd

    return run


BREAKDOWN = (
    "exact: all [ms]",
    "positions at the n points [ms]",
    "Φ_q and its block inverses [ms]",
    "ν, γ and the two solves [ms]",
    "differences: all (forward, h=1e-3) [ms]",
    "positions at the 2n neighbours [ms]",
)


def breakdown(system, sched, t, timing: bool, repeat=None, rounds: int = 3):
    """Wall times (s) of the kinematics stage and its parts, in the order of BREAKDOWN."""
    if not timing:
        return [None] * len(BREAKDOWN)
    q = solve_positions(system, t, sched).q
    _, psi_d, psi_dd = sched(t)
    blocks = [(p.rows, p.cols) for p in system.plans]
    lu = BlockFactor(jacobian(system, q), blocks)
    h = 1e-3 / sched.reference
    neighbours = np.concatenate((t + h, t + 2 * h))

    def solves():
        qd = lu.solve(nu(system, psi_d))
        return lu.solve(gamma(system, q, qd, psi_dd))

    funcs = (
        kinematics(system, sched, t, "exact", None),
        lambda: solve_positions(system, t, sched),
        lambda: BlockFactor(jacobian(system, q), blocks),
        solves,
        kinematics(system, sched, t, "forward", 1e-3),
        lambda: solve_positions(system, neighbours, sched),
    )
    best = [np.inf] * len(funcs)
    for _ in range(rounds):  # interleaved, so that a load spike hits no column alone
        best = [min(b, ac.best_of(f, repeat=repeat)) for b, f in zip(best, funcs)]
    return best


def reference(name, system, sched, t, phi):
    if name == "slider_crank":
        from tests.oracles import slider_crank_closed_form as cf

        return ac.slider_crank_state(cf.SliderCrank(), phi)[1:]
    return kinematics(system, sched, t, "exact", None)()[1:]


def schemes():
    yield "exact", None
    for s in ("forward", "central"):
        for h in STEPS:
            yield s, h


def build(timing: bool = True):
    blocks, points = {}, {}
    verdicts = []
    for name, ref_label in CASES:
        system, sched, t, phi = setup(name, 360)
        qd_ref, qdd_ref = reference(name, system, sched, t, phi)
        tab = Table(
            ["method", "step h (rad)", "q̇ error", "q̈ error", "kinematics [ms]", "analyze [ms]"],
            timing={"kinematics [ms]", "analyze [ms]"},
        )
        pts = []
        for scheme, h in schemes():
            run = kinematics(system, sched, t, scheme, h)
            _, qd, qdd = run()
            ev, ea = ac.column_error(qd, qd_ref), ac.column_error(qdd, qdd_ref)
            tk = ta = None
            if timing:
                tk = ac.best_of(run)
                by = "jacobian" if scheme == "exact" else scheme
                ta = ac.best_of(
                    lambda system=system, by=by, h=h: ks.analyze(
                        system, positions=None, friction=False, derivatives_by=by, step=h or 1.0
                    )
                )
            tab.add(scheme, "—" if h is None else f"{h:.0e}", e(ev), e(ea), ms(tk), ms(ta))
            pts.append((scheme, h, ev, ea, tk, ta))
        points[name] = pts
        text = [
            f"**{name}** ({len(system.links)} moving links, groups: "
            f"{'; '.join(p.group.label for p in system.plans)}), 360 positions, "
            f"reference: the {ref_label}.",
            "",
            tab.markdown(),
        ]
        if timing:
            exact = pts[0]
            diffs = pts[1:]
            slower = [p for p in diffs if p[4] <= exact[4]]
            better_v = [p for p in diffs if p[2] <= max(exact[2], 1e-15)]
            better_a = [p for p in diffs if p[3] <= max(exact[3], 1e-15)]
            fastest = min(diffs, key=lambda p: p[4])
            text += [
                "",
                f"Exact vs the best difference scheme: q̇ error {exact[2]:.1e} vs "
                f"{min(p[2] for p in diffs):.1e}, q̈ error {exact[3]:.1e} vs "
                f"{min(p[3] for p in diffs):.1e}; kinematics time {exact[4] * 1e3:.3g} ms vs "
                f"{fastest[4] * 1e3:.3g} ms (fastest difference scheme). "
                f"Difference schemes at least as fast as the exact method: "
                f"{len(slower)} of {len(diffs)} in the kinematics stage, "
                f"{sum(p[5] <= exact[5] for p in diffs)} of {len(diffs)} in ks.analyze; "
                f"at least as accurate: {len(better_v)} (q̇), {len(better_a)} (q̈).",
            ]
            verdicts.append((name, exact, slower))
        blocks[f"derivatives-{name}"] = "\n".join(text)
    # where the time goes: the exact solves against the positions the differences add
    tab = Table(
        [
            "mechanism",
            "positions",
            "exact: all [ms]",
            "positions at the n points [ms]",
            "Φ_q and its block inverses [ms]",
            "ν, γ and the two solves [ms]",
            "differences: all (forward, h=1e-3) [ms]",
            "positions at the 2n neighbours [ms]",
        ],
        timing=set(BREAKDOWN) | {"faster"},
    )
    tab.header.append("faster")
    faster = []
    for name, _ in CASES:
        for n in (360, N_LARGE):
            system, sched, t, _ = setup(name, n)
            times = breakdown(
                system, sched, t, timing, repeat=3 if n == 360 else 1, rounds=3 if n == 360 else 2
            )
            verdict = None if not timing else "exact" if times[0] < times[4] else "differences"
            tab.add(name, f"{n:,}", *(ms(x) for x in times), verdict or ac.PLACEHOLDER)
            if timing:
                faster.append((name, n, verdict, times))
    text = [tab.markdown()]
    if timing:
        text += [
            "",
            "The kinematics stage is faster by differences where solving the positions "
            "a second time (at 2n neighbours) costs less than assembling Φ_q, inverting "
            "its diagonal blocks and the two solves: "
            + "; ".join(
                f"{name} at {n:,} positions: positions at the 2n neighbours "
                f"{tm[5] * 1e3:.3g} ms against Φ_q + solves {(tm[2] + tm[3]) * 1e3:.3g} ms "
                f"→ {v} faster"
                for name, n, v, tm in faster
            )
            + ".",
        ]
    blocks["derivatives-large"] = "\n".join(text)

    def plot():
        import matplotlib.pyplot as plt

        floor = 1e-17  # an exact reference (error 0) is drawn here
        fig, axes = plt.subplots(2, len(CASES), figsize=(4.4 * len(CASES), 7.5), squeeze=False)
        for c, (name, ref_label) in enumerate(CASES):
            pts = points[name]
            ex = pts[0]
            ax = axes[0, c]
            for scheme, color in (("forward", "C0"), ("central", "C1")):
                sel = [p for p in pts if p[0] == scheme]
                hs = [p[1] for p in sel]
                ax.loglog(
                    hs, [max(p[2], floor) for p in sel], "o-", color=color, label=f"{scheme}: q̇"
                )
                ax.loglog(
                    hs, [max(p[3], floor) for p in sel], "s--", color=color, label=f"{scheme}: q̈"
                )
            ax.axhline(
                max(ex[2], ex[3], floor),
                color="k",
                ls=":",
                label="exact (Jacobian)"
                + ("" if max(ex[2], ex[3]) > 0 else ": error 0, drawn at 1e-17"),
            )
            ax.set_title(f"{name}\nerror against step (reference: {ref_label})", fontsize=9)
            ax.set_xlabel("driver step h [rad]")
            ax.set_ylabel("relative error")
            ax.grid(True, which="both", alpha=0.3)
            ax.legend(fontsize=6)
            ax = axes[1, c]
            for scheme, color in (("forward", "C0"), ("central", "C1")):
                sel = [p for p in pts if p[0] == scheme]
                ax.semilogy(
                    [p[4] * 1e3 for p in sel],
                    [max(p[3], floor) for p in sel],
                    "s",
                    color=color,
                    label=f"{scheme}: q̈",
                )
                ax.semilogy(
                    [p[4] * 1e3 for p in sel],
                    [max(p[2], floor) for p in sel],
                    "o",
                    color=color,
                    mfc="none",
                    label=f"{scheme}: q̇",
                )
                for p in sel:
                    if p[1] in (1e-1, 1e-4, 1e-7):
                        ax.annotate(
                            f"h={p[1]:.0e}",
                            (p[4] * 1e3, max(p[3], floor)),
                            fontsize=6,
                            xytext=(4, -2),
                            textcoords="offset points",
                            color=color,
                        )
            ax.semilogy(
                [ex[4] * 1e3], [max(ex[2], ex[3], floor)], "k*", ms=12, label="exact (Jacobian)"
            )
            ax.set_title(f"{name}: error against wall time (q̈ filled, q̇ open)", fontsize=9)
            ax.set_xlabel("kinematics stage, 360 positions [ms]")
            ax.set_ylabel("relative error")
            ax.grid(True, which="both", alpha=0.3)
            ax.legend(fontsize=6)
        return ac.save_figure(fig, "accuracy_derivatives.png")

    return blocks, (plot if timing else None)


if __name__ == "__main__":
    ac.main(build)
