"""When a system's kinematic plan pays for itself (``plan.PLAN_AFTER``): what generating and
compiling it costs, and what an analysis saves with it, per reference machine.

For each machine a fresh system is analysed (friction as the file) until its plan is
made; the cost is that analysis's CPU time less the one before it.  Then each analysis
of 3, 360 and 3,000 positions is timed with the plan and on the general path
(``plan.ENABLED`` off), alternated, medians of ``--rounds`` rounds of five calls each;
the saving of a call is fitted as ``a + b·rows`` and the break-even printed as the number
of short calls (``cost / a``) and of rows (``cost / b``) it takes.

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
ROWS = (3, 360, 3000)


def _cpu(fn) -> float:
    t0 = time.process_time()
    fn()
    return time.process_time() - t0


def generation_cost(model) -> float:
    """CPU seconds of the analysis that makes the plan, less the one before it."""
    system, at = build_system(model), np.radians([10.0, 20.0, 30.0])
    before = 0.0
    for _ in range(10_000):
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


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--rounds", type=int, default=7)
    ap.add_argument("files", nargs="*")
    args = ap.parse_args()
    files = args.files or [ROOT / "mechanisms" / f"{m}.yaml" for m in MACHINES]
    print(f"PLAN_AFTER = {plan.PLAN_AFTER} (short calls, rows)")
    print("| mechanism | cost [ms] | saving at 3 / 360 / 3,000 rows [ms] | a [ms] | b [µs/row] "
          "| break-even: short calls | rows |")  # fmt: skip
    print("|---|---|---|---|---|---|---|")
    for f in files:
        model = ks.load(f)
        cost = statistics.median(generation_cost(model) for _ in range(3))
        s = savings(model, args.rounds)
        b, a = np.polyfit(np.array(ROWS, float), [s[n] for n in ROWS], 1)
        print(
            f"| {model.name} | {cost * 1e3:.1f} | "
            + " / ".join(f"{s[n] * 1e3:.2f}" for n in ROWS)
            + f" | {a * 1e3:.2f} | {b * 1e6:.2f} | {cost / a:.0f} | {cost / b:,.0f} |"
        )


if __name__ == "__main__":
    main()
