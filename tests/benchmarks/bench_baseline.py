"""Analyses timed in this tree and in another, in whole processes alternated round by round.

A change to the engine is measured against the tree before it: each round starts one
process per tree (each tree first in every other round), which loads the shipped files
with ``analysis.positions`` set to each size, analyses each a few times untimed, then
times the analyses (CPU time of the process, ``time.process_time``; the median of
``--repeat`` calls, every column read, as ``bench_speed.py`` reads them) and prints
them; one more case is optimize's generation: a stacked analysis of 24 designs of the
slotting machine (``BC_ratio`` 0.8–1.2, ``L_O2O3`` 130–170 mm, the same 24 in both
trees) at 360 positions with both friction solutions.  The table gives each case's
median over the rounds in each tree and their ratio (this tree / the other).  Machines
drift over minutes (a long run's page faults, other loads): the trees share every round.

    PYTHONPATH=src python tests/benchmarks/bench_baseline.py --baseline TREE [--rounds 5]
        [--positions 360 36000] [--level full] [--numba]

``TREE`` is a checkout of the project (``git worktree add /tmp/before <commit>``).
Nothing here is a test and nothing is written into the docs: the commits and the docs
quote what it prints.
"""

from __future__ import annotations

import argparse
import json
import os
import statistics
import subprocess
import sys
import warnings
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
FILES = ("slider_crank", "slotting_machine")
LEVELS = {"kinematics": {"kinematics_only": True}, "frictionless": {"friction": False}, "full": {}}


def _child(args) -> None:
    """In the process of one tree: time every case, print ``{case: ms}`` as JSON."""
    import re

    import numpy as np

    import kinetostatics as ks

    warnings.simplefilter("ignore")
    if args.numba:
        from kinetostatics.base import kernels

        kernels.set_backend("numba")
    out = {}
    for name in FILES:
        text = (ROOT / "mechanisms" / f"{name}.yaml").read_text(encoding="utf-8")
        for n in args.positions:
            model = ks.loads(re.sub(r"positions: *\d+", f"positions: {n}", text))
            kw = LEVELS[args.level]

            def run(model=model, kw=kw):
                result = ks.analyze(model, **kw)
                for c in result.columns:
                    result[c]

            out[f"{name}, {args.level}, {n} positions"] = _median(run, args.repeat, n)
    from kinetostatics.analysis.vectorised import analyze_stacked
    from kinetostatics.batch.variants import Template
    from kinetostatics.model.stacking import stack

    tpl = Template.load(ROOT / "mechanisms" / "slotting_machine.yaml")
    rng = np.random.default_rng(0)
    lo, hi = np.array([0.8, 130.0]), np.array([1.2, 170.0])
    designs = [dict(zip(("BC_ratio", "L_O2O3"), lo + (hi - lo) * rng.random(2))) for _ in range(24)]
    models = [tpl.model(d) for d in designs]
    stacked = stack(models)
    key = "slotting_machine, 24 designs stacked, friction, 360 positions"
    out[key] = _median(lambda: analyze_stacked(models, stacked=stacked), args.repeat, 8640)
    print(json.dumps(out))


def _median(f, repeat: int, positions: int) -> float:
    """The median CPU time of ``f`` in ms (``repeat`` calls, fewer over many positions),
    after three untimed calls."""
    import time

    for _ in range(3):
        f()
    times = []
    for _ in range(max(3, repeat if positions <= 10_000 else repeat // 10)):
        t0 = time.process_time()
        f()
        times.append(time.process_time() - t0)
    return 1e3 * statistics.median(times)


def main(argv=None) -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--baseline", type=Path, required=True, help="the other source tree")
    ap.add_argument("--rounds", type=int, default=5)
    ap.add_argument("--repeat", type=int, default=50, help="calls timed per case")
    ap.add_argument("--positions", type=int, nargs="+", default=[360, 36_000])
    ap.add_argument("--level", choices=list(LEVELS), default="full")
    ap.add_argument("--numba", action="store_true", help="the optional compiled backend")
    ap.add_argument("--child", action="store_true", help=argparse.SUPPRESS)
    args = ap.parse_args(argv)
    if args.child:
        _child(args)
        return
    trees = {"this tree": ROOT / "src", "baseline": args.baseline.resolve() / "src"}
    child = [sys.executable, __file__, "--child", "--baseline", str(args.baseline)]
    child += ["--repeat", str(args.repeat), "--level", args.level, "--positions"]
    child += [str(n) for n in args.positions] + (["--numba"] if args.numba else [])
    got: dict[str, list[dict]] = {tree: [] for tree in trees}
    for k in range(args.rounds):
        for tree, src in list(trees.items())[:: 1 if k % 2 == 0 else -1]:  # each first in turn
            env = dict(os.environ, PYTHONPATH=str(src))
            done = subprocess.run(child, env=env, capture_output=True, text=True, check=True)
            got[tree].append(json.loads(done.stdout.strip().splitlines()[-1]))
        print(f"  round {k + 1}/{args.rounds}", file=sys.stderr)
    print(f"| case | this tree [ms] | baseline ({args.baseline}) [ms] | ratio |")
    print("|---|---|---|---|")
    for case in got["this tree"][0]:
        a, b = (statistics.median(r[case] for r in got[tree]) for tree in trees)
        print(f"| {case} | {a:.3g} | {b:.3g} | {a / b:.3f} |")


if __name__ == "__main__":
    main()
