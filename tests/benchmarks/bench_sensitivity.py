"""The cost of a Monte Carlo sample against that of a batch variant of the same file, measured
in one run (docs/sensitivity.md, *Cost*; issue 41: at most 1.5×).

The slotting machine at 72 positions with both friction solutions, the flywheel not sized:
``monte_carlo`` of N designs with tolerances on K, H, L_O2O3, BC_ratio, G3, G5 and Q (its
nominal analysis, the draw, the batch, the statistics), and ``run_batch`` of N variants drawn
uniformly within the same tolerances (the default executor, a process per core, for both).
Each is run ``--repeat`` times, alternated, and the least time of each is compared.

    python tests/benchmarks/bench_sensitivity.py              # 2,000 designs, 2 rounds
    python tests/benchmarks/bench_sensitivity.py --n 500 --write   # the line into the page
"""

from __future__ import annotations

import argparse
import os
import re
import tempfile
import time

import numpy as np
from _common import ROOT

from kinetostatics import batch
from kinetostatics.batch.runner import BatchOptions
from kinetostatics.batch.sensitivity import parse_tolerances
from kinetostatics.batch.tolerance import monte_carlo
from kinetostatics.batch.variants import Template

PATH = ROOT / "mechanisms" / "slotting_machine.yaml"
PAGE = ROOT / "docs" / "sensitivity.md"
VARY = ["K=±1%", "H=±0.5", "L_O2O3=±0.5", "BC_ratio=±1%", "G3=±2%", "G5=±2%", "Q=±5%"]


def _batch(n: int, positions: int, out: str) -> float:
    tols = parse_tolerances(VARY, Template.load(PATH).parameters)
    rng = np.random.default_rng(1)
    tasks = [
        batch.Task(f"{k + 1}", 0, {t.name: t.nominal + t.half * rng.uniform(-1, 1) for t in tols})
        for k in range(n)
    ]
    t0 = time.perf_counter()
    batch.run_batch(
        str(PATH), tasks, out, positions=positions, flywheel=False, overwrite=True, progress=False
    )
    return time.perf_counter() - t0


def _monte_carlo(n: int, positions: int, out: str) -> tuple[float, object]:
    opts = BatchOptions(positions=positions, overwrite=True, progress=False)
    t0 = time.perf_counter()
    mc = monte_carlo(PATH, VARY, samples=n, dist="uniform", seed=1, options=opts, out=out)
    return time.perf_counter() - t0, mc


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--n", type=int, default=2000, help="designs in each")
    ap.add_argument("--positions", type=int, default=72)
    ap.add_argument("--repeat", type=int, default=2, help="rounds of each, alternated")
    ap.add_argument("--write", action="store_true", help="write the result into the page")
    args = ap.parse_args()
    tb, tm, mc = [], [], None
    load = os.getloadavg()[0]
    with tempfile.TemporaryDirectory(prefix="bench_sensitivity_") as tmp:
        for _ in range(args.repeat):
            tb.append(_batch(args.n, args.positions, f"{tmp}/batch"))
            t, mc = _monte_carlo(args.n, args.positions, f"{tmp}/mc")
            tm.append(t)
    b, m = min(tb), min(tm)
    lines = [
        f"slotting machine, {args.positions} positions, friction (both solutions), flywheel not "
        f"sized, {len(VARY)} toleranced parameters, {args.n} designs, best of {args.repeat} "
        f"(load average {load:.1f} at the start, {os.cpu_count()} cores)",
        f"batch: {args.n} variants in {b:.2f} s = {1e3 * b / args.n:.3f} ms a variant",
        f"Monte Carlo: {args.n} samples in {m:.2f} s = {1e3 * m / args.n:.3f} ms a sample "
        f"({mc.failed} failed, {mc.alone} analysed one by one)",
        f"ratio (Monte Carlo sample / batch variant): {m / b:.3f} (target <= 1.5: "
        f"{'met' if m / b <= 1.5 else 'NOT met'})",
    ]
    print("\n".join(lines))
    if args.write:
        text = PAGE.read_text(encoding="utf-8")
        block = "<!-- bench:begin -->\n```text\n" + "\n".join(lines) + "\n```\n<!-- bench:end -->"
        new, n = re.subn(r"<!-- bench:begin -->.*?<!-- bench:end -->", block, text, flags=re.S)
        if n != 1:
            raise SystemExit(f"{PAGE}: no <!-- bench:begin --> … <!-- bench:end --> block")
        PAGE.write_text(new, encoding="utf-8")
        print(f"wrote {PAGE}")


if __name__ == "__main__":
    main()
