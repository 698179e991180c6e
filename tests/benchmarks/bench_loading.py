"""Loading a file and the size of a mechanism (issue 40): ``ks.loads`` of a 60-link chain
against its analysis, the time per link of the analysis at 20, 60 and 120 links (and
beyond, with ``--sizes``), and ``kinetostatics run`` against ``python -c "import numpy"``.

The chains are tests/chains.py's ``dyad_chain(n)``: a four-bar followed by RRR dyads, n
dyads in all, 2n + 1 moving links; "60 links" is n = 30 (61 moving links), 20 is n = 10,
120 is n = 60.  All times are CPU time of this process (``time.process_time``), the
candidates interleaved round by round (one untimed round first), each ratio the median
of the ratios of its rounds:

- *loads / analysis*: ``ks.loads(text)`` against ``ks.analyze(model)`` at 360 positions
  of the model it loaded, its System already built (the analysis alone; the System's
  construction is timed apart, ``build_system``);
- *per link*: ``ks.analyze(model)`` of a model just loaded (its System built in the call,
  as a user's first analysis pays it) over the number of moving links, and its ratio to
  the 20-link chain's in the same round;
- *run*: tests/benchmarks/bench_commands.py's measurement of ``run`` alone (whole
  processes, CPU time of each).

    PYTHONPATH=src python tests/benchmarks/bench_loading.py [--rounds N] [--runs K]
        [--sizes N ...] [--write] [--note TEXT]

``--phases`` prints only where ``ks.loads`` of the 61-link chain goes (libyaml's
composition, the walks that check the tree, the reading of the sections).
``--write`` rewrites the table of docs/accuracy.md between ``<!-- loading:begin -->``
and ``<!-- loading:end -->``.  Nothing here is a test: the targets are the project's aims.
"""

from __future__ import annotations

import argparse
import statistics
import sys
import tempfile
import time
from pathlib import Path

import bench_commands as commands
from _common import machine, publish  # and the repository on sys.path, for tests.chains

import kinetostatics as ks
from tests.chains import dyad_chain

ROOT = Path(__file__).resolve().parents[2]
BEGIN, END = "<!-- loading:begin -->", "<!-- loading:end -->"
LOADS_DYADS = 30  # 61 moving links
SIZES = (10, 30, 60)  # dyads: 21, 61, 121 moving links
TARGET_LOADS, TARGET_PER_LINK, TARGET_RUN = 0.5, 1.2, 2.2


def _cpu(f) -> float:
    t0 = time.process_time()
    f()
    return time.process_time() - t0


def links(n: int) -> int:
    return 2 * n + 1


def measure(rounds: int, sizes: tuple[int, ...], log=print) -> dict[str, list[float]]:
    """CPU times (s) of each candidate, round by round (the first round untimed)."""
    texts = {n: dyad_chain(n, positions=360) for n in sorted({LOADS_DYADS, *sizes})}
    loaded = ks.loads(texts[LOADS_DYADS])
    ks.analyze(loaded)  # its System built: the analysis alone is timed below
    times: dict[str, list[float]] = {}

    def one_round() -> dict[str, float]:
        t = {
            "loads": _cpu(lambda: ks.loads(texts[LOADS_DYADS])),
            "analysis": _cpu(lambda: ks.analyze(loaded)),
            "build_system": _cpu(lambda: ks.build_system(ks.loads(texts[LOADS_DYADS]))),
        }
        t["build_system"] -= t["loads"]  # the loads in it, about
        for n in sizes:
            model = ks.loads(texts[n])
            t[f"analyze {n}"] = _cpu(lambda m=model: ks.analyze(m))
        return t

    one_round()
    for k in range(rounds):
        for name, v in one_round().items():
            times.setdefault(name, []).append(v)
        log(
            f"  round {k + 1}/{rounds}: "
            + ", ".join(f"{n} {v[-1] * 1e3:.1f} ms" for n, v in times.items())
        )
    return times


def per_link(times: dict[str, list[float]], n: int, ref: int) -> list[float]:
    """Per round: time per link at n dyads over that at ``ref`` dyads."""
    a, b = times[f"analyze {n}"], times[f"analyze {ref}"]
    return [(x / links(n)) / (y / links(ref)) for x, y in zip(a, b)]


def _med(v: list[float]) -> float:
    return statistics.median(v)


def _range(v: list[float]) -> str:
    return f"{min(v):.3g}–{max(v):.3g}"


def rows(times: dict[str, list[float]], run: list[float], sizes) -> list[tuple[str, str, str]]:
    """(measure, target, value) of one run."""
    ratio = [x / y for x, y in zip(times["loads"], times["analysis"])]
    out = [
        (
            f"`ks.loads` of the {links(LOADS_DYADS)}-link chain / its analysis at 360 "
            "positions (System built)",
            f"≤ {TARGET_LOADS:g}×",
            f"{_med(ratio):.3g}× ({_range(ratio)}); loads {_med(times['loads']) * 1e3:.1f} ms, "
            f"analysis {_med(times['analysis']) * 1e3:.1f} ms, "
            f"build_system {_med(times['build_system']) * 1e3:.1f} ms",
        )
    ]
    ref = sizes[0]
    for n in sizes:
        ms = _med(times[f"analyze {n}"]) * 1e3
        value = f"{ms:.1f} ms, {ms / links(n):.3f} ms per link"
        target = "—"
        if n != ref:
            r = per_link(times, n, ref)
            value += f"; {_med(r):.3g}× ({_range(r)}) the {links(ref)}-link chain's"
            target = f"≤ {TARGET_PER_LINK:g}×" if links(n) <= 121 else "—"
        what = f"first `ks.analyze` of a {links(n)}-link chain (360 positions)"
        out.append((what, target, value))
    out.append(
        ('`kinetostatics run` / `python -c "import numpy"`', f"≤ {TARGET_RUN:g}×",
         f"{_med(run):.3g}× ({_range(run)})")
    )  # fmt: skip
    return out


def table(runs: list[list[tuple[str, str, str]]]) -> str:
    head = "| measure | target |" + "".join(f" run {k} |" for k in range(1, len(runs) + 1))
    lines = [head, "|---|---|" + "---|" * len(runs)]
    for i, (what, target, _v) in enumerate(runs[0]):
        lines.append(f"| {what} | {target} |" + "".join(f" {r[i][2]} |" for r in runs))
    return "\n".join(lines)


def phases(rounds: int) -> None:
    """Where ``ks.loads`` of the 61-link chain goes: libyaml's composition, the walks that
    check the tree, and the reading of the sections (medians of ``rounds``, CPU time,
    the collector held off as the loader holds it)."""
    import gc

    import yaml

    from kinetostatics.base import document
    from kinetostatics.errors import Collector
    from kinetostatics.io import builder

    text = dyad_chain(LOADS_DYADS, positions=360)
    root = document._compose_fast(text)[1]
    steps = {
        "ks.loads": lambda: ks.loads(text),
        "libyaml's composition": lambda: yaml.compose(text, Loader=document._CLoader),
        "the walks that check it": lambda: (
            document._within_limits(root),
            document._check_keys_and_duplicates(root, "<s>", Collector()),
        ),
        "composed and checked (compose)": lambda: document.compose(text),
        "read into the model (build)": lambda: builder.build(document.compose(text)),
    }
    times: dict[str, list[float]] = {name: [] for name in steps}
    for _ in range(rounds + 1):
        for name, step in steps.items():
            gc.disable()
            times[name].append(_cpu(step))
            gc.enable()
    build = [b - c for b, c in zip(times.pop("read into the model (build)"),
                                   times["composed and checked (compose)"])]  # fmt: skip
    for name, v in [*times.items(), ("read into the model (build)", build)]:
        print(f"{name}: {_med(v[1:]) * 1e3:.2f} ms")


def main(argv=None) -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--rounds", type=int, default=7, help="timed rounds per run (default 7)")
    ap.add_argument("--runs", type=int, default=1, help="whole measurements (default 1)")
    ap.add_argument("--sizes", type=int, nargs="+", default=list(SIZES), help="dyads per chain")
    ap.add_argument("--write", action="store_true", help="rewrite the table in docs/accuracy.md")
    ap.add_argument("--note", default="", help="text added to the conditions")
    ap.add_argument("--phases", action="store_true", help="where ks.loads goes, only")
    args = ap.parse_args(argv)
    if args.phases:
        phases(args.rounds)
        return
    sizes = tuple(args.sizes)
    if args.write and sizes != SIZES:
        raise SystemExit("--write records the default sizes: no --sizes")
    runs, conditions = [], []
    log = lambda s: print(s, file=sys.stderr)  # noqa: E731
    for k in range(args.runs):
        before, t0 = commands.load(), time.perf_counter()
        times = measure(args.rounds, sizes, log=log)
        with tempfile.TemporaryDirectory() as d:
            cands = commands.candidates(Path(d), ["run"], None)
            run = commands.ratios(commands.measure(cands, args.rounds, log=log))["run"]
        conditions.append(
            f"run {k + 1}: {time.strftime('%Y-%m-%d %H:%M')} UTC, {args.rounds} rounds "
            f"({time.perf_counter() - t0:.0f} s), load average {before} (1/5/15 min) "
            f"before and {commands.load()} after"
        )
        runs.append(rows(times, run, sizes))
        for what, target, value in runs[-1]:
            print(f"{what}: {value} (target {target})")
    body = (
        f"**Conditions:** {machine()}; CPU time; "
        + "; ".join(conditions)
        + (f"; {args.note}" if args.note else "")
        + ".\n\n"
        + table(runs)
    )
    publish(BEGIN, END, body, args.write)


if __name__ == "__main__":
    main()
