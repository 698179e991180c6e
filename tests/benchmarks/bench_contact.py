"""Speed against error of the contact–impact clearance model (b): the swing mechanism
(mechanisms/ammunition_swing.yaml) with e1 = e2 = 0.5 mm, Hertzian stiffness, over its
start-up 0–30 ms (the unloaded start and the contacts settling; the costliest part of
a run).  Errors of the arm's angle, velocity and acceleration at 61 times against a
tight reference (BDF, rtol 1e-8, checked against Radau at rtol 1e-7; Radau at 1e-8
needs ~10× BDF's evaluations).  Rows with the
stiffness scaled down show what a softer contact saves and costs (error against the
Hertzian reference).

    python tests/benchmarks/bench_contact.py            # print the table (~10 min)
    python tests/benchmarks/bench_contact.py --write    # and put it into docs/clearance.md
    python tests/benchmarks/bench_contact.py --profile [--write]   # one RHS's cost (~1 min)
"""

from __future__ import annotations

import sys
import time

import numpy as np
from _common import ROOT

sys.path.insert(0, str(ROOT / "docs" / "scripts"))
from clearance_values import b_run, write_block  # noqa: E402

from kinetostatics.dynamics.contact import ContactLaw  # noqa: E402

T_END, E = 0.03, 0.5e-3
CASES = [
    ("RK45", 1e-4, 1.0),
    ("RK45", 1e-5, 1.0),
    ("LSODA", 1e-5, 1.0),
    ("Radau", 1e-5, 1.0),
    ("BDF", 1e-3, 1.0),
    ("BDF", 1e-4, 1.0),
    ("BDF", 1e-5, 1.0),
    ("BDF", 1e-6, 1.0),
    ("BDF", 1e-7, 1.0),
    ("BDF", 1e-5, 0.1),
    ("BDF", 1e-5, 0.01),
]
BEGIN, END = "<!-- bench_contact: begin -->", "<!-- bench_contact: end -->"


def run(method: str, rtol: float, scale: float = 1.0):
    law = ContactLaw(journal_radius=0.02, restitution=0.9, scale=scale)
    r = b_run(E, np.linspace(0.0, T_END, 61), until=T_END, law=law, method=method, rtol=rtol)
    return r, float(r["wall"][0]), int(r["nfev"][0])


def profile(until: float = 0.01) -> str:
    """Cost of one right-hand side and where it goes (cProfile, BDF rtol 1e-5 over
    0–``until`` s), and the evaluations with the finite-difference Jacobian instead."""
    import cProfile
    import pstats

    import kinetostatics as ks
    from kinetostatics.dynamics.clearance import with_clearance
    from kinetostatics.dynamics.contact import simulate_contact

    law = ContactLaw(journal_radius=0.02, restitution=0.9)
    model = with_clearance(
        ks.load(ROOT / "mechanisms" / "ammunition_swing.yaml"), size=E, kind="contact", contact=law
    )
    counts = {}
    for jac in (True, False):
        t0 = time.perf_counter()
        n = simulate_contact(model, until, method="BDF", rtol=1e-5, jacobian=jac).nfev
        counts[jac] = (n, time.perf_counter() - t0)
    prof = cProfile.Profile()
    prof.enable()
    n = simulate_contact(model, until, method="BDF", rtol=1e-5).nfev
    prof.disable()
    stats = pstats.Stats(prof).stats

    def cumulative(module: str, name: str) -> float:
        return sum(v[3] for f, v in stats.items() if f[0].endswith(module) and f[2] == name)

    total = cumulative("dynamics/engine.py", "evaluate")
    share = {
        "positions": cumulative("dynamics/engine.py", "positions") / total,
        "derivatives": cumulative("kinematics/derivatives.py", "derivatives") / total,
        "kinetics": cumulative("inverse.py", "kinetics") / total,
    }
    return (
        f"Swing, e = 0.5 mm, BDF rtol 1e-5, 0–{until * 1e3:g} ms: one right-hand side "
        f"{counts[True][1] / counts[True][0] * 1e3:.1f} ms; of an evaluation (cProfile, "
        f"{n} of them) positions {share['positions']:.0%}, velocities and "
        f"accelerations {share['derivatives']:.0%}, Newton–Euler "
        f"{share['kinetics']:.0%}. Evaluations with the analytic contact Jacobian: "
        f"{counts[True][0]} ({counts[True][1]:.1f} s); with solve_ivp's finite "
        f"differences: {counts[False][0]} ({counts[False][1]:.1f} s)."
    )


def main() -> None:
    if "--profile" in sys.argv:
        text = profile()
        print(text)
        if "--write" in sys.argv:
            write_block(
                "<!-- bench_contact_profile: begin -->", "<!-- bench_contact_profile: end -->", text
            )
        return
    ref, wall_ref, n_ref = run("BDF", 1e-8)
    check, _, _ = run("Radau", 1e-7)
    a_scale = np.max(np.abs(ref["alpha"]))

    def errors(r):
        return (
            np.max(np.abs(r["theta"] - ref["theta"])),
            np.max(np.abs(r["omega"] - ref["omega"])),
            np.max(np.abs(r["alpha"] - ref["alpha"])) / a_scale,
        )

    lines = [
        f"Reference: BDF, rtol 1e-8 ({wall_ref:.0f} s, {n_ref} evaluations); against "
        "Radau at rtol 1e-7: max |Δθ| = {:.1e} rad, max |Δω| = {:.1e} rad/s, "
        "max |Δα| / max |α| = {:.1e}.".format(*errors(check)),
        "",
        "| method | rtol | stiffness × | wall time (s) | RHS evaluations | "
        "max \\|Δθ\\| (rad) | max \\|Δω\\| (rad/s) | max \\|Δα\\| / max \\|α\\| |",
        "|---|---|---|---|---|---|---|---|",
    ]
    for method, rtol, scale in CASES:
        r, wall, nfev = run(method, rtol, scale)
        lines.append(
            f"| {method} | {rtol:.0e} | {scale:g} | {wall:.1f} | {nfev} | "
            "{:.1e} | {:.1e} | {:.1e} |".format(*errors(r))
        )
        print(lines[-1], file=sys.stderr, flush=True)
    text = "\n".join(lines)
    print(text)
    if "--write" in sys.argv:
        write_block(BEGIN, END, text)


if __name__ == "__main__":
    main()
