"""Size scaling: time per link of `build_system` and `analyze` for long chains of dyads.

Target (issue 17): a 60-link chain of dyads analyses at 360 positions in no more than
about 2× the time per link of a 20-link chain; no input makes the structure search
exponential.  The chains (tests/chains.py) are a four-bar followed by RRR dyads, n
dyads in all, 2n + 1 moving links.  Also timed: the structure of inputs that used to
make the group search combinatorial (an unsolvable open chain, a densely jointed fan
that now stops at ``MAX_SEARCH`` steps) and a large overconstrained chain.

    PYTHONPATH=src python tests/benchmarks/bench_scaling.py
"""

from __future__ import annotations

import time

import _common  # noqa: F401  (puts the repository on sys.path, for tests.chains)

import kinetostatics as ks
from kinetostatics.errors import StructureError
from tests.chains import dyad_chain, fan, open_chain


def cpu_best_of(f, repeat: int = 5) -> float:
    """Least CPU time of one call of f (s): steadier than wall time on a shared machine."""
    f()
    best = float("inf")
    for _ in range(repeat):
        t0 = time.process_time()
        f()
        best = min(best, time.process_time() - t0)
    return best


def _time_once(f) -> tuple[float, str]:
    t0 = time.process_time()
    try:
        f()
        outcome = "built"
    except StructureError as e:
        outcome = "StructureError: " + str(e).split(": ", 2)[-1][:60] + "…"
    return time.process_time() - t0, outcome


def main() -> None:
    print("CPU time, least of 5 runs")
    print(f"{'dyads':>6}{'links':>7}{'build [ms]':>12}{'analyze [ms]':>14}{'per link [ms]':>15}")
    per_link = {}
    for n in (10, 30, 20, 60):
        model = ks.loads(dyad_chain(n, positions=360))
        links = 2 * n + 1
        build = cpu_best_of(lambda m=model: ks.build_system(m))
        analyze = cpu_best_of(lambda m=model: ks.analyze(m))
        per_link[links] = (build / links, analyze / links)
        print(
            f"{n:>6}{links:>7}{build * 1e3:>12.1f}{analyze * 1e3:>14.1f}"
            f"{analyze / links * 1e3:>15.2f}"
        )
    for small, large in ((21, 61), (41, 121)):
        b = per_link[large][0] / per_link[small][0]
        a = per_link[large][1] / per_link[small][1]
        print(
            f"time per link, {large} links / {small} links: build_system {b:.2f}×, "
            f"analyze {a:.2f}× (target ≤ 2×)"
        )
    print()
    for label, text in (
        ("open chain, 199 links, 1 driver (unsolvable)", open_chain(199)),
        ("fan of 30 spokes (61 links, undecomposable)", fan(30)),
        ("fan of 40 spokes (81 links, past MAX_SEARCH)", fan(40)),
        ("overconstrained chain, 198 links", dyad_chain(66, redundant=True)),
    ):
        model = ks.loads(text)
        wall, outcome = _time_once(lambda m=model: ks.build_system(m))
        print(f"build_system, {label:<46} {wall:7.3f} s CPU  {outcome}")


if __name__ == "__main__":
    main()
