"""Kinetostatics of the shipped slider-crank at 360 and 36,000 positions against a
closed-form numpy slider-crank (kinematics + reactions, and + the source's eq. 9
for the friction torque) measured in the same run.

Targets (issue "Kinetostatics"): at 360 positions frictionless ≤ 30×, full
analysis with both friction solutions ≤ 50×; errors at round-off.

    python tests/benchmarks/bench_kinetostatics.py
"""

from __future__ import annotations

import numpy as np
from _common import ROOT, best_of

import kinetostatics as ks
from tests.oracles import slider_crank_closed_form as cf


def main() -> None:
    p = cf.SliderCrank()
    system = ks.build_system(ks.load(ROOT / "mechanisms" / "slider_crank.yaml"))
    print(
        f"{'case':<34}{'positions':>10}{'ours [ms]':>11}{'closed [ms]':>13}{'ratio':>8}"
        f"{'max rel. error':>16}"
    )
    for n in (360, 36_000):
        phi = np.arange(n) * 2 * np.pi / n

        def closed(phi=phi):
            cf.kinematics(p, phi)
            return cf.reactions(p, phi)

        def closed_friction(phi=phi):
            closed(phi)
            return cf.friction_approx_torque_eq9(p, phi)

        t_cf, t_cf_f = best_of(closed), best_of(closed_friction)
        # read what the closed form computes: every reaction and the torque (columns are lazy)
        plain = [
            "O.Fx",
            "O.Fy",
            "A.Fx",
            "A.Fy",
            "B.Fx",
            "B.Fy",
            "slide.N",
            "slide.M",
            "motor.torque",
        ]
        with_f = plain + [
            n.replace("motor.torque", "motor.torque_friction_approx") for n in plain[-1:]
        ]

        def frictionless(phi=phi, plain=plain):
            r = ks.analyze(system, positions=phi, friction=False)
            return [r[n] for n in plain]

        def full(phi=phi, with_f=with_f):
            r = ks.analyze(system, positions=phi)
            return [r[n] for n in with_f + ["motor.torque_friction"]]

        t0, t1 = best_of(frictionless, repeat=5), best_of(full, repeat=5)
        r = ks.analyze(system, positions=phi)
        ref = cf.reactions(p, phi)
        e0 = np.max(np.abs(r["motor.torque"] - ref["M1"])) / np.max(np.abs(ref["M1"]))
        eq9 = cf.friction_approx_torque_eq9(p, phi)
        e1 = np.max(np.abs(r["motor.torque_friction_approx"] - eq9)) / np.max(np.abs(eq9))
        print(
            f"{'frictionless reactions + torque':<34}{n:>10}{t0 * 1e3:>11.2f}{t_cf * 1e3:>13.3f}"
            f"{t0 / t_cf:>8.1f}{e0:>16.1e}"
        )
        print(
            f"{'full (approximate + consistent)':<34}{n:>10}{t1 * 1e3:>11.2f}{t_cf_f * 1e3:>13.3f}"
            f"{t1 / t_cf_f:>8.1f}{e1:>16.1e}"
        )


if __name__ == "__main__":
    main()
