"""When a system's kinematic plan pays for itself (``plan.PLAN_AFTER``): what generating and
compiling it costs, and what an analysis saves with it, per reference machine.

For each machine a fresh system is analysed (friction as the file) until its plan is
made; the cost is that analysis's CPU time less the one before it.  Then each analysis
of 3, 360, 3,000 and 36,000 positions is timed with the plan and on the general path
(``plan.ENABLED`` off), alternated, medians of ``--rounds`` rounds of five calls each;
the saving of a call is read as ``a + b·rows`` (``a`` at 3 rows, ``b`` the slope from 360
to 36,000) and the break-even printed as the number of short calls (``cost / a``) and of
rows (``cost / b``) it takes.  A system whose groups are larger than
``plan.PLANNED_BLOCKS`` (a triad) is measured with that limit lifted: the row says it is
not planned, and why (its savings).

    PYTHONPATH=src python tests/benchmarks/bench_plan_after.py [--rounds 7] [FILE ...]
"""

from __future__ import annotations

import argparse
import statistics
import time

import numpy as np
from _common import ROOT

import kinetostatics as ks
from kinetostatics.kinematics import plan
from kinetostatics.structure.system import build_system

MACHINES = ("slider_crank", "slotting_machine", "stephenson_sixbar", "shaper")
ROWS = (3, 360, 3000, 36_000)


def _cpu(fn) -> float:
    t0 = time.process_time()
    fn()
    return time.process_time() - t0


def generation_cost(model) -> float:
    """CPU seconds of the analysis that makes the plan, less the one before it."""
    system, at = build_system(model), np.radians([10.0, 20.0, 30.0])
    before = 0.0
    for _ in range(200):  # PLAN_AFTER's 20 short analyses, with room
        took = _cpu(lambda: ks.analyze(system, positions=at))
        if "kinematic plan" in system.memo:
            return took - before
        before = took
    raise RuntimeError("no plan made")


def savings(model, rounds: int) -> dict[int, float]:
    """Per rows: the general path's CPU seconds less the plan's, for one analysis."""
    out = {}
    for n in ROWS:
        at = np.linspace(0.1, 0.1 + 2 * np.pi * (n > 3), n, endpoint=False)
        systems = {True: build_system(model), False: build_system(model)}
        times: dict[bool, list[float]] = {True: [], False: []}
        after = plan.PLAN_AFTER
        try:
            plan.PLAN_AFTER = (0, 0)
            for _ in range(rounds + 1):  # the first round warms both
                for enabled, system in systems.items():
                    plan.ENABLED = enabled
                    five = lambda s=system, x=at: [ks.analyze(s, positions=x) for _ in range(5)]  # noqa: E731
                    times[enabled].append(_cpu(five) / 5)
        finally:
            plan.PLAN_AFTER, plan.ENABLED = after, True
        out[n] = statistics.median(times[False][1:]) - statistics.median(times[True][1:])
    return out


def _lifted(fn):
    """``fn()`` with every system planned, whatever its groups' size."""
    kept = plan.PLANNED_BLOCKS
    plan.PLANNED_BLOCKS = 10**9
    try:
        return fn()
    finally:
        plan.PLANNED_BLOCKS = kept


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--rounds", type=int, default=7)
    ap.add_argument("files", nargs="*")
    args = ap.parse_args()
    files = args.files or [ROOT / "mechanisms" / f"{m}.yaml" for m in MACHINES]
    print(f"PLAN_AFTER = {plan.PLAN_AFTER} (short calls, rows)")
    print("| mechanism | planned | cost [ms] | saving at 3 / 360 / 3,000 / 36,000 rows [ms] "
          "| a [ms] | b [µs/row] | break-even: short calls | rows |")  # fmt: skip
    print("|---|---|---|---|---|---|---|---|")
    for f in files:
        model = ks.load(f)
        system = build_system(model)
        planned = plan.covers(system, np.zeros((1, system.n_q)))
        cost = statistics.median(_lifted(lambda m=model: generation_cost(m)) for _ in range(3))
        s = _lifted(lambda m=model: savings(m, args.rounds))
        a, b = s[ROWS[0]], (s[ROWS[-1]] - s[ROWS[1]]) / (ROWS[-1] - ROWS[1])
        print(
            f"| {model.name} | {'yes' if planned else 'no'} | {cost * 1e3:.1f} | "
            + " / ".join(f"{s[n] * 1e3:.2f}" for n in ROWS)
            + f" | {a * 1e3:.2f} | {b * 1e6:.2f} | {cost / a:.0f} | {cost / b:,.0f} |"
        )


if __name__ == "__main__":
    main()
