"""Work–precision of forward dynamics on Andrews' squeezer mechanism (the Bari test set's
"andrews" problem; mechanisms/andrews_squeezer.yaml): the error of the seven angles at
t = 0.03 s against the published reference, and the CPU time, over integrator tolerances.

    python tests/benchmarks/bench_andrews.py            # print the table
    python tests/benchmarks/bench_andrews.py --write    # and put it into docs/benchmarks.md
"""

from __future__ import annotations

import os
import platform
import sys
import time

import numpy as np
from _common import ROOT

import kinetostatics as ks
from kinetostatics.dynamics import simulate
from tests import andrews_reference as ref

CASES = [
    ("RK45", 1e-6),
    ("RK45", 1e-8),
    ("DOP853", 1e-6),
    ("DOP853", 1e-8),
    ("DOP853", 1e-9),
    ("DOP853", 1e-10),
    ("DOP853", 1e-11),
    ("DOP853", 1e-12),
]
BEGIN, END = "<!-- bench_andrews: begin -->", "<!-- bench_andrews: end -->"


def _machine() -> str:
    cpu = platform.processor() or platform.machine()
    try:
        with open("/proc/cpuinfo", encoding="utf-8") as f:
            cpu = next(line.split(":", 1)[1].strip() for line in f if "model name" in line)
    except (OSError, StopIteration):
        pass
    return (
        f"{cpu}, {os.cpu_count()} logical cores shared, Python {platform.python_version()}, "
        f"NumPy {np.__version__}"
    )


def main() -> None:
    model = ks.load(ROOT / "mechanisms" / "andrews_squeezer.yaml")
    lines = [
        f"Machine: {_machine()}. CPU time (`time.process_time`) of `simulate(model, 0.03, "
        "method=..., rtol=...)` from the consistent start at rest; error: the largest of "
        "the seven angles' |Δ| (rad) at t = 0.03 s against the reference, and the largest "
        "|Δ| of their rates over the largest rate (1424 rad/s).",
        "",
        "| method | rtol | CPU time (s) | RHS evaluations | max \\|Δ angle\\| (rad) | "
        "max \\|Δ rate\\| / max rate |",
        "|---|---|---|---|---|---|",
    ]
    for method, rtol in CASES:
        t0 = time.process_time()
        sim = simulate(model, ref.T_END, method=method, rtol=rtol)
        cpu = time.process_time() - t0
        q, qd = ref.state_at(sim, ref.T_END)
        system = sim.dynamics.system
        da = np.max(np.abs(ref.relative_angles(system, q) - ref.FINAL))
        dw = np.max(np.abs(ref.relative_angles(system, qd) - ref.FINAL_SPEED))
        lines.append(
            f"| {method} | {rtol:.0e} | {cpu:.2f} | {sim.nfev} | {da:.1e} | "
            f"{dw / np.max(np.abs(ref.FINAL_SPEED)):.1e} |"
        )
        print(lines[-1], file=sys.stderr)
    text = "\n".join(lines)
    print(text)
    if "--write" in sys.argv:
        doc = ROOT / "docs" / "benchmarks.md"
        old = doc.read_text(encoding="utf-8")
        i, j = old.index(BEGIN) + len(BEGIN), old.index(END)
        doc.write_text(old[:i] + "\n" + text + "\n" + old[j:], encoding="utf-8")


if __name__ == "__main__":
    main()
