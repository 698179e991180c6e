"""A batch of slotting-machine variants × 72 positions with friction through
``run_batch`` (the default executor: one process per core), against a plain
loop of single analyses (``ks.analyze`` + ``summary_row``, one process) over a
sub-sample, both measured in the same run.

10,000 variants must complete on a 2-core machine: at least 500 variants/s, and
the speed target is 1,000 variants/s on a quiet 2-core machine.  The file's
flywheel is not sized (``--flywheel`` sizes it; that path analyses one variant at
a time).  The variants are a seeded random sample over K, H, L_O2O3, BC_ratio,
the weights and the cutting force, in ranges that assemble.

    python tests/benchmarks/bench_batch.py              # 10,000 variants, loop of 200
    python tests/benchmarks/bench_batch.py --n 500 --loop 50
"""

from __future__ import annotations

import argparse
import math
import os
import tempfile
import time

from _common import ROOT

import kinetostatics as ks
from kinetostatics import batch
from kinetostatics.batch import sweeps
from kinetostatics.batch.variants import Template, failure_row, summary_row

SWEEP = """
random:
  n: {n}
  seed: 2026
  params:
    K: {{uniform: [1.6, 2.4]}}
    H: {{uniform: [80, 120]}}
    L_O2O3: {{uniform: [130, 170]}}
    BC_ratio: {{uniform: [0.8, 1.2]}}
    G3: {{uniform: [140, 180]}}
    G5: {{uniform: [280, 360]}}
    Q: {{uniform: [800, 1200]}}
"""


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--n", type=int, default=10_000, help="variants in the batch")
    ap.add_argument("--loop", type=int, default=200, help="variants in the plain loop")
    ap.add_argument("--positions", type=int, default=72)
    ap.add_argument("--workers", type=int, default=None, help="default: the number of cores")
    ap.add_argument("--chunk", type=int, default=None, help="default: batch.auto_chunk")
    ap.add_argument("--out", default=None, help="output folder (default: a temporary one)")
    ap.add_argument(
        "--flywheel",
        action="store_true",
        help="also size the file's flywheel (not vectorised: one by one)",
    )
    args = ap.parse_args()
    path = ROOT / "mechanisms" / "slotting_machine.yaml"
    variants = sweeps.expand(sweeps.load_sweep(SWEEP.format(n=args.n), "bench"))
    tasks = [batch.Task(vid, 0, ov) for vid, ov in variants]
    out = args.out or tempfile.mkdtemp(prefix="bench_batch_")

    t0 = time.perf_counter()
    s = batch.run_batch(
        str(path),
        tasks,
        out,
        positions=args.positions,
        workers=args.workers,
        chunk=args.chunk,
        flywheel=args.flywheel,
        overwrite=True,
    )
    t_batch = time.perf_counter() - t0

    tpl = Template.load(path)
    loop_rows = []
    t0 = time.perf_counter()
    for _, ov in variants[: args.loop]:
        try:
            result = ks.analyze(tpl.model(ov, positions=args.positions))
            loop_rows.append(summary_row(result, flywheel=args.flywheel))
        except (ks.KinetostaticsError, ValueError, ArithmeticError) as exc:
            loop_rows.append(failure_row(exc))
    t_loop = time.perf_counter() - t0

    rows = batch.read_summary(s.summary_csv)[1]
    # each value against the loop's: relative to itself (worst named), and relative to the
    # largest |value| of its column (a value near zero, such as a least efficiency of 1e-4,
    # carries the round-off of the efforts it is a quotient of)
    worst, where, scale = 0.0, "", {}
    for ref in loop_rows:
        for k, v in ref.items():
            if isinstance(v, float) and math.isfinite(v):
                scale[k] = max(scale.get(k, 0.0), abs(v))
    worst_col = 0.0
    for row, ref, (vid, _) in zip(rows, loop_rows, variants):
        for k, v in ref.items():
            if isinstance(v, float) and math.isfinite(v) and v != 0:
                d = abs(float(row[k]) - v)
                if d / abs(v) > worst:
                    worst, where = d / abs(v), f"{k} of variant {vid}, {v:.3g}"
                worst_col = max(worst_col, d / scale[k])
    rate_batch, rate_loop = args.n / t_batch, args.loop / t_loop
    print(
        f"slotting machine, {args.positions} positions, friction (both solutions), "
        f"flywheel {'sized' if args.flywheel else 'not sized'}, {os.cpu_count()} cores"
    )
    print(
        f"batch: {args.n} variants in {t_batch:.1f} s = {rate_batch:.1f} variants/s "
        f"({s.workers} workers, chunks of {s.chunk}; {s.failed} failed, {s.errors} errors; "
        f"{s.alone} analysed one by one)"
        f" -> {s.summary_csv}"
    )
    print(
        f"plain loop of single analyses: {args.loop} variants in {t_loop:.1f} s = "
        f"{rate_loop:.1f} variants/s (one process)"
    )
    print(
        f"speed-up over the loop: {rate_batch / rate_loop:.2f}x "
        f"({rate_batch / rate_loop / s.workers:.2f}x per worker); target >= 1,000 variants/s "
        f"on a quiet 2-core machine: {'met' if rate_batch >= 1000 else 'not met'} (>= 500: "
        f"{'met' if rate_batch >= 500 else 'not met'})"
    )
    print(
        f"batch rows vs the loop's, max relative difference: {worst:.2e}"
        + (f" ({where})" if where else "")
        + f"; relative to each column's largest value: {worst_col:.2e}"
    )


if __name__ == "__main__":
    main()
