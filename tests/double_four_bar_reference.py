"""Reference of the double four-bar mechanism (mechanisms/double_four_bar.yaml; IFToMM
benchmark problem A02 with N = 2; docs/benchmarks.md).

Two kinds of reference:

- the exact motion.  In its parallelogram mode every crank turns by the same angle θ and
  the couplers translate, so the linkage is a one-degree-of-freedom pendulum: with bars of
  mass m = 1 kg and length L = 1 m (J = m L²/12 about the centre), three cranks and two
  couplers, T = 3·½(m L²/3) θ̇² + 2·½ m L² θ̇² = 1.5 θ̇² and V = g (3·m L/2 + 2·m L) sin θ
  = 3.5 g sin θ, so 3 θ̈ = −3.5 g cos θ.  :func:`exact` integrates that scalar equation to
  1e-13 (independent of the program's multibody equations), and the energy integral
  1.5 θ̇² + 3.5 g sin θ = 1.5 + 3.5 g checks it;
- the published solution for N = 2 of Exudyn's test model of the problem, file
  main/pythonDev/TestModels/fourBarMechanismIftomm.py of the public repository
  jgerstmayr/EXUDYN ("double four-bar mechanism according to IFToMM benchmarks",
  J. Gerstmayr, 2021): the position and velocity of the tip B0 of the first crank at
  t = 10 s by generalized-α with steps h = 1e-3 … 1.25e-4, as stated in its comments.
  The values of its finest step are :data:`EXUDYN_B0`; the differences between its steps
  fall by 4 per halving (second order), so its last value is within about 1e-6 of the limit.

The benchmark library of the University of A Coruña states the problem for N = 40 and
gives its reference as a data file (A02_solution_data.txt), which was not available to
this work; no value of it is used here.
"""

from __future__ import annotations

import numpy as np

G = 9.81
THETA0, OMEGA0 = np.pi / 2, -1.0  # cranks vertical; B0 at 1 m/s along +x
T_END = 10.0
# (x, y, vx, vy) of B0 at t = 10 s for Exudyn's steps h (s), from its source's comments
EXUDYN_STEPS = {
    1e-3: (0.3284112372, 0.9445348375, 1.422958522, -0.4947565894),
    5e-4: (0.3284465114, 0.9445225721, 1.423028497, -0.494841072),
    2.5e-4: (0.3284552113, 0.9445195467, 1.423045728, -0.4948619021),
    1.25e-4: (0.3284573768, 0.9445187937, 1.423050003, -0.4948670827),
}
EXUDYN_B0 = np.array(EXUDYN_STEPS[1.25e-4])


def exact(t) -> tuple[np.ndarray, np.ndarray]:
    """(θ, θ̇) of the cranks at times ``t`` (s) from the reduced equation 3θ̈ = −3.5 g cos θ."""
    from scipy.integrate import solve_ivp

    t = np.atleast_1d(np.asarray(t, dtype=float))
    sol = solve_ivp(
        lambda _, y: [y[1], -3.5 * G * np.cos(y[0]) / 3.0],
        (0.0, float(np.max(t))),
        [THETA0, OMEGA0],
        method="DOP853",
        rtol=1e-13,
        atol=1e-13,
        dense_output=True,
    )
    theta, omega = sol.sol(t)
    return theta, omega


def b0(theta, omega) -> np.ndarray:
    """(x, y, vx, vy) of the crank tip B0 (crank pivot at the origin, L = 1 m)."""
    return np.array([np.cos(theta), np.sin(theta), -np.sin(theta) * omega, np.cos(theta) * omega])
