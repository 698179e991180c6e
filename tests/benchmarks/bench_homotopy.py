"""The consistent friction solution's homotopy: the self-locking hard case with a homotopy
step's cycling Newton given up at its 12th iteration (``kinetics/friction.py``,
``homotopy.CYCLING``) against each Newton run to its 30th, timed in turns in one process
(CPU time, the median of the rounds), at a few numbers of positions.  Prints the times,
their ratio, the Newton iterations of the rows the homotopy took, and whether every
column is the same.  Nothing here is a test; docs/accuracy.md (section 2) quotes it.

    PYTHONPATH=src python tests/benchmarks/bench_homotopy.py [--positions 360 3000] [--rounds 3]
"""

from __future__ import annotations

import argparse
import re
import time
import warnings

import numpy as np
from _common import ROOT

import kinetostatics as ks
from kinetostatics.kinetics import homotopy

PATH = ROOT / "tests" / "hard" / "slider_crank_self_locking.yaml"


def _analysed(model, cycling):
    old = homotopy.CYCLING
    homotopy.CYCLING = cycling
    try:
        t = time.process_time()
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            r = ks.analyze(model)
        return r, time.process_time() - t
    finally:
        homotopy.CYCLING = old


def main(argv=None) -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--positions", type=int, nargs="+", default=[360, 3000])
    ap.add_argument("--rounds", type=int, default=3)
    args = ap.parse_args(argv)
    patient = (homotopy.NEWTON + 1, np.inf)
    text = PATH.read_text("utf-8")
    print(
        "| positions | self-locked rows | rows by homotopy | given up at 12 [ms] | run to 30 [ms] "
        "| ratio | Newton iterations (homotopy rows) | every column the same |"
    )
    print("|---|---|---|---|---|---|---|---|")
    for n in args.positions:
        model = ks.loads(re.sub(r"positions: *\d+", f"positions: {n}", text), str(PATH))
        _analysed(model, homotopy.CYCLING)  # the system built, the plans made
        times: dict[str, list[float]] = {"early": [], "patient": []}
        for _ in range(args.rounds):
            early, t_early = _analysed(model, homotopy.CYCLING)
            late, t_late = _analysed(model, patient)
            times["early"].append(t_early)
            times["patient"].append(t_late)
        status = early["friction.status"]
        took = (status == 1) | (status == 2)
        it_e, it_l = early["friction.iterations"][took], late["friction.iterations"][took]
        same = all(
            np.array_equal(np.asarray(early[c]), np.asarray(late[c]), equal_nan=True)
            for c in early.columns
            if c != "friction.iterations"
        )
        te, tl = np.median(times["early"]), np.median(times["patient"])
        print(
            f"| {n} | {int((status == 2).sum())} | {int(took.sum())} | {te * 1e3:.0f} "
            f"| {tl * 1e3:.0f} | {te / tl:.2f} | {int(it_e.sum())} against {int(it_l.sum())} "
            f"| {'yes' if same else 'no'} |"
        )


if __name__ == "__main__":
    main()
