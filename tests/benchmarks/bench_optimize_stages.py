"""Where a design's time goes (issue 40): the CPU time of ``bench_optimize.py``'s
``optimize`` with friction (360 positions, ``--generations`` generations of 24 designs)
and of its vectorised batch (``--variants`` variants at 72 positions) split by stage.

Each stage is a function of the package, timed by a wrapper around it (``time.process_time``
before and after, summed over its calls) in this one process; a stage that calls another
includes it (the friction solutions include their setup, the approximate and the
consistent solution; the approximate one includes the n_f solves both share).  A share
is the median over ``--rounds`` rounds of the stage's time over the whole call's.  The
wrappers cost a little (~2 % of the call): the shares, not the rates, are the point.

    PYTHONPATH=src python tests/benchmarks/bench_optimize_stages.py [--rounds 5]
        [--generations 5] [--variants 125] [--write]

``--write`` rewrites the table of docs/accuracy.md between ``<!-- throughput-stages:begin
-->`` and ``<!-- throughput-stages:end -->``.
"""

from __future__ import annotations

import argparse
import importlib
import statistics
import time
import warnings
from datetime import datetime, timezone

import bench_optimize as bo
from _common import machine, publish

BEGIN, END = "<!-- throughput-stages:begin -->", "<!-- throughput-stages:end -->"
# (module, function, what it is), in the order of a design's analysis; the stages are
# patched where the callers look them up (the module that imports them)
STAGES = [
    ("batch.variants", "build", "building each design's model from the file's tree"),
    ("batch.variants", "stack", "stacking the models along the variant axis"),
    ("analysis.vectorised", "_start", "the start poses"),
    ("analysis.vectorised", "closed_form_path", "the paths (the dyads' closed forms)"),
    ("analysis.vectorised", "derivatives_at", "the velocities and accelerations"),
    ("analysis.vectorised", "travel_extremes_stacked", "the outputs' travel extremes"),
    ("kinetics.inverse", "loads", "the loads"),
    ("kinetics.inverse", "equilibrium", "the frictionless equilibrium"),
    ("kinetics.inverse", "friction_solutions", "both friction solutions, of it:"),
    ("kinetics.friction", "setup", "· their setup (the coordinate gradients, the signs)"),
    ("kinetics.friction", "_per_effort", "· the n_f solves A⁻¹g_k both share"),
    ("kinetics.friction", "consistent", "· the consistent solution (its fixed point)"),
    ("analysis.vectorised", "analyze_stacked", "the stacked analysis (start poses to friction)"),
    ("batch.variants", "summary_row", "the rows (the quantities named)"),
    ("analysis.pipeline", "analyze", "the best design's whole row (analysed alone)"),
]


def patch(acc: dict) -> None:
    """Wrap every stage of :data:`STAGES` so that its CPU time adds up in ``acc``."""
    for mod, name, _ in STAGES:
        m = importlib.import_module(f"kinetostatics.{mod}")
        f = getattr(m, name)

        def timed(*a, _f=f, _key=(mod, name), **k):
            t0 = time.process_time()
            try:
                return _f(*a, **k)
            finally:
                acc[_key] = acc.get(_key, 0.0) + time.process_time() - t0

        setattr(m, name, timed)


def shares(run, rounds: int, acc: dict) -> tuple[float, dict]:
    """(the call's median CPU time, each stage's median share of it)."""
    run()  # warm
    totals, parts = [], []
    for _ in range(rounds):
        acc.clear()
        t0 = time.process_time()
        run()
        totals.append(time.process_time() - t0)
        parts.append(dict(acc))
    return statistics.median(totals), {
        (m, n): statistics.median(p.get((m, n), 0.0) / t for p, t in zip(parts, totals))
        for m, n, _ in STAGES
    }


def per_position(sizes=(24, 96), seconds: float = 1.0) -> list[str]:
    """Lines of a table: a stacked analysis's CPU time per design and position at 360
    positions, without and with friction, for populations of ``sizes`` random designs in
    the optimize's bounds; and the consistent fixed point's iterations at the positions
    of the first population (how many positions stop at each count)."""
    import numpy as np

    from kinetostatics.analysis import vectorised
    from kinetostatics.batch.variants import Template
    from kinetostatics.kinetics import friction

    tpl = Template.load(bo.PATH)
    rng = np.random.default_rng(0)
    lines = ["| designs | without friction [µs] | with both friction solutions [µs] |"]
    lines.append("|---|---|---|")
    iterations = []
    real = friction.consistent

    def counted(*a, **k):
        out = real(*a, **k)
        iterations.append(out.iterations.ravel())
        return out

    for size in sizes:
        models = [
            tpl.model({k: rng.uniform(*b) for k, b in bo.VARY.items()}, positions=360)
            for _ in range(size)
        ]
        cells = []
        for with_friction in (False, True):
            vectorised.analyze_stacked(models, friction=with_friction)  # warm
            n, t0 = 0, time.process_time()
            while n < 2 or time.process_time() - t0 < seconds:
                vectorised.analyze_stacked(models, friction=with_friction)
                n += 1
            cells.append((time.process_time() - t0) / n / size / 360 * 1e6)
        lines.append(f"| {size} | {cells[0]:.2f} | {cells[1]:.2f} |")
        if size == sizes[0]:
            friction.consistent = counted
            try:
                vectorised.analyze_stacked(models, friction=True)
            finally:
                friction.consistent = real
    counts = np.bincount(np.concatenate(iterations))
    share = ", ".join(f"{k}: {c / counts.sum() * 100:.0f} %" for k, c in enumerate(counts) if c)
    return lines + [
        "",
        f"The fixed point's iterations at the {sizes[0]} designs' positions: {share}.",
    ]


def main(argv=None) -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--rounds", type=int, default=5)
    ap.add_argument("--generations", type=int, default=5)
    ap.add_argument("--variants", type=int, default=125)
    ap.add_argument("--write", action="store_true")
    args = ap.parse_args(argv)
    warnings.simplefilter("ignore")
    acc: dict = {}
    patch(acc)
    calls = {
        "optimize": bo.search_ks(True, args.generations, "motor.torque_friction_rms"),
        "batch": bo.batch_ks(bo.sweep(args.variants)),
    }
    when = datetime.now(timezone.utc).strftime("%Y-%m-%d %H:%M UTC")
    got = {name: shares(run, args.rounds, acc) for name, run in calls.items()}
    head = "| stage | function | " + " | ".join(
        f"{n}: share of {t * 1e3:.0f} ms" for n, (t, _) in got.items()
    )
    lines = [head + " |", "|---|---|" + "---|" * len(got)]
    for m, n, what in STAGES:
        line = f"| {what} | `{m}.{n}` |"
        line += "".join(f" {s[(m, n)] * 100:.1f} % |" for _, s in got.values())
        lines.append(line)
    body = (
        f"**Conditions:** {machine()}; CPU time of this process; {when}; {args.rounds} "
        f"rounds; `optimize` with friction, {args.generations} generations of "
        f"{bo.POPSIZE} × {len(bo.VARY)} designs at 360 positions; the batch of "
        f"{args.variants} variants at 72 positions with both friction solutions.\n\n"
        + "\n".join(lines)
        + "\n\nA stacked analysis per design and position (`analysis.vectorised.analyze_stacked`"
        + ", 360 positions, CPU time):\n\n"
        + "\n".join(per_position())
    )
    publish(BEGIN, END, body, args.write)


if __name__ == "__main__":
    main()
