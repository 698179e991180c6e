"""The compiled backend's stages against NumPy's: Φ_q's group blocks, γ, the inverse of the
driven crank's 3×3 block (the adjugate), the consistent friction solution (its fixed
point and checks, ``friction.consistent``) and the kinematic plan's derivative stage with
the groups' condition numbers after it (``plan.planned_derivatives``: its whole-array
lines and ``condition_number`` on NumPy, the fused program, which computes both, on
numba: kinematics/fused.py).

For each reference machine at 360 and 36,000 positions, the state of its own analysis
(the poses, rates and reactions that ``ks.analyze`` evaluates them at) is kept, and each
stage is timed on it with each backend in turns (medians of alternated samples); the two
backends' arrays are checked first: equal to the bit, the derivative stage's within
1e-12 of each array's largest value (the compiled backend's contract: its eliminations'
row order may differ).  Needs numba (``pip install 'kinetostatics[numba]'``).

    PYTHONPATH=src python tests/benchmarks/bench_kernels.py [--first-use]

``--first-use`` prints instead what the backend's first use costs in a new process
(wall time of the slotting machine's first analysis on numba, then of its next eight,
the eighth making the fused stage): with numba's cache in an empty folder (everything
compiled), then again with it filled.
"""

from __future__ import annotations

import os
import re
import subprocess
import sys
import tempfile
import time

import numpy as np
from _common import ROOT

import kinetostatics as ks
from kinetostatics.analysis import pipeline
from kinetostatics.base import kernels
from kinetostatics.base.blocks import BlockFactor
from kinetostatics.base.linalg import small_inverse
from kinetostatics.kinematics import plan
from kinetostatics.kinetics import friction, inverse
from kinetostatics.structure import evaluation, system


def state(name: str, n: int):
    """(sets, layout, poses, rates, ψ̈) of the last evaluation in an analysis of
    ``mechanisms/<name>.yaml`` at ``n`` positions."""
    text = (ROOT / "mechanisms" / f"{name}.yaml").read_text()
    model = ks.loads(re.sub(r"positions: 360}", f"positions: {n}}}", text), f"{name}.yaml")
    kept = {}
    blocks, gamma = system.jacobian_blocks_all, system.gamma_all

    def keep_blocks(sets, layout, pe):
        kept["blocks"] = (sets, layout, pe)
        return blocks(sets, layout, pe)

    def keep_gamma(sets, n_rows, pe, ve, psi_dd):
        kept["gamma"] = (sets, n_rows, pe, ve, psi_dd)
        return gamma(sets, n_rows, pe, ve, psi_dd)

    consistent, planned = friction.consistent, plan.planned_derivatives

    def keep_consistent(*args):
        kept["friction"] = args
        return consistent(*args)

    def keep_planned(*args):
        kept["planned"] = args
        return planned(*args)

    system.jacobian_blocks_all, system.gamma_all = keep_blocks, keep_gamma
    inverse.fr.consistent, plan.planned_derivatives = keep_consistent, keep_planned
    after, plan.ENABLED = plan.PLAN_AFTER, False
    try:
        ks.analyze(model, kinematics_only=True)  # the general stage: its Φ_q and γ
        blocks_state, gamma_state = kept["blocks"], kept["gamma"]
        plan.PLAN_AFTER, plan.ENABLED = (0, 0), True  # the plan made at the next analysis
        ks.analyze(model)
    finally:
        system.jacobian_blocks_all, system.gamma_all = blocks, gamma
        inverse.fr.consistent, plan.planned_derivatives = consistent, planned
        plan.PLAN_AFTER, plan.ENABLED = after, True
    return blocks_state, gamma_state, kept["friction"], kept["planned"]


def timed(fn, rounds: int = 7) -> dict[str, float]:
    """Median time (s) of ``fn()`` per backend, the backends alternated."""
    times: dict[str, list[float]] = {"numpy": [], "numba": []}
    for name in times:  # warm: compiled and cached
        kernels.set_backend(name)
        fn()
    for _ in range(rounds):
        for name in times:
            kernels.set_backend(name)
            number, t0 = 0, time.perf_counter()
            while number < 3 or time.perf_counter() - t0 < 0.05:
                fn()
                number += 1
            times[name].append((time.perf_counter() - t0) / number)
    kernels.set_backend("numpy")
    return {k: float(np.median(v)) for k, v in times.items()}


def arrays(out) -> list[np.ndarray]:
    """The arrays of ``jacobian_blocks_all``'s (blocks, ground) or of γ."""
    if isinstance(out, np.ndarray):
        return [out]
    if isinstance(out, friction.FrictionSolution):
        return [out.x, out.e, out.status, out.iterations, out.reach]
    if len(out) == 4:  # the derivative stage: q̇, q̈, the blocks' inverses, the conditions
        inverses = out[2].inv if isinstance(out[2], BlockFactor) else []  # the rates alone
        return [out[0], out[1], *inverses, *out[3].values()]
    blocks, ground = out
    parts = [p for d, lo, _ in blocks for p in (d, lo) if p is not None]
    return parts + ([] if ground is None else [ground])


def _derivatives(system_, q, psi_d, psi_dd, factors=True):
    """The plan's derivative stage and the groups' condition numbers after it, as an
    analysis asks for them (on numba the fused program computes both; without
    ``factors``, as ``kinematics_only=True`` asks, its program of the rates alone)."""
    qd, qdd, lu = plan.planned_derivatives(system_, q, psi_d, psi_dd, factors)
    return qd, qdd, lu, pipeline._conditions(system_, q, lu)


def _same(a: np.ndarray, b: np.ndarray, to_scale: bool) -> bool:
    """Equal to the bit, or with ``to_scale`` within 1e-12 of ``a``'s largest |value|."""
    if not to_scale:
        return np.array_equal(a, b, equal_nan=True)
    return bool(np.allclose(a, b, rtol=0, atol=1e-12 * np.max(np.abs(a)), equal_nan=True))


FIRST_USE = """
import time
import kinetostatics as ks
ks.set_backend("numba")
model = ks.load("mechanisms/slotting_machine.yaml")
t = time.perf_counter(); ks.analyze(model); first = time.perf_counter() - t
t = time.perf_counter()
for _ in range(8):
    ks.analyze(model)
print(f"{first:.2f} s, then {time.perf_counter() - t:.2f} s")
"""


def first_use() -> None:
    """The first analyses' wall time in new processes, numba's cache empty then filled."""
    with tempfile.TemporaryDirectory() as cache:
        env = {**os.environ, "NUMBA_CACHE_DIR": cache}
        for when in ("empty cache (all compiled)", "cache filled"):
            out = subprocess.run(
                [sys.executable, "-c", FIRST_USE],
                env=env,
                cwd=ROOT,
                text=True,
                capture_output=True,
                check=True,
            )
            print(f"{when}: first analysis, then the next eight: {out.stdout.strip()}")


def main() -> None:
    if "--first-use" in sys.argv[1:]:
        first_use()
        return
    print("| mechanism | positions | stage | NumPy [ms] | numba [ms] | ratio |")
    print("|---|---|---|---|---|---|")
    for name in ("slider_crank", "slotting_machine"):
        for n in (360, 36_000):
            b, g, f, d = state(name, n)
            blocks = evaluation.jacobian_blocks_all(*b)[0]
            small = next(d for d, _, _ in blocks if d.shape[-1] <= 3)  # the crank's group
            k = small.shape[-1]
            stages = {
                "Φ_q blocks": lambda b=b: evaluation.jacobian_blocks_all(*b),
                "γ": lambda g=g: evaluation.gamma_all(*g),
                f"{k}×{k} block inverse": lambda a=small: small_inverse(a),
                "consistent friction": lambda f=f: friction.consistent(*f),
                "derivatives and conditions (planned)": lambda d=d: _derivatives(*d[:4]),
                "the same, the kinematics alone": lambda d=d: _derivatives(*d[:4], factors=False),
            }
            for label, fn in stages.items():
                out = {}
                for backend in ("numpy", "numba"):
                    kernels.set_backend(backend)
                    out[backend] = fn()
                kernels.set_backend("numpy")
                a, c = (arrays(out[k]) for k in ("numpy", "numba"))
                if len(a) != len(c):  # the rates alone on numba: the inverses not kept
                    a = a[:2] + a[len(a) - len(c) + 2 :]
                close = label.startswith(("derivatives", "the same"))
                if not all(_same(x, y, close) for x, y in zip(a, c)):
                    raise SystemExit(f"{name}, {label}: the backends differ")
                t = timed(fn)
                print(
                    f"| {name} | {n:,} | {label} | {t['numpy'] * 1e3:.3g} | "
                    f"{t['numba'] * 1e3:.3g} | {t['numpy'] / t['numba']:.2g}× |"
                )


if __name__ == "__main__":
    main()
