"""The cost of each stage of an analysis, per position, at 360 and 36,000 positions.

The stages of ``ks.analyze`` (src/kinetostatics/analysis.py) are called one
by one on one system, in the order of the pipeline, each timed with
``best_of`` (tests/benchmarks/_common.py) on the outputs of the previous
stages.  The model is the shipped file with ``analysis.positions`` set to n
(a full cycle).  *once* rows do not depend on n; the per-position column
divides every row by n.  The last rows time the whole ``ks.analyze`` and the
``run`` outputs (results.csv, summary.json) for comparison with the sum.

    python tests/benchmarks/accuracy_stages.py [--quick] [--update]
"""

from __future__ import annotations

import tempfile
from pathlib import Path

import accuracy_common as ac
import numpy as np
from accuracy_common import Table

import kinetostatics as ks
from kinetostatics.analysis.columns import build_columns
from kinetostatics.analysis.results import Result
from kinetostatics.base.blocks import BlockFactor
from kinetostatics.kinematics.derivatives import derivatives
from kinetostatics.kinematics.motion import Motion
from kinetostatics.kinematics.newton import condition_number
from kinetostatics.kinematics.positions import solve_positions
from kinetostatics.kinematics.schedule import sample_times, schedule
from kinetostatics.kinematics.start import assemble_start
from kinetostatics.kinetics import friction as fr
from kinetostatics.kinetics.conditions import load_events
from kinetostatics.kinetics.forces import (
    external_forces,
    gravity_forces,
    inertia_forces,
    mass_vector,
)
from kinetostatics.kinetics.inverse import (
    Equilibrium,
    FrictionSolutions,
    Kinetics,
    Loads,
    Power,
)
from kinetostatics.kinetics.reactions import effort_joints, ground_reaction
from kinetostatics.structure.system import coordinate_gradient, gamma, jacobian_blocks, nu

NAMES = ("slider_crank", "slotting_machine")
SIZES = (360, 36_000)


def model_text(name: str, n: int) -> str:
    text = (ac.ROOT / "mechanisms" / f"{name}.yaml").read_text()
    return text.replace("positions: 360}", f"positions: {n}}}")


def power_terms(system, q, qd, qdd, x0, q_grav, q_ext, cons, fs):
    """The power block of ``inverse.kinetics``, as there."""
    eff = effort_joints(system)
    rel = np.stack(
        [np.einsum("...n,...n->...", coordinate_gradient(system, q, k), qd) for k in eff], -1
    )
    n_j = system.n_joint_rows
    p = {
        "input": np.sum(x0[..., n_j:] * rel, axis=-1),
        "kinetic": np.einsum("...n,n,...n->...", qd, mass_vector(system), qdd),
        "potential": -np.einsum("...n,...n->...", qd, q_grav),
        "external": -np.einsum("...n,...n->...", qd, q_ext),
    }
    p["residual"] = p["input"] - p["kinetic"] - p["potential"] - p["external"]
    if cons is not None:
        loss = np.sum(np.abs(cons.e * fs.speed), axis=-1)
        p["friction"] = loss
        p["input_friction"] = np.sum(cons.x[..., n_j:] * rel, axis=-1)
        p["residual_friction"] = (
            p["input_friction"] - p["kinetic"] - p["potential"] - p["external"] - loss
        )
    return p


def stage_times(name: str, n: int, timing: bool):
    """[(stage, seconds or None, once)], checking the pieces against ks.analyze."""
    text = model_text(name, n)
    rep = None if n <= 360 else 3
    T = (lambda f: ac.best_of(f, repeat=rep)) if timing else (lambda f: None)
    rows = []
    rows.append(("read YAML (ks.loads)", T(lambda: ks.loads(text, file=f"{name}.yaml")), True))
    model = ks.loads(text, file=f"{name}.yaml")
    rows.append(("structure and plan (ks.build_system)", T(lambda: ks.build_system(model)), True))
    system = ks.build_system(model)
    sched = schedule(system)
    rows.append(("start pose from the sketch", T(lambda: assemble_start(system, 0.0, sched)), True))
    rows.append(
        ("schedule and times", T(lambda: sample_times(system, schedule(system), None)), False)
    )
    t, full = sample_times(system, sched, None)
    sol = solve_positions(system, t, sched)
    rows.append(("positions", T(lambda: solve_positions(system, t, sched)), False))
    q = sol.q
    psi, psi_d, psi_dd = sched(t)
    blocks = [(p.rows, p.cols) for p in system.plans]

    def velocities():  # as kinematics.derivatives: Φ_q by the system's evaluation plan
        lu = BlockFactor(None, blocks, jacobian_blocks(system, q))
        return lu, lu.solve(nu(system, psi_d))

    rows.append(("velocities (Φ_q, block inverses, solve ν)", T(velocities), False))
    lu, qd = velocities()
    rows.append(
        ("accelerations (γ, solve)", T(lambda: lu.solve(gamma(system, q, qd, psi_dd))), False)
    )
    qdd = lu.solve(gamma(system, q, qd, psi_dd))
    assert all(
        np.array_equal(a, b) for a, b in zip((qd, qdd), derivatives(system, q, psi_d, psi_dd))
    )
    motion = Motion(t, psi, q, qd, qdd, psi_d, psi_dd, lu)
    ev = lambda: load_events(system, sched, motion, full)  # noqa: E731
    rows.append(("load switching events, travel extremes", T(ev), False))
    extremes, _, _ = ev()

    def loads():
        g = gravity_forces(system, q.shape[:-1])
        i = inertia_forces(system, qdd)
        x = external_forces(system, q, qd, psi[..., 0], extremes, sched.reference)
        return g, i, x

    rows.append(("loads (gravity, inertia, external)", T(loads), False))
    q_grav, q_inert, q_ext = loads()
    q_load = q_grav + q_inert + q_ext
    rows.append(("reactions and driver efforts", T(lambda: lu.solve_transposed(-q_load)), False))
    x0 = lu.solve_transposed(-q_load)

    def approx():
        fs = fr.setup(system, q, qd, sched.reference)
        return fs, fr.approximate(system, fs, lu.solve_transposed, q_load, x0)

    rows.append(("friction: approximate (setup, one back substitution)", T(approx), False))
    fs, (xa, ea) = approx()
    # A = Φ_qᵀ by the kinematic factors, as the pipeline passes it
    cons_f = lambda: fr.consistent(system, fs, lu, lu.solve_transposed, q_load, x0)  # noqa: E731
    rows.append(("friction: consistent", T(cons_f), False))
    cons = cons_f()
    rows.append(
        (
            "power balance",
            T(lambda: power_terms(system, q, qd, qdd, x0, q_grav, q_ext, cons, fs)),
            False,
        )
    )
    power = power_terms(system, q, qd, qdd, x0, q_grav, q_ext, cons, fs)

    def conds():
        return {
            p.group: condition_number(system, p, lu.diag[g], lu.inv[g])
            for g, p in enumerate(system.plans)
            if p.group.kind != "driven"
        }

    rows.append(("condition numbers", T(conds), False))
    cond = conds()
    kin = Kinetics(
        Loads(q_grav, q_inert, q_ext),
        Equilibrium(x0, None, lu, np.zeros(len(t), dtype=bool)),
        FrictionSolutions(fs, xa, ea, cons),
        Power(**power),
    )

    def columns():
        shaking = ground_reaction(system, q, x0)
        return build_columns(system, motion, kin, cond=cond, shaking=shaking)

    rows.append(("shaking force, result columns", T(columns), False))
    cols, units = columns()
    result = Result(
        system=system,
        t=t,
        coordinate=psi[..., 0],
        q=q,
        qd=qd,
        qdd=qdd,
        lam=x0,
        columns=cols,
        units=units,
        singular=tuple(sol.singular),
        full_cycle=full,
        extremes=extremes,
    )
    # the pieces reproduce ks.analyze (without event rows)
    ref = ks.analyze(system, events=False)
    assert set(ref.names) == set(cols) and all(
        np.allclose(ref[k], cols[k], rtol=1e-12, atol=1e-12, equal_nan=True) for k in cols
    ), name
    with tempfile.TemporaryDirectory() as tmp:
        rows.append(
            ("write results.csv", T(lambda: result.to_csv(Path(tmp) / "results.csv")), False)
        )
        rows.append(
            ("write summary.json", T(lambda: result.to_json(Path(tmp) / "summary.json")), False)
        )
    rows.append(
        ("— total ks.analyze (events=False)", T(lambda: ks.analyze(system, events=False)), None)
    )
    return rows, len(cols)


def build(timing: bool = True):
    blocks, data = {}, {}
    for name in NAMES:
        per = {
            n: stage_times(name, n if timing else SIZES[0], timing) for n in SIZES
        }  # untimed: labels only
        tab = Table(
            [
                "stage",
                "360: ms",
                "360: µs/position",
                "36,000: ms",
                "36,000: µs/position",
                "36,000: share of the sum",
            ],
            timing={
                "360: ms",
                "360: µs/position",
                "36,000: ms",
                "36,000: µs/position",
                "36,000: share of the sum",
            },
        )
        rows = {n: per[n][0] for n in SIZES}
        total = {
            n: sum(s for _, s, once in rows[n] if once is not None and s is not None) for n in SIZES
        }
        for k, (stage, _, once) in enumerate(rows[SIZES[0]]):
            cells = [stage + (" (once)" if once else "")]
            for n in SIZES:
                s = rows[n][k][1]
                cells += [
                    ac.ms(s),
                    ac.PLACEHOLDER
                    if s is None
                    else (f"{s / n * 1e6:.3g}" if once is False else "—"),
                ]
            s = rows[SIZES[-1]][k][1]
            cells.append(
                ac.PLACEHOLDER
                if s is None or once is None
                else f"{100 * s / total[SIZES[-1]]:.1f} %"
            )
            tab.add(*cells)
        sums = ["sum of the stages"]
        for n in SIZES:
            sums += [
                ac.ms(total[n] if timing else None),
                ac.PLACEHOLDER if not timing else f"{total[n] / n * 1e6:.3g}",
            ]
        tab.add(*sums, "100 %" if timing else ac.PLACEHOLDER)
        links = len(ks.build_system(ks.load(ac.ROOT / "mechanisms" / f"{name}.yaml")).links)
        blocks[f"stages-{name}"] = (
            f"**{name}** ({links} moving links, {per[360][1]} result columns)\n\n" + tab.markdown()
        )
        data[name] = rows

    def plot():
        import matplotlib.pyplot as plt

        fig, axes = plt.subplots(1, len(NAMES), figsize=(14, 5.5), sharex=False)
        for ax, name in zip(np.atleast_1d(axes), NAMES):
            rows = data[name]
            labels = [s for s, _, once in rows[360] if once is False]
            y = np.arange(len(labels))
            for k, n in enumerate(SIZES):
                vals = [
                    s / n * 1e6
                    for s, (_, _, once) in zip([r[1] for r in rows[n]], rows[n])
                    if once is False
                ]
                ax.barh(y + (k - 0.5) * 0.4, vals, height=0.4, label=f"{n:,} positions")
            ax.set_yticks(y, labels, fontsize=7)
            ax.invert_yaxis()
            ax.set_xscale("log")
            ax.set_xlabel("wall time per position [µs] (log scale)")
            ax.set_title(f"{name}: cost of each stage")
            ax.grid(True, axis="x", which="both", alpha=0.3)
            ax.legend(fontsize=7)
        return ac.save_figure(fig, "accuracy_stages.png")

    return blocks, (plot if timing else None)


if __name__ == "__main__":
    ac.main(build)
