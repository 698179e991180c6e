"""Full-cycle kinematics (positions, velocities, accelerations) of the shipped
slider-crank and slotting machine at 360 and 36,000 positions, and the ratio to
a closed-form numpy slider-crank measured in the same run.

Targets (issue "Core 2"): at 360 positions ≤ 25× the closed form (stretch 10×);
`kinetostatics run` of a shipped example under 1 s wall time with start-up.

    python tests/benchmarks/bench_kinematics.py
"""

from __future__ import annotations

import subprocess
import sys
import tempfile
import time

import numpy as np
from _common import ROOT, best_of

import kinetostatics as ks
from kinetostatics.kinematics.positions import derivatives, solve_positions
from kinetostatics.kinematics.schedule import sample_times, schedule
from tests.oracles import slider_crank_closed_form as cf


def kinematics(system, coords):
    sched = schedule(system)
    t, _ = sample_times(system, sched, coords)

    def run():
        sol = solve_positions(system, t, sched)
        _, psi_d, psi_dd = sched(t)
        return sol.q, *derivatives(system, sol.q, psi_d, psi_dd)[:2]

    return run


def main() -> None:
    p = cf.SliderCrank()
    print(
        f"{'mechanism':<18}{'positions':>10}{'ours [ms]':>12}{'closed form [ms]':>18}{'ratio':>8}"
        f"{'max rel. error':>16}"
    )
    for n in (360, 36_000):
        phi = np.arange(n) * 2 * np.pi / n
        t_cf = best_of(lambda phi=phi: cf.kinematics(p, phi))
        for name in ("slider_crank", "slotting_machine"):
            system = ks.build_system(ks.load(ROOT / "mechanisms" / f"{name}.yaml"))
            start = system.model.analysis.start
            sign = np.sign(system.motion_drivers[0].driver.motion.speed)
            run = kinematics(system, start + sign * phi)
            t_ours = best_of(run)
            err = ""
            if name == "slider_crank":
                q, qd, qdd = run()
                k = cf.kinematics(p, phi)
                e = max(
                    np.max(np.abs(q[:, 6] - k["xB"])) / np.max(np.abs(k["xB"])),
                    np.max(np.abs(qd[:, 5] - k["omega2"])) / np.max(np.abs(k["omega2"])),
                    np.max(np.abs(qdd[:, 5] - k["alpha2"])) / np.max(np.abs(k["alpha2"])),
                )
                err = f"{e:.1e}"
            print(
                f"{name:<18}{n:>10}{t_ours * 1e3:>12.3f}{t_cf * 1e3:>18.3f}"
                f"{t_ours / t_cf:>8.1f}{err:>16}"
            )
    with tempfile.TemporaryDirectory() as out:
        walls = []
        for _ in range(3):
            t0 = time.perf_counter()
            subprocess.run(
                [
                    sys.executable,
                    "-m",
                    "kinetostatics.cli",
                    "run",
                    str(ROOT / "mechanisms" / "slotting_machine.yaml"),
                    "--out",
                    out,
                ],
                check=True,
                capture_output=True,
            )
            walls.append(time.perf_counter() - t0)
    print(
        f"kinetostatics run slotting_machine.yaml (360 positions, with start-up): "
        f"{min(walls):.3f} s (best of 3)"
    )


if __name__ == "__main__":
    main()
