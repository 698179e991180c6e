"""Andrews' squeezer mechanism (mechanisms/andrews_squeezer.yaml): the published reference
values and the source's relative angles of a state of the model (tests/dynamics/test_andrews.py,
tests/benchmarks/bench_andrews.py).

Source: the "andrews" problem of the Test Set for IVP Solvers (University of Bari,
revision "andrews.F,v 1.2 2006/10/02"; after Hairer & Wanner, Solving ODEs II, §VII.7), as
redistributed in the R package deTestSet (Ex_andrews.f, ex_andrews.R).  The solution at
t = 0.03 s was computed there with PSIDE, rtol = atol = 1e-14, on a Cray C90 in Cray double
precision: 1112 steps, 26000 f evaluations, 56.74 s of CPU time.
"""

from __future__ import annotations

import numpy as np

NAMES = ("beta", "Theta", "gamma", "Phi", "delta", "Omega", "epsilon")

INITIAL = np.array(  # y(1..7) at t = 0, at rest
    [
        -0.0617138900142764496358948458001,
        0.0,
        0.455279819163070380255912382449,
        0.222668390165885884674473185609,
        0.487364979543842550225598953530,
        -0.222668390165885884674473185609,
        1.23054744454982119249735015568,
    ]
)
INITIAL_ACCELERATION = np.array(  # y(15..21) at t = 0
    [14222.4439199541138705911625887, -10666.8329399655854029433719415, 0, 0, 0, 0, 0]
)
INITIAL_LAMBDA = np.array(  # y(22..27): multipliers of g1..g6 at t = 0
    [98.5668703962410896057654982170, -6.12268834425566265503114393122, 0, 0, 0, 0]
)
T_END = 0.03
FINAL = np.array(  # y(1..7) at t = 0.03 s
    [
        0.1581077119629904e2,
        -0.1575637105984298e2,
        0.4082224013073101e-1,
        -0.5347301163226948e0,
        0.5244099658805304e0,
        0.5347301163226948e0,
        0.1048080741042263e1,
    ]
)
FINAL_SPEED = np.array(  # y(8..14) at t = 0.03 s
    [
        0.1139920302151208e4,
        -0.1424379294994111e4,
        0.1103291221937134e2,
        0.1929337464421385e2,
        0.5735699284790808e0,
        -0.1929337464421385e2,
        0.3231791658026955e0,
    ]
)


def relative_angles(system, x: np.ndarray) -> np.ndarray:
    """The source's seven angles (or their rates) from q (or q̇) of the model: body k's
    absolute angle is β, β + Θ, γ, Φ + δ, δ, Ω + ε, ε (mechanisms/andrews_squeezer.yaml)."""
    th = {n: x[..., 3 * k + 2] for k, n in enumerate(system.links)}
    return np.stack(
        [
            th["body1"],
            th["body2"] - th["body1"],
            th["body3"],
            th["body4"] - th["body5"],
            th["body5"],
            th["body6"] - th["body7"],
            th["body7"],
        ],
        axis=-1,
    )


def state_at(sim, t: float) -> tuple[np.ndarray, np.ndarray]:
    """(q, q̇) of a simulation of the model at time t."""
    dyn = sim.dynamics
    y = sim.sample([t])[0]
    ev = dyn.evaluate(t, y[: dyn.n_f], y[dyn.n_f : 2 * dyn.n_f])
    return ev.q, ev.qd
