"""How many of the long run's generated mechanisms do not close after one turn.

Each seed's mechanism (``generate.generate``) is analysed over its one-turn cycle
(kinematics only) and its ``closure`` self-check read (docs/theory.md): the last row
carried on to one period after the first, against the first pose.  The counts go to
docs/verification.md between ``<!-- closure:begin -->`` and ``<!-- closure:end -->``
with ``--write``; results are kept in ``long_run/closure.jsonl`` (resumed).

    PYTHONPATH=src python tests/net/closure_scan.py [--mechanisms 10000] [--workers 2] [--write]
"""

from __future__ import annotations

import argparse
import json
import multiprocessing as mp
import sys
import warnings
from pathlib import Path

HERE = Path(__file__).resolve().parent
ROOT = HERE.parents[1]
RESULTS = HERE / "long_run" / "closure.jsonl"
BEGIN, END = "<!-- closure:begin -->", "<!-- closure:end -->"


def one(seed: int):
    sys.path.insert(0, str(HERE))
    import generate as G

    import kinetostatics as ks

    try:
        doc = G.generate(seed)
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            res = ks.analyze(G.system_of(G.to_text(doc)), kinematics_only=True)
        c = res.checks.closure
        return [seed, None if c is None else c.value, "" if c is None else c.where]
    except Exception as exc:  # noqa: BLE001 — counted, not hidden
        return [seed, f"{type(exc).__name__}", ""]


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--mechanisms", type=int, default=10_000)
    ap.add_argument("--first-seed", type=int, default=1_000_000)
    ap.add_argument("--workers", type=int, default=2)
    ap.add_argument("--write", action="store_true")
    a = ap.parse_args(argv)
    seeds = range(a.first_seed, a.first_seed + a.mechanisms)
    done = {}
    if RESULTS.exists():
        for line in RESULTS.read_text(encoding="utf-8").splitlines():
            seed, value, where = json.loads(line)
            done[seed] = (value, where)
    todo = [s for s in seeds if s not in done]
    if todo:
        with mp.Pool(a.workers) as pool, RESULTS.open("a", encoding="utf-8") as f:
            for seed, value, where in pool.imap_unordered(one, todo, chunksize=20):
                f.write(json.dumps([seed, value, where]) + "\n")
                f.flush()
                done[seed] = (value, where)
    from kinetostatics.analysis.checks import CLOSURE_TOL

    rows = [(s, *done[s]) for s in seeds if s in done]
    errors = [r for r in rows if isinstance(r[1], str)]
    open_ = [r for r in rows if isinstance(r[1], float) and not r[1] <= CLOSURE_TOL]
    closed = [r for r in rows if isinstance(r[1], float) and r[1] <= CLOSURE_TOL]
    worst = max((r[1] for r in closed), default=0.0)
    lines = [
        BEGIN,
        "",
        f"`python tests/net/closure_scan.py --mechanisms {a.mechanisms}`: {len(rows)} of the long "
        f"run's {a.mechanisms} mechanisms analysed over their one-turn cycle; {len(closed)} close "
        f"(largest gap {worst:.1g}), **{len(open_)} do not** (closure > {CLOSURE_TOL:g}), "
        f"{len(errors)} raised.",
        "",
    ]
    lines += [f"- seed {s}: closure {v:.3g} ({w})" for s, v, w in open_[:40]]
    if len(open_) > 40:
        lines.append(f"- … and {len(open_) - 40} more")
    lines += [f"- seed {s}: {v}" for s, v, _ in errors[:10]]
    lines += ["", END]
    block = "\n".join(lines)
    print(block)
    if a.write:
        sys.path.insert(0, str(HERE))
        from long_run import write_block

        write_block(block, BEGIN, END)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
