"""The cost of the cam joint: CPU time of ``ks.analyze`` of cam mechanisms, as ratios
measured in one run (issue 40: measure before optimising; issue 36's long run spends
most of its time on generated cams).

    PYTHONPATH=src python tests/benchmarks/bench_cam.py [--rounds N] [--write] [[NAME=]TREE ...]

The mechanisms: the shipped ``cam_roller.yaml`` and ``cam_flat_oscillating.yaml``, and
two cam mechanisms of the verification net's generator (``tests/net/generate.py``,
``generate(seed, features=("cam",))``, seeds 3000000 and 3000001), each loaded once and
analysed in full (``ks.analyze(model)``, both friction solutions).  For each, in one
process:

- *CPU ms*: CPU time (``time.process_time``) of one analysis, samples of at least
  50 ms each;
- *× slider-crank*: against the analysis of ``mechanisms/slider_crank.yaml`` (no cam)
  timed in turns with it, the median of the per-sample ratios: what a cam costs
  above a plain linkage on the same machine under the same load;
- *cam share*: the part of a cProfile (in CPU time) of three analyses spent in calls
  into the cam's modules (``joints/cam.py``, ``_camlaw.py``, ``_camprofile.py``,
  ``_camphase.py``) from outside them.

Each TREE (a checkout's root: its ``src`` goes on PYTHONPATH; default this checkout;
named NAME in the table, its folder's name without one) is
measured in a fresh process per round, the trees in turns (N rounds, default 3); with
two or more, *× first tree* is the median over the rounds of each round's ratio of the
CPU ms to the first tree's: an older checkout against this one gives before/after in
one run (the mechanisms' texts are made here, once, and given to every tree).
``--write`` puts the table into docs/benchmarks.md (between its ``bench_cam`` markers).
Nothing here is a test.
"""

from __future__ import annotations

import argparse
import json
import os
import statistics
import subprocess
import sys
import time
import warnings
from pathlib import Path

from _common import ROOT
from bench_speed import load, machine

sys.path.insert(0, str(ROOT / "tests" / "net"))
import generate as G  # noqa: E402

DOC = ROOT / "docs" / "benchmarks.md"
BEGIN, END = "<!-- bench_cam: begin -->", "<!-- bench_cam: end -->"
SEEDS = (3000000, 3000001)

CHILD = r"""
import cProfile, json, statistics, sys, time, warnings
warnings.simplefilter("ignore")
import kinetostatics as ks

CAM = ("joints/cam.py", "joints/_camlaw.py", "joints/_camprofile.py", "joints/_camphase.py")
cases, reference = json.loads(sys.stdin.read())


def per_call(f):
    n, t = 0, 0.0
    while t < 0.05:
        t0 = time.process_time()
        f()
        t += time.process_time() - t0
        n += 1
    return t / n


def share(f):
    pr = cProfile.Profile(time.process_time)
    pr.enable()
    for _ in range(3):
        f()
    pr.disable()
    import pstats

    st = pstats.Stats(pr)
    inside = lambda fn: fn[0].replace("\\", "/").endswith(CAM)
    cam = sum(
        edge[3]
        for fn, (_, _, _, _, callers) in st.stats.items() if inside(fn)
        for caller, edge in callers.items() if not inside(caller)
    )
    return cam / st.total_tt


ref_model = ks.load(reference)
ref = lambda: ks.analyze(ref_model)
ref()
out = {}
for name, kind, source in cases:
    model = ks.load(source) if kind == "file" else ks.loads(source)
    f = lambda: ks.analyze(model)
    f()
    times, ratios = [], []
    for _ in range(3):
        a, b = per_call(f), per_call(ref)
        times.append(a)
        ratios.append(a / b)
    out[name] = {"ms": 1e3 * statistics.median(times), "ref": statistics.median(ratios),
                 "share": share(f)}
print(json.dumps(out))
"""


def cases() -> list[tuple[str, str, str]]:
    out = [
        (name, "file", str(ROOT / "mechanisms" / name))
        for name in ("cam_roller.yaml", "cam_flat_oscillating.yaml")
    ]
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        for seed in SEEDS:
            doc = G.generate(seed, features=("cam",))
            out.append((f"generated {seed}", "text", G.to_text(doc)))
    return out


def _tree(arg: str) -> tuple[str, Path]:
    name, _, path = arg.rpartition("=")
    return name or Path(path).resolve().name, Path(path).resolve()


def measure(tree: Path, payload: str) -> dict:
    env = dict(os.environ, PYTHONPATH=str(tree / "src"))
    run = subprocess.run(
        [sys.executable, "-c", CHILD], input=payload, env=env, capture_output=True, text=True
    )
    if run.returncode:
        raise SystemExit(f"{tree}: {run.stderr.strip().splitlines()[-1]}")
    return json.loads(run.stdout)


def _median(rounds: list[list[dict]], k: int, name: str, key: str) -> float:
    return statistics.median(r[k][name][key] for r in rounds)


def table(trees: list[tuple[str, Path]], rounds: list[list[dict]], names: list[str]) -> str:
    multi = len(trees) > 1
    head = "| mechanism | tree | CPU ms per analysis | × slider-crank | cam share |"
    lines = [head + (" × first tree |" if multi else ""),
             "|---|---|---|---|---|" + ("---|" if multi else "")]  # fmt: skip
    for name in names:
        for k, (tree, _) in enumerate(trees):
            ms, ref, share = (_median(rounds, k, name, key) for key in ("ms", "ref", "share"))
            row = f"| {name} | {tree} | {ms:.3g} | {ref:.3g}× | {100 * share:.0f} % |"
            if multi:
                first = statistics.median(r[k][name]["ms"] / r[0][name]["ms"] for r in rounds)
                row += f" {first:.3g}× |"
            lines.append(row)
    return "\n".join(lines)


def main(argv=None) -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("trees", nargs="*", help="[NAME=]checkout to compare (default this one)")
    ap.add_argument("--rounds", type=int, default=3)
    ap.add_argument("--write", action="store_true", help="rewrite the table in docs/benchmarks.md")
    args = ap.parse_args(argv)
    trees = [_tree(t) for t in args.trees] or [(ROOT.name, ROOT)]
    before, t0 = load(), time.perf_counter()
    cs = cases()
    payload = json.dumps([cs, str(ROOT / "mechanisms" / "slider_crank.yaml")])
    rounds = []
    for r in range(args.rounds):
        order = list(range(len(trees)))[:: 1 if r % 2 == 0 else -1]
        got = {k: measure(trees[k][1], payload) for k in order}
        rounds.append([got[k] for k in range(len(trees))])
        print(f"round {r + 1} of {args.rounds} done", file=sys.stderr)
    body = "\n".join(
        [
            f"**Conditions:** measured {time.strftime('%Y-%m-%d')} on {machine()}; {before} "
            f"before and {load()} after the run ({time.perf_counter() - t0:.0f} s), "
            f"rounds: {args.rounds}; trees: " + ", ".join(f"`{name}`" for name, _ in trees) + ".",
            "",
            table(trees, rounds, [c[0] for c in cs]),
        ]
    )
    print(body)
    if args.write:
        text = DOC.read_text(encoding="utf-8")
        i, j = text.index(BEGIN) + len(BEGIN), text.index(END)
        DOC.write_text(text[:i] + "\n" + body + "\n" + text[j:], encoding="utf-8")


if __name__ == "__main__":
    main()
