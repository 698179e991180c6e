"""The pictures one by one, and the picture commands against another source tree.

Per picture: the slotting machine's pictures each built and saved as ``plot`` saves them
(``save_png`` inside ``drawn_once``), in one process, the CPU time of each build and save
(``time.process_time``), the median over ``--repeat`` after two untimed ones.  With
``--baseline TREE`` the same runs in a process on that tree's ``src`` in turns with this
one (``--rounds`` rounds), and each picture's medians are printed side by side.

``--command "plot"`` (or ``"report --pdf"``) times whole processes instead: the command on
the slotting machine, this tree's and the baseline's in turns, each process's CPU time
(user + system), and prints the median of the rounds' ratios (this tree / baseline) with
their range: a change of a few per cent, which the commands' table (``bench_commands.py``,
ratios to ``import numpy`` moving ±10 % between rounds) cannot resolve.

    PYTHONPATH=src python tests/benchmarks/bench_pictures.py [--baseline TREE]
        [--rounds 2] [--repeat 12] [--only polar torque …]
    PYTHONPATH=src python tests/benchmarks/bench_pictures.py --baseline TREE
        --command "plot" [--rounds 15]
"""

from __future__ import annotations

import argparse
import json
import os
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

from bench_commands import cpu_time  # one process's CPU time (user + system)

ROOT = Path(__file__).resolve().parents[2]
FILE = ROOT / "mechanisms" / "slotting_machine.yaml"
PICTURES = ("drawing", "motion", "torque", "reactions", "polar", "velocity", "acceleration")


def _figure(pl, result, name: str):
    if name == "drawing":
        return pl.draw_mechanism(result, row=0)
    if name == "motion":
        return pl.motion_diagram(result)
    if name == "torque":
        return pl.torque_curves(result)
    if name == "reactions":
        return pl.reaction_curves(result, friction=True)
    if name == "polar":
        return pl.polar_diagrams(result)
    return pl.polygon_figure(result, name, row=0)


def pictures(names, repeat: int) -> dict[str, float]:
    """{picture: median CPU time of its build and save, s} in this process."""
    import matplotlib

    matplotlib.use("Agg")
    import kinetostatics as ks
    from kinetostatics.outputs import plotting as pl
    from kinetostatics.outputs.plotting.crop import drawn_once, save_png

    result = pl.analyze_for_pictures(ks.load(FILE), course=True, events=True)
    out = {}
    with tempfile.TemporaryDirectory() as tmp, drawn_once():
        for name in names:
            times = []
            for k in range(repeat + 2):
                t0 = time.process_time()
                save_png(_figure(pl, result, name), Path(tmp) / f"{name}.png", 110)
                if k >= 2:
                    times.append(time.process_time() - t0)
            out[name] = statistics.median(times)
    return out


def _env(tree: Path) -> dict:
    env = dict(os.environ, PYTHONPATH=str(tree / "src"), OPENBLAS_NUM_THREADS="1")
    env.pop("PYTHONDONTWRITEBYTECODE", None)  # bytecode written once, loaded after
    return env


def commands(command: str, baseline: Path, rounds: int) -> None:
    with tempfile.TemporaryDirectory() as tmp:
        cmd = [sys.executable, "-m", "kinetostatics", *command.split(), str(FILE), "--out", tmp]
        trees = {"this tree": ROOT, "baseline": baseline}
        for tree in trees.values():  # the bytecode written, the files cached
            cpu_time(cmd, _env(tree))
        ratios = []
        for _ in range(rounds):
            ours, theirs = (cpu_time(cmd, _env(t)) for t in trees.values())
            ratios.append(ours / theirs)
    print(
        f"{command}: this tree / baseline {statistics.median(ratios):.3f} "
        f"(rounds {min(ratios):.3f}-{max(ratios):.3f}, {rounds} rounds)"
    )


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--baseline", type=Path, help="another source tree, timed in turns")
    ap.add_argument("--rounds", type=int, default=2, help="rounds in turns with the baseline")
    ap.add_argument("--repeat", type=int, default=12, help="timed builds per picture")
    ap.add_argument("--only", nargs="+", choices=PICTURES, default=list(PICTURES))
    ap.add_argument("--command", help='whole processes: "plot" or "report --pdf"')
    ap.add_argument("--json", action="store_true", help=argparse.SUPPRESS)  # a child's
    args = ap.parse_args()
    if args.json:
        print(json.dumps(pictures(args.only, args.repeat)))
        return
    if args.command:
        if args.baseline is None:
            raise SystemExit("--command needs --baseline")
        commands(args.command, args.baseline.resolve(), args.rounds)
        return
    trees = {"this tree": ROOT}
    if args.baseline is not None:
        trees["baseline"] = args.baseline.resolve()
    argv = [__file__, "--json", "--repeat", str(args.repeat), "--only", *args.only]
    got: dict[str, list] = {t: [] for t in trees}
    for _ in range(args.rounds if args.baseline is not None else 1):
        for label, tree in trees.items():
            run = subprocess.run(
                [sys.executable, *argv], env=_env(tree), check=True, capture_output=True
            )
            got[label].append(json.loads(run.stdout))
    print("picture".ljust(14) + "".join(f"{t:>22}" for t in trees) + "  [ms, CPU, medians]")
    for name in args.only:
        cells = [1e3 * statistics.median(r[name] for r in got[t]) for t in trees]
        print(name.ljust(14) + "".join(f"{c:>22.1f}" for c in cells))


if __name__ == "__main__":
    main()
