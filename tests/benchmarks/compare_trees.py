"""Every column of every shipped file and hard case, analysed by this tree and by another,
compared on the scale of its unit: what a change to the engine moved.

Each tree runs in a process of its own (``PYTHONPATH`` its ``src``), analyses
``mechanisms/*.yaml`` and ``tests/hard/*.yaml`` at their own positions and with
``analysis.positions`` set to each ``--positions``, and writes every column; this
process compares them.  A column's difference is max |a − b| over its rows (angles
modulo 360°), divided by the largest finite |value| among the columns of its unit in
that analysis (m, m/s, N, N*m…).  Per analysis the table gives the worst column, its
row's largest group condition number (``.cond``: where round-off is amplified) and its
friction status; ``friction.iterations`` (a count) is reported apart.

    PYTHONPATH=src python tests/benchmarks/compare_trees.py --baseline TREE [--positions 20000]

Nothing here is a test; a commit or docs/accuracy.md quotes what it prints.
"""

from __future__ import annotations

import argparse
import os
import pickle
import re
import subprocess
import sys
import tempfile
import warnings
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[2]
FILES = sorted((ROOT / "mechanisms").glob("*.yaml")) + sorted((ROOT / "tests/hard").glob("*.yaml"))


def _child(out: str, sizes: list[int]) -> None:
    """In one tree's process: every file at each size, its columns (or the error) pickled."""
    import kinetostatics as ks

    warnings.simplefilter("ignore")
    dump = {}
    for path in FILES:
        text = path.read_text(encoding="utf-8")
        for n in [None, *sizes]:
            key = (path.relative_to(ROOT).as_posix(), n)
            if n is not None:
                text_n, k = re.subn(r"positions: *\d+", f"positions: {n}", text, count=1)
                if not k:
                    continue
            try:
                r = ks.analyze(ks.loads(text if n is None else text_n, str(path)))
                dump[key] = {c: (np.asarray(r[c]).copy(), r.units[c]) for c in r.columns}
            except Exception as exc:  # noqa: BLE001  the same error in both trees is no change
                dump[key] = f"{type(exc).__name__}: {exc}"[:300]
    Path(out).write_bytes(pickle.dumps(dump))


def _run(tree: Path, sizes: list[int], out: Path) -> dict:
    env = {**os.environ, "PYTHONPATH": str(tree / "src")}
    args = [sys.executable, __file__, "--child", str(out), "--positions", *map(str, sizes)]
    subprocess.run(args, env=env, check=True, cwd=ROOT)
    return pickle.loads(out.read_bytes())


def _scales(cols: dict) -> dict[str, float]:
    scale: dict[str, float] = {}
    for value, unit in cols.values():
        if value.dtype.kind in "fiu":
            finite = np.abs(value[np.isfinite(value)])
            if finite.size:
                scale[unit] = max(scale.get(unit, 0.0), float(finite.max()))
    return scale


def _worst(a: dict, b: dict) -> tuple[float, str, int, int]:
    """(difference over the unit's scale, column, row, iterations' largest change)."""
    scale, worst = _scales(a), (0.0, "", 0)
    for name, (x, unit) in a.items():
        y = b[name][0]
        if x.dtype.kind not in "fiu" or name == "friction.iterations" or x.shape != y.shape:
            continue
        d = np.abs(x.astype(float) - y)
        if unit == "deg":
            d = np.abs((x - y + 180.0) % 360.0 - 180.0)
        d[~np.isfinite(d)] = 0.0  # a NaN or ∞ in both trees
        if d.size and (e := float(d.max()) / (scale.get(unit) or 1.0)) > worst[0]:
            worst = (e, name, int(d.argmax()))
    it = a.get("friction.iterations"), b.get("friction.iterations")
    steps = int(np.max(np.abs(it[0][0] - it[1][0]), initial=0)) if None not in it else 0
    return (*worst, steps)


def main(argv=None) -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--baseline", type=Path, help="the other tree (a checkout)")
    ap.add_argument("--positions", type=int, nargs="*", default=[20000])
    ap.add_argument("--child", help=argparse.SUPPRESS)
    args = ap.parse_args(argv)
    if args.child:
        return _child(args.child, args.positions)
    with tempfile.TemporaryDirectory() as tmp:
        ours = _run(ROOT, args.positions, Path(tmp) / "ours.pickle")
        theirs = _run(args.baseline.resolve(), args.positions, Path(tmp) / "theirs.pickle")
    head = "file | positions | worst / unit's scale | column | row | row's condition | status"
    print(f"| {head} | iterations ± |\n" + "|---" * 8 + "|")
    for key, a in ours.items():
        b = theirs.get(key)
        if isinstance(a, str) or isinstance(b, str):
            same = "the same error" if a == b else "DIFFERENT"
            print(f"| {key[0]} | {key[1] or 'own'} | {same} | | | | | |")
            continue
        e, name, row, steps = _worst(a, b)
        conds = [v[row] for c, (v, _) in a.items() if c.endswith(".cond") and v.shape[:1] > (row,)]
        status = a.get("friction.status", (np.array([np.nan] * (row + 1)), ""))[0][row]
        cond = f"{max(conds):.3g}" if conds and name else "—"
        cells = [key[0], key[1] or "own", f"{e:.1e}", name or "—", row, cond, f"{status:g}", steps]
        print("| " + " | ".join(map(str, cells)) + " |")


if __name__ == "__main__":
    main()
