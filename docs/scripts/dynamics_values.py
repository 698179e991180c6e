"""Every number of docs/dynamics.md (except the integrator table, which
tests/benchmarks/bench_integrators.py writes).

    python docs/scripts/dynamics_values.py            # print all sections (about a minute)
    python docs/scripts/dynamics_values.py --design   # the flywheel design only (fast)
    python docs/scripts/dynamics_values.py --write    # and replace the block in docs/dynamics.md
"""

from __future__ import annotations

import sys
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT / "src"))
sys.path.insert(0, str(ROOT))

import kinetostatics as ks  # noqa: E402
from kinetostatics.dynamics import equivalent, simulate, speed_fluctuation  # noqa: E402
from kinetostatics.dynamics.flywheel import design, verify  # noqa: E402

SLOTTING = ROOT / "mechanisms" / "slotting_machine.yaml"
RATIO = 24  # an assumed motor: 1440 rpm through a 24:1 reduction to the 60 rpm crank
BEGIN, END = "<!-- dynamics_values: begin -->", "<!-- dynamics_values: end -->"


def _bound(x: float) -> str:
    """``less than 1e-12`` for a round-off difference (its digits move with any reordered
    sum, on any machine), else the value."""
    return "less than 1e-12" if x < 1e-12 else f"{x:.1e}"


def design_section() -> str:
    model = ks.load(SLOTTING)
    fw = design(model, ratio=RATIO)
    fr = design(model, ratio=RATIO, friction=True)
    je = fw.machine_inertia
    rows = [
        "| quantity | frictionless balancing moment | with friction (consistent) |",
        "|---|---|---|",
        f"| work per cycle W (J) | {fw.work_per_cycle:.4f} | {fr.work_per_cycle:.4f} |",
        f"| mean driving moment M_d = W/2π (N·m) | {fw.mean_torque:.4f} | {fr.mean_torque:.4f} |",
        f"| maximum energy swing ΔW_max (J) | {fw.energy_swing:.4f} | {fr.energy_swing:.4f} |",
        f"| maximum stored energy at crank angle (°) | {np.degrees(fw.at_max) % 360:.3f} | "
        f"{np.degrees(fr.at_max) % 360:.3f} |",
        f"| minimum stored energy at crank angle (°) | {np.degrees(fw.at_min) % 360:.3f} | "
        f"{np.degrees(fr.at_min) % 360:.3f} |",
        f"| J_F = ΔW_max/(ω_m² δ), crank shaft (kg·m²) | {fw.inertia:.4f} | {fr.inertia:.4f} |",
        f"| J_F − J_e,mean, crank shaft (kg·m²) | {fw.inertia_net:.4f} | {fr.inertia_net:.4f} |",
        f"| J_F on the motor shaft, ratio {RATIO} (kg·m²) | {fw.motor_inertia:.5f} | "
        f"{fr.motor_inertia:.5f} |",
        f"| J_F − J_e,mean on the motor shaft (kg·m²) | {fw.motor_inertia_net:.5f} | "
        f"{fr.motor_inertia_net:.5f} |",
    ]
    from kinetostatics.analysis import cycle

    saved = cycle.NODES, cycle.PIECES
    cycle.NODES, cycle.PIECES = 16, 2 * cycle.PIECES  # the order check: twice the order
    finer = design(model)  # on twice the pieces
    cycle.NODES, cycle.PIECES = saved
    lines = [
        f"δ = {fw.delta:g}, ω_m = {fw.omega_m:.6f} rad/s (60 rpm, clockwise); the machine's "
        f"equivalent inertia J_e over the cycle: mean {je['mean']:.5f}, min {je['min']:.5f}, "
        f"max {je['max']:.5f} kg·m².",
        "",
        *rows,
        "",
        f"Order check: with 16-point instead of 8-point Gauss–Legendre on twice the pieces, "
        f"ΔW_max changes by {_bound(abs(finer.energy_swing - fw.energy_swing))} J and M_d by "
        f"{_bound(abs(finer.mean_torque - fw.mean_torque))} N·m.",
    ]
    return "\n".join(lines)


def equivalent_section() -> str:
    model = ks.load(SLOTTING)
    system = ks.build_system(model)
    r = ks.analyze(system, friction=False)
    k = np.arange(0, 360, 30)
    eq = equivalent(system, r.q[k], r.coordinate[k], speed=-2 * np.pi, extremes=r.extremes)
    rows = [
        "| position | crank angle (°) | J_e (kg·m²) | dJ_e/dφ (kg·m²/rad) | "
        "equivalent load torque (N·m) | balancing moment (N·m) |",
        "|---|---|---|---|---|---|",
    ]
    for n, kk in enumerate(k):
        rows.append(
            f"| {n + 1} | {r['angle'][kk]:.0f} | {eq['inertia'][n]:.5f} | "
            f"{eq['inertia_derivative'][n]:+.5f} | {eq['torque'][n]:+.4f} | "
            f"{r['motor.torque'][kk]:+.4f} |"
        )
    return "\n".join(rows)


def verification_section() -> str:
    model = ks.load(SLOTTING)
    fw = design(model)
    out = [
        "| run | flywheel (kg·m²) | start | cycles | ω_min … ω_max (rad/s) | "
        "ω_mean (rad/s) | δ simulated | δ / 0.04 |",
        "|---|---|---|---|---|---|---|---|",
    ]

    def row(label, check, start):
        c = check["last_cycle"]
        out.append(
            f"| {label} | {check['inertia']:.4f} | {start} | {check['cycles']} | "
            f"{c['omega_min']:.5f} … {c['omega_max']:.5f} | {c['omega_mean']:.5f} | "
            f"{check['delta']:.5f} | {check['delta'] / 0.04:.4f} |"
        )
        return check

    row("constant M_d, J_F − J_e,mean", verify(model, fw), "ω_m at max. energy")
    row("constant M_d, J_F", verify(model, fw, inertia=fw.inertia), "ω_m at max. energy")
    row(
        "constant M_d, J_F − J_e,mean",
        verify(model, fw, speed=fw.omega_m * (1 + fw.delta / 2)),
        "ω_m(1 + δ/2) at max. energy",
    )
    motor = row(
        "motor curve s = 0.05, J_F − J_e,mean",
        verify(model, fw, torque="motor", cycles=25, start="rest"),
        "rest",
    )
    sim, marks = motor["simulation"], motor["marks"]
    per = [speed_fluctuation(sim, a, b) for a, b in zip(marks[:-1], marks[1:])]
    lines = [
        "\n".join(out),
        "",
        "Motor curve, from rest: δ and mean speed per cycle (cycles between passes "
        "through the position of maximum stored energy):",
        "",
        "| cycle | starts at t (s) | ω_mean (rad/s) | δ |",
        "|---|---|---|---|",
    ]
    for n, p in enumerate(per, 1):
        if n <= 6 or n % 5 == 0 or n == len(per):
            lines.append(f"| {n} | {p['t0']:.4f} | {p['omega_mean']:.5f} | {p['delta']:.5f} |")
    # the linear theory of the damping by the motor's droop (docs/dynamics.md)
    c = fw.mean_torque / (0.05 * fw.omega_m)
    j = fw.inertia_net + fw.machine_inertia["mean"]
    ratio = c / (j * fw.omega_m)
    lines += [
        "",
        f"Motor-curve damping: c = M_d/(s ω_m) = {c:.4f} N·m·s, c/(J ω_m) = "
        f"{ratio:.4f}; first-harmonic reduction 1/√(1 + (c/(J ω_m))²) = "
        f"{1 / np.sqrt(1 + ratio**2):.4f}; time constant J/c = {j / c:.4f} s.",
    ]
    return "\n".join(lines)


def validation_section() -> str:
    from tests.dynamics.test_dynamics import PENDULUM, free_slider_crank, lagrange

    rows = [
        "| case | method, rtol | simulated | RHS evaluations | result |",
        "|---|---|---|---|---|",
    ]
    sim = simulate(ks.load(PENDULUM), 25.0, method="DOP853", rtol=1e-10)
    cols, _ = sim.table(points=801)
    e = cols["energy.total"]
    drift = np.max(np.abs(e - e[0])) / np.ptp(cols["energy.kinetic"])
    rows.append(
        f"| pendulum, 30° amplitude | DOP853, 1e-10 | 25 s (≈ 21 periods) | {sim.nfev} | "
        f"max \\|E − E₀\\| / (T_max) = {drift:.1e} |"
    )
    sim = simulate(
        free_slider_crank("0"), 1.2, initial={"motor": (0.0, 80.0)}, method="DOP853", rtol=1e-9
    )
    cols, _ = sim.table(points=241)
    e = cols["energy.total"]
    rows.append(
        f"| slider-crank coasting from 80 rad/s | DOP853, 1e-9 | 1.2 s "
        f"({cols['motor.angle'][-1] / 360:.1f} rev) | {sim.nfev} | "
        f"max \\|E − E₀\\| / E = {np.max(np.abs(e - e[0])) / e.max():.1e} |"
    )
    sim = simulate(free_slider_crank("5"), 0.5, method="DOP853", rtol=1e-11)
    ref = lagrange(5.0, 0.5)
    t = np.linspace(0, 0.5, 51)
    y, x = sim.sample(t), ref.sol(t)
    rows.append(
        f"| slider-crank start-up, 5 N·m from rest | DOP853, 1e-11 | 0.5 s "
        f"(ω(0.5 s) = {x[1, -1]:.4f} rad/s) | {sim.nfev} | vs Lagrange: "
        f"max \\|Δφ\\| = {np.max(np.abs(y[:, 0] - x[0])):.1e} rad, max \\|Δω\\| = "
        f"{np.max(np.abs(y[:, 1] - x[1])):.1e} rad/s |"
    )
    return "\n".join(rows)


def main() -> None:
    if "--design" in sys.argv:
        print(design_section())
        return
    t0 = time.perf_counter()
    parts = [
        ("### Flywheel design (slotting machine)", design_section()),
        (
            "### Equivalent inertia and torque at the 12 course-design positions",
            equivalent_section(),
        ),
        ("### Verification by simulation", verification_section()),
        ("### Energy conservation and the Lagrange check", validation_section()),
    ]
    text = "\n\n".join(f"{h}\n\n{b}" for h, b in parts)
    print(text)
    if "--write" in sys.argv:
        doc = ROOT / "docs" / "dynamics.md"
        old = doc.read_text()
        i, j = old.index(BEGIN) + len(BEGIN), old.index(END)
        doc.write_text(old[:i] + "\n" + text + "\n" + old[j:])
    print(f"\n(generated in {time.perf_counter() - t0:.0f} s)", file=sys.stderr)


if __name__ == "__main__":
    main()
