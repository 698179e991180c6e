"""Speed against error of the integrators for the forward dynamics: the start-up of
the slider-crank (docs/validation.md, "The reference machines", without friction
and load, gravity kept) under
a constant 5 N·m from rest, 0.5 s.  Each run's error is taken against a tight
reference run (DOP853, rtol 1e-13) at 51 times; the reference itself is checked
against an independent integration of Lagrange's equation (tests/dynamics/test_dynamics.py).

    python tests/benchmarks/bench_integrators.py            # print the table
    python tests/benchmarks/bench_integrators.py --write    # and put it into docs/dynamics.md
"""

from __future__ import annotations

import sys
import time

import numpy as np
from _common import ROOT

from kinetostatics.dynamics import simulate
from tests.dynamics.test_dynamics import free_slider_crank, lagrange

CASES = [
    ("RK23", 1e-4),
    ("RK23", 1e-6),
    ("RK45", 1e-4),
    ("RK45", 1e-6),
    ("RK45", 1e-8),
    ("RK45", 1e-10),
    ("DOP853", 1e-6),
    ("DOP853", 1e-8),
    ("DOP853", 1e-10),
    ("DOP853", 1e-12),
    ("Radau", 1e-6),
    ("Radau", 1e-8),
    ("BDF", 1e-6),
    ("LSODA", 1e-6),
    ("LSODA", 1e-8),
]
BEGIN, END = "<!-- bench_integrators: begin -->", "<!-- bench_integrators: end -->"
T_END = 0.5


def main() -> None:
    model = free_slider_crank("5")
    t = np.linspace(0.0, T_END, 51)
    ref = simulate(model, T_END, method="DOP853", rtol=1e-13).sample(t)
    exact = lagrange(5.0, T_END).sol(t)
    w_scale = np.max(np.abs(ref[:, 1]))
    lines = [
        f"Reference: DOP853, rtol 1e-13; against Lagrange's equation: max |Δφ| = "
        f"{np.max(np.abs(ref[:, 0] - exact[0])):.1e} rad, max |Δω| / max ω = "
        f"{np.max(np.abs(ref[:, 1] - exact[1])) / w_scale:.1e}.",
        "",
        "| method | rtol | wall time (s) | RHS evaluations | max \\|Δφ\\| (rad) | "
        "max \\|Δω\\| / max ω |",
        "|---|---|---|---|---|---|",
    ]
    for method, rtol in CASES:
        t0 = time.perf_counter()
        sim = simulate(model, T_END, method=method, rtol=rtol)
        wall = time.perf_counter() - t0
        y = sim.sample(t)
        lines.append(
            f"| {method} | {rtol:.0e} | {wall:.3f} | {sim.nfev} | "
            f"{np.max(np.abs(y[:, 0] - ref[:, 0])):.1e} | "
            f"{np.max(np.abs(y[:, 1] - ref[:, 1])) / w_scale:.1e} |"
        )
        print(lines[-1], file=sys.stderr)
    text = "\n".join(lines)
    print(text)
    if "--write" in sys.argv:
        doc = ROOT / "docs" / "dynamics.md"
        old = doc.read_text()
        i, j = old.index(BEGIN) + len(BEGIN), old.index(END)
        doc.write_text(old[:i] + "\n" + text + "\n" + old[j:])


if __name__ == "__main__":
    main()
