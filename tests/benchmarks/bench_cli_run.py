"""Wall and CPU time of the whole ``kinetostatics run`` process against a bare
``python -c "import numpy"`` (issue 17), interleaved so that both see the same load.

    python tests/benchmarks/bench_cli_run.py [N] [TREE ...]

N runs of each command (default 5), the median reported; each TREE is a source tree
(its ``src`` goes on PYTHONPATH; default this checkout).  The environment is inherited:
with ``PYTHONDONTWRITEBYTECODE=1`` every module is compiled from source on every run.
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


def main(argv: list[str]) -> None:
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
