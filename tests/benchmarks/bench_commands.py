"""The commands users wait for, as whole processes against ``python -c "import numpy"``
(issue 40): ``run``, ``plot`` (all pictures) and ``report --pdf`` of the slotting machine.

Each round runs every candidate once, in turns (``import numpy`` first, then the
commands), each as a fresh process; its cost is the CPU time of the process (user +
system, from ``getrusage`` of the children), so that a load on the machine that delays
a process does not count, only what it computed.  A command's ratio is the median over
the rounds of its CPU time / ``import numpy``'s CPU time *in the same round*.  One round,
untimed, comes first: it writes the package's bytecode and fills the file cache, as a
user's second command finds them.

    PYTHONPATH=src python tests/benchmarks/bench_commands.py [--rounds N] [--runs K]
        [--baseline TREE] [--only NAME ...] [--write] [--note TEXT]

``--runs K`` repeats the whole measurement K times (the table of docs/accuracy.md
records two); ``--baseline TREE`` also times each command from another source tree
(its ``src``, e.g. a ``git worktree`` of an older commit), in the same rounds, to
measure a change; ``--write`` rewrites the table of docs/accuracy.md between
``<!-- commands:begin -->`` and ``<!-- commands:end -->`` with the conditions (machine,
load before and after).  Nothing here is a test: the targets are the project's aims.
"""

from __future__ import annotations

import argparse
import os
import resource
import statistics
import subprocess
import sys
import tempfile
import time
from dataclasses import dataclass
from pathlib import Path

from _common import machine, publish

ROOT = Path(__file__).resolve().parents[2]
BEGIN, END = "<!-- commands:begin -->", "<!-- commands:end -->"
MECHANISM = "mechanisms/slotting_machine.yaml"

# name: (arguments after ``kinetostatics``, target ratio, the row's words)
COMMANDS = {
    "run": (["run", MECHANISM], 2.2, "`kinetostatics run` (results.csv, summary.json)"),
    "plot": (["plot", MECHANISM], 10.0, "`kinetostatics plot` (all nine pictures, PNG)"),
    "report --pdf": (
        ["report", MECHANISM, "--pdf"],
        15.0,
        "`kinetostatics report --pdf` (report.md, report.html, report.pdf, img/)",
    ),
}


# the floor under a picture command: matplotlib alone drawing as many bare figures as it
# writes pictures (mpl_floor.py), timed in the same rounds
FLOORS = {"plot": 9, "report --pdf": 28}


# ``import numpy`` as the commands load it: one BLAS thread (cli.main sets
# OPENBLAS_NUM_THREADS where the user has not), without the other threads' spin as NumPy
# starts them; a row of its own, beside the baseline the targets are read against
ONE_THREAD = "import numpy, one BLAS thread"


def floor_name(command: str) -> str:
    return f"floor of {command}"


@dataclass(frozen=True)
class Candidate:
    name: str
    cmd: list[str]
    env: dict[str, str]


def cpu_time(cmd: list[str], env: dict[str, str]) -> float:
    """CPU time (user + system, s) of one process running ``cmd``."""
    r0 = resource.getrusage(resource.RUSAGE_CHILDREN)
    subprocess.run(cmd, env=env, cwd=ROOT, check=True, capture_output=True)
    r1 = resource.getrusage(resource.RUSAGE_CHILDREN)
    return r1.ru_utime + r1.ru_stime - r0.ru_utime - r0.ru_stime


def candidates(out: Path, only: list[str], baseline: Path | None) -> list[Candidate]:
    base = {k: v for k, v in os.environ.items() if k != "PYTHONDONTWRITEBYTECODE"}
    base["MPLBACKEND"] = "Agg"
    numpy = [sys.executable, "-c", "import numpy"]
    one = dict(base, OPENBLAS_NUM_THREADS=base.get("OPENBLAS_NUM_THREADS", "1"))
    found = [Candidate("import numpy", numpy, dict(base)), Candidate(ONE_THREAD, numpy, one)]
    trees = [("", ROOT)] + ([(" (baseline)", baseline)] if baseline else [])
    for name, (args, _target, _words) in COMMANDS.items():
        if only and name not in only:
            continue
        for suffix, tree in trees:
            env = dict(base, PYTHONPATH=str(tree / "src"))
            folder = out / f"{name}{suffix}".replace(" ", "_")
            cmd = [sys.executable, "-m", "kinetostatics", *args, "--out", str(folder)]
            found.append(Candidate(name + suffix, cmd, env))
    for name, n in FLOORS.items():
        if not only or name in only:
            script = str(ROOT / "tests" / "benchmarks" / "mpl_floor.py")
            cmd = [sys.executable, script, str(n), str(out / f"floor {n}")]
            found.append(Candidate(floor_name(name), cmd, one))  # as the commands run
    return found


def measure(cands: list[Candidate], rounds: int, log=print) -> dict[str, list[float]]:
    """CPU times of each candidate, round by round (the first round untimed)."""
    for c in cands:
        cpu_time(c.cmd, c.env)
    times: dict[str, list[float]] = {c.name: [] for c in cands}
    for k in range(rounds):
        for c in cands:
            times[c.name].append(cpu_time(c.cmd, c.env))
        log(
            f"  round {k + 1}/{rounds}: "
            + ", ".join(f"{n} {v[-1] * 1e3:.0f} ms" for n, v in times.items())
        )
    return times


def ratios(times: dict[str, list[float]]) -> dict[str, list[float]]:
    """Per-round ratio of each command to ``import numpy`` in the same round."""
    ref = times["import numpy"]
    return {n: [t / r for t, r in zip(v, ref)] for n, v in times.items() if n != "import numpy"}


def load() -> str:
    try:
        return " / ".join(f"{x:.2f}" for x in os.getloadavg())
    except OSError:
        return "unknown"


@dataclass(frozen=True)
class Run:
    conditions: str
    times: dict[str, list[float]]

    def ratio(self, name: str) -> float:
        return statistics.median(ratios(self.times)[name])

    def spread(self, name: str) -> str:
        r = ratios(self.times)[name]
        return f"{min(r):.3g}–{max(r):.3g}"

    def ms(self, name: str) -> str:
        return f"{statistics.median(self.times[name]) * 1e3:.0f}"


def table(runs: list[Run]) -> str:
    head = "| command | target |"
    rule = "|---|---|"
    for k, _ in enumerate(runs, 1):
        head += f" run {k}: CPU [ms] | run {k}: ratio (rounds' range) |"
        rule += "---|---|"
    head += " met |"
    rule += "---|"
    lines = [head, rule]
    first = runs[0]
    row = '| `python -c "import numpy"` | — |'
    for r in runs:
        row += f" {r.ms('import numpy')} | 1× |"
    lines.append(row + " — |")
    row = '| · `python -c "import numpy"` with one BLAS thread, as the commands set it | — |'
    for r in runs:
        row += f" {r.ms(ONE_THREAD)} | {r.ratio(ONE_THREAD):.3g}× ({r.spread(ONE_THREAD)}) |"
    lines.append(row + " — |")
    for name, (_args, target, words) in COMMANDS.items():
        if name not in first.times:
            continue
        row = f"| {words} | ≤ {target:g}× |"
        for r in runs:
            row += f" {r.ms(name)} | {r.ratio(name):.3g}× ({r.spread(name)}) |"
        met = all(r.ratio(name) <= target for r in runs)
        lines.append(row + f" {'yes' if met else 'no'} |")
        floor = floor_name(name)
        if floor in first.times:
            n = FLOORS[name]
            row = f"| · its floor: matplotlib alone, {n} bare figures (one BLAS thread) | — |"
            for r in runs:
                row += f" {r.ms(floor)} | {r.ratio(floor):.3g}× ({r.spread(floor)}) |"
            lines.append(row + " — |")
    return "\n".join(lines)


def main(argv=None) -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--rounds", type=int, default=7, help="timed rounds per run (default 7)")
    ap.add_argument("--runs", type=int, default=1, help="whole measurements (default 1)")
    ap.add_argument("--only", nargs="+", default=[], choices=list(COMMANDS), help="commands")
    ap.add_argument("--baseline", type=Path, help="another source tree, timed in the same rounds")
    ap.add_argument("--write", action="store_true", help="rewrite the table in docs/accuracy.md")
    ap.add_argument("--note", default="", help="text added to the conditions")
    args = ap.parse_args(argv)
    if args.write and (args.only or args.baseline):
        raise SystemExit("--write records every command of this tree: no --only, no --baseline")
    runs = []
    with tempfile.TemporaryDirectory() as d:
        cands = candidates(Path(d), args.only, args.baseline and args.baseline.resolve())
        for k in range(args.runs):
            before, t0 = load(), time.perf_counter()
            times = measure(cands, args.rounds, log=lambda s: print(s, file=sys.stderr))
            conditions = (
                f"run {k + 1}: {time.strftime('%Y-%m-%d %H:%M')} UTC, {args.rounds} rounds "
                f"({time.perf_counter() - t0:.0f} s), load average {before} (1/5/15 min) "
                f"before and {load()} after"
            )
            runs.append(Run(conditions, times))
            for name, v in ratios(times).items():
                print(f"{name}: {Run(conditions, times).ratio(name):.3g}× import numpy "
                      f"(rounds {', '.join(f'{x:.3g}' for x in v)})")  # fmt: skip
    body = (
        f"**Conditions:** {machine()}; CPU time of each process; "
        + "; ".join(r.conditions for r in runs)
        + (f"; {args.note}" if args.note else "")
        + ".\n\n"
        + table(runs)
    )
    publish(BEGIN, END, body, args.write)


if __name__ == "__main__":
    main()
