"""Long runs and the C allocator: what fresh memory costs an analysis at many positions.

Over tens of thousands of positions an analysis makes arrays of megabytes.  glibc's
``malloc`` gives blocks above its *mmap threshold* (dynamic, at most 32 MB) fresh pages
from the kernel and returns them on free, and it trims the top of its heap; every fresh
page costs a page fault on first touch.  This script analyses each case in fresh
processes, alternately with the default allocator and with

    MALLOC_MMAP_THRESHOLD_=67108864 MALLOC_TRIM_THRESHOLD_=268435456 MALLOC_TOP_PAD_=67108864

(glibc's environment variables: blocks up to 64 MB from the heap, kept after a free),
and prints the median time of ``ks.analyze`` (in-process, after one warm call), the
minor page faults and the system (kernel) time per analysis.  The numbers are the same
(the allocator does not change arithmetic); only where the memory comes from changes.

    PYTHONPATH=src python tests/benchmarks/bench_allocator.py [ROUNDS]
"""

from __future__ import annotations

import os
import statistics
import subprocess
import sys

from _common import ROOT

CASES = [("slotting_machine", "kinematics"), ("slotting_machine", "frictionless"),
         ("slider_crank", "frictionless")]  # fmt: skip
POSITIONS = 36_000
TUNED = {
    "MALLOC_MMAP_THRESHOLD_": str(64 << 20),
    "MALLOC_TRIM_THRESHOLD_": str(256 << 20),
    "MALLOC_TOP_PAD_": str(64 << 20),
}
CHILD = r"""
import gc, resource, sys, time
sys.path.insert(0, {bench!r})
from bench_speed import case, LEVEL_KW
import kinetostatics as ks
c = case({name!r}, {n}); kw = LEVEL_KW[{level!r}]
ks.analyze(c.model, **kw)
r0, ts = resource.getrusage(resource.RUSAGE_SELF), []
for _ in range(7):
    gc.disable(); t0 = time.perf_counter(); ks.analyze(c.model, **kw)
    ts.append(time.perf_counter() - t0); gc.enable()
r1 = resource.getrusage(resource.RUSAGE_SELF)
print(sorted(ts)[3], (r1.ru_minflt - r0.ru_minflt) / 7, (r1.ru_stime - r0.ru_stime) / 7)
"""


def run(name: str, level: str, tuned: bool) -> tuple[float, float, float]:
    env = dict(os.environ)
    for k in TUNED:
        env.pop(k, None)
    if tuned:
        env.update(TUNED)
    code = CHILD.format(bench=str(ROOT / "tests" / "benchmarks"), name=name, n=POSITIONS,
                        level=level)  # fmt: skip
    out = subprocess.run([sys.executable, "-c", code], env=env, capture_output=True,
                         text=True, check=True)  # fmt: skip
    t, faults, sys_time = map(float, out.stdout.split())
    return t, faults, sys_time


def main() -> None:
    rounds = int(sys.argv[1]) if len(sys.argv) > 1 else 3
    print(f"ks.analyze at {POSITIONS:,} positions, medians of {rounds} alternated processes")
    print("| mechanism | level | allocator | ms | page faults | kernel ms | time saved |")
    print("|---|---|---|---|---|---|---|")
    for name, level in CASES:
        got: dict[bool, list] = {False: [], True: []}
        for _ in range(rounds):
            for tuned in (False, True):
                got[tuned].append(run(name, level, tuned))
        med = {k: [statistics.median(col) for col in zip(*v)] for k, v in got.items()}
        for tuned in (False, True):
            t, faults, sys_time = med[tuned]
            saved = f"{1 - t / med[False][0]:.0%}" if tuned else ""
            label = "tuned" if tuned else "default"
            print(f"| {name} | {level} | {label} | {t * 1e3:.1f} | {faults:,.0f} | "
                  f"{sys_time * 1e3:.1f} | {saved} |")  # fmt: skip


if __name__ == "__main__":
    main()
