"""Wall and CPU time of the whole ``kinetostatics run`` process against a bare
``python -c "import numpy"`` (issue 17), interleaved so that both see the same load.

    python tests/benchmarks/bench_cli_run.py [N] [TREE ...]
    python tests/benchmarks/bench_cli_run.py --stages [N]

N runs of each command (default 5), the median reported; each TREE is a source tree
(its ``src`` goes on PYTHONPATH; default this checkout).  The environment is inherited:
with ``PYTHONDONTWRITEBYTECODE=1`` every module is compiled from source on every run.
``--stages``: what a run spends its CPU time on, each stage timed in a fresh process as
``run`` calls it, with one BLAS thread as ``run`` sets it (medians of N processes):
importing NumPy, then the package (and how much of it is making its dataclasses),
reading the file, the analysis, the cycle's stages, the summary, ``results.csv`` and
``summary.json``.
"""

from __future__ import annotations

import os
import resource
import statistics
import subprocess
import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
MECHANISM = ROOT / "mechanisms" / "slotting_machine.yaml"


def _time(cmd: list[str], env: dict[str, str]) -> tuple[float, float]:
    r0 = resource.getrusage(resource.RUSAGE_CHILDREN)
    t0 = time.perf_counter()
    subprocess.run(cmd, env=env, stdout=subprocess.DEVNULL, check=True)
    wall = time.perf_counter() - t0
    r1 = resource.getrusage(resource.RUSAGE_CHILDREN)
    return wall, r1.ru_utime + r1.ru_stime - r0.ru_utime - r0.ru_stime


STAGES = """
import time, dataclasses
made = []  # the CPU time of each dataclass made while the package is imported
_process = dataclasses._process_class
def _timed(*a, **k):
    t0 = time.process_time(); cls = _process(*a, **k); made.append(time.process_time() - t0)
    return cls
t = [time.process_time()]
import numpy
t.append(time.process_time())
dataclasses._process_class = _timed
import kinetostatics.cli
from kinetostatics.analysis import analyze
from kinetostatics.dynamics.stages import cycle_stage
from kinetostatics.outputs.loading import load
dataclasses._process_class = _process
t.append(time.process_time())
model = load({mechanism!r}); t.append(time.process_time())
result = analyze(model); t.append(time.process_time())
cycle = cycle_stage(result); t.append(time.process_time())
s = result.summary(cycle); t.append(time.process_time())
result.to_csv({out!r} + "/results.csv"); t.append(time.process_time())
result.to_json({out!r} + "/summary.json", s); t.append(time.process_time())
print(" ".join(str(b - a) for a, b in zip(t, t[1:])), sum(made), len(made))
"""
NAMES = ("import numpy", "import the package", "read the file", "analysis", "the cycle's stages",
         "summary", "results.csv", "summary.json")  # fmt: skip


def stages(n: int) -> None:
    """CPU time of each stage of ``run`` (the slotting machine has no sizing data), medians
    of ``n`` fresh processes; the package's import also as the dataclasses it makes."""
    out = Path(os.environ.get("TMPDIR", "/tmp")) / "bench_cli_run"
    out.mkdir(parents=True, exist_ok=True)
    code = STAGES.format(mechanism=str(MECHANISM), out=str(out))
    env = dict(os.environ, PYTHONPATH=str(ROOT / "src"))
    env.setdefault("OPENBLAS_NUM_THREADS", "1")  # as `run` sets it (cli.main) before NumPy
    cmd = [sys.executable, "-c", code]
    subprocess.run(cmd, env=env, check=True, capture_output=True)  # bytecode written
    runs = [
        [float(x) for x in subprocess.run(cmd, env=env, check=True, capture_output=True,
                                          text=True).stdout.split()]
        for _ in range(n)
    ]  # fmt: skip
    k = len(NAMES)
    for i, name in enumerate(NAMES):
        print(f"{name}: {statistics.median(r[i] for r in runs) * 1e3:.1f} ms")
        if i == 1:
            print(f"  of which making its {runs[0][k + 1]:.0f} dataclasses: "
                  f"{statistics.median(r[k] for r in runs) * 1e3:.1f} ms")  # fmt: skip
    print(f"in all: {statistics.median(sum(r[:k]) for r in runs) * 1e3:.1f} ms of CPU")


def main(argv: list[str]) -> None:
    if argv[:1] == ["--stages"]:
        stages(int(argv[1]) if len(argv) > 1 else 5)
        return
    n = int(argv[0]) if argv else 5
    trees = [Path(t).resolve() for t in argv[1:]] or [ROOT]
    out = Path(os.environ.get("TMPDIR", "/tmp")) / "bench_cli_run"
    cmds = {"import numpy": ([sys.executable, "-c", "import numpy"], dict(os.environ))}
    for tree in trees:
        run = [sys.executable, "-m", "kinetostatics.cli", "run", str(MECHANISM), "--out", str(out)]
        cmds[f"run ({tree})"] = (run, dict(os.environ, PYTHONPATH=str(tree / "src")))
    times: dict[str, list[tuple[float, float]]] = {k: [] for k in cmds}
    for _ in range(n):
        for name, (cmd, env) in cmds.items():
            times[name].append(_time(cmd, env))
    base_wall = statistics.median(w for w, _ in times["import numpy"])
    base_cpu = statistics.median(c for _, c in times["import numpy"])
    for name, v in times.items():
        wall = statistics.median(w for w, _ in v)
        cpu = statistics.median(c for _, c in v)
        print(
            f"{name}: wall {wall * 1e3:.0f} ms (x{wall / base_wall:.2f}), "
            f"cpu {cpu * 1e3:.0f} ms (x{cpu / base_cpu:.2f})"
        )


if __name__ == "__main__":
    main(sys.argv[1:])
