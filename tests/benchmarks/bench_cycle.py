"""CPU time of the cycle's stage (:func:`~kinetostatics.dynamics.stages.cycle_stage`, the
means, the flywheel and the drive of ``run``) on shipped mechanisms at 360 positions,
this tree against another (issue 40), candidates interleaved round by round.

    python tests/benchmarks/bench_cycle.py [--rounds N] [--baseline TREE] [NAME ...]

Each round runs one fresh process per tree (its ``src`` on PYTHONPATH) that loads the
mechanism, analyses it, runs the stage once to warm it, then times ``cycle_stage`` on the
same result (``time.process_time``, the median of several calls).  Printed: each tree's
median over the rounds and the median of the per-round ratios (baseline / this tree).
NAME: mechanism files under ``mechanisms/`` (default: the slotting machine, the
slider-crank, the jaw crusher and the cam roller).
"""

from __future__ import annotations

import argparse
import os
import statistics
import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
DEFAULT = ("slotting_machine", "slider_crank", "jaw_crusher", "cam_roller")

WORKER = """
import statistics, sys, time, warnings
warnings.simplefilter("ignore")
import kinetostatics as ks
from kinetostatics.dynamics.stages import cycle_stage
r = ks.analyze(ks.load(sys.argv[1]))
cycle_stage(r)
out = []
for _ in range(int(sys.argv[2])):
    t = time.process_time()
    cycle_stage(r)
    out.append(time.process_time() - t)
print(statistics.median(out))
"""


def _one(tree: Path, path: Path, calls: int) -> float:
    env = dict(os.environ, PYTHONPATH=str(tree / "src"))
    out = subprocess.run(
        [sys.executable, "-c", WORKER, str(path), str(calls)],
        env=env,
        capture_output=True,
        text=True,
        check=True,
        cwd=ROOT,
    )
    return float(out.stdout.split()[-1])


def main(argv: list[str] | None = None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("names", nargs="*", default=list(DEFAULT))
    parser.add_argument("--rounds", type=int, default=5)
    parser.add_argument("--calls", type=int, default=5)
    parser.add_argument("--baseline", type=Path, help="another source tree")
    args = parser.parse_args(argv)
    trees = [ROOT] + ([args.baseline] if args.baseline else [])
    head = f"{'mechanism':<18} {'this tree ms':>13}"
    print(head + (" baseline ms   ratio" if args.baseline else ""))
    for name in args.names:
        path = ROOT / "mechanisms" / f"{name}.yaml"
        times: dict[Path, list[float]] = {t: [] for t in trees}
        for i in range(args.rounds):
            for tree in trees if i % 2 == 0 else trees[::-1]:
                times[tree].append(_one(tree, path, args.calls))
        row = f"{name:<18} {1e3 * statistics.median(times[ROOT]):>13.1f}"
        if args.baseline:
            ratio = statistics.median(b / a for a, b in zip(times[ROOT], times[args.baseline]))
            row += f" {1e3 * statistics.median(times[args.baseline]):>11.1f} {ratio:>7.2f}×"
        print(row, flush=True)


if __name__ == "__main__":
    main()
