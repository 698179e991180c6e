"""What ``result.summary()`` costs beside the analysis it summarises (docs/benchmarks.md).

The plain summary formats what the rows hold and solves nothing; the cycle's stages
(``dynamics.stages.cycle_stage``: the cycle means, the output strokes, the self-locked
zones' edges, the flywheel and the drive) solve again between the rows and cost what they
cost, only when asked for.  For each case: CPU time (``time.process_time``, best of 3) of
``analyze``, of ``summary()`` of a fresh result (its self-checks included), and of
``summary(cycle_stage(result))``, and the ratios to the analysis, measured in this one run.
The cases: the 12-position self-locked slider-crank
(``tests/hard/slider_crank_self_locking.yaml`` at μ's case s = 90, the slowest summary
before the cycle became a stage) and every shipped mechanism at its file's positions (the
files driven by an effort, for forward dynamics only, are not analysed and say so).

    PYTHONPATH=src python tests/benchmarks/bench_summary.py   # --quick: the first case only
"""

from __future__ import annotations

import re
import sys
import time
import warnings
from pathlib import Path

import kinetostatics as ks
from kinetostatics.dynamics.stages import cycle_stage

ROOT = Path(__file__).resolve().parents[2]


def _cpu(fn, repeat: int = 3) -> tuple[float, object]:
    best, out = float("inf"), None
    for _ in range(repeat):
        t0 = time.process_time()
        out = fn()
        best = min(best, time.process_time() - t0)
    return best, out


def _cases():
    text = (ROOT / "tests" / "hard" / "slider_crank_self_locking.yaml").read_text("utf-8")
    text = re.sub(r"\n  s: 3 ", "\n  s: 90 ", text)
    text = re.sub(r"positions: 360", "positions: 12", text)
    yield "self-locked slider-crank, 12 positions", ks.loads(text, file="locked.yaml")
    for path in sorted((ROOT / "mechanisms").glob("*.yaml")):
        yield path.stem, ks.load(path)


def main(argv: list[str]) -> int:
    print(f"{'case':40s} {'analyze':>9s} {'summary()':>10s} {'ratio':>7s} {'with cycle':>11s}")
    for k, (name, model) in enumerate(_cases()):
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            try:
                ks.analyze(model)  # the system compiled once, as a second call finds it
            except ks.KinetostaticsError as exc:
                print(f"{name:40s} not analysed: {str(exc).splitlines()[0][:60]}")
                continue
            t_a, result = _cpu(lambda m=model: ks.analyze(m))
            # a fresh result each time: its self-checks are computed on first use
            t_s = min(_cpu(ks.analyze(model).summary, repeat=1)[0] for _ in range(3))
            t_c, _ = _cpu(lambda r=result: r.summary(cycle_stage(r)), repeat=1)
        print(f"{name:40s} {t_a:8.3f}s {t_s:9.4f}s {t_s / t_a:7.3f} {t_c:8.2f}s ({t_c / t_a:.1f}×)")
        if "--quick" in argv and k == 0:
            break
    return 0


if __name__ == "__main__":
    raise SystemExit(main(sys.argv[1:]))
