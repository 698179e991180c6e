"""The compiled backend's stages against NumPy's: Φ_q's group blocks, γ, the inverse of the
driven crank's 3×3 block (the adjugate) and the consistent friction solution (its fixed
point and checks, ``friction.consistent``).

For each reference machine at 360 and 36,000 positions, the state of its own analysis
(the poses, rates and reactions that ``ks.analyze`` evaluates them at) is kept, and each
stage is timed on it with each backend in turns (medians of alternated samples); the two
backends' arrays are checked equal to the bit first.  Needs numba (``pip install
'kinetostatics[numba]'``).

    PYTHONPATH=src python tests/benchmarks/bench_kernels.py
"""

from __future__ import annotations

import re
import time

import numpy as np
from _common import ROOT

import kinetostatics as ks
from kinetostatics.base import kernels
from kinetostatics.base.linalg import small_inverse
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

    consistent = friction.consistent

    def keep_consistent(*args):
        kept["friction"] = args
        return consistent(*args)

    system.jacobian_blocks_all, system.gamma_all = keep_blocks, keep_gamma
    inverse.fr.consistent = keep_consistent
    try:
        ks.analyze(model, kinematics_only=True)
        blocks_state, gamma_state = kept["blocks"], kept["gamma"]
        ks.analyze(model)
    finally:
        system.jacobian_blocks_all, system.gamma_all = blocks, gamma
        inverse.fr.consistent = consistent
    return blocks_state, gamma_state, kept["friction"]


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
    blocks, ground = out
    parts = [p for d, lo, _ in blocks for p in (d, lo) if p is not None]
    return parts + ([] if ground is None else [ground])


def main() -> None:
    print("| mechanism | positions | stage | NumPy [ms] | numba [ms] | ratio |")
    print("|---|---|---|---|---|---|")
    for name in ("slider_crank", "slotting_machine"):
        for n in (360, 36_000):
            b, g, f = state(name, n)
            blocks = evaluation.jacobian_blocks_all(*b)[0]
            small = next(d for d, _, _ in blocks if d.shape[-1] <= 3)  # the crank's group
            k = small.shape[-1]
            stages = {
                "Φ_q blocks": lambda b=b: evaluation.jacobian_blocks_all(*b),
                "γ": lambda g=g: evaluation.gamma_all(*g),
                f"{k}×{k} block inverse": lambda a=small: small_inverse(a),
                "consistent friction": lambda f=f: friction.consistent(*f),
            }
            for label, fn in stages.items():
                out = {}
                for backend in ("numpy", "numba"):
                    kernels.set_backend(backend)
                    out[backend] = fn()
                kernels.set_backend("numpy")
                a, c = (arrays(out[k]) for k in ("numpy", "numba"))
                if not all(np.array_equal(x, y, equal_nan=True) for x, y in zip(a, c)):
                    raise SystemExit(f"{name}, {label}: the backends differ")
                t = timed(fn)
                print(
                    f"| {name} | {n:,} | {label} | {t['numpy'] * 1e3:.3g} | "
                    f"{t['numba'] * 1e3:.3g} | {t['numpy'] / t['numba']:.2g}× |"
                )


if __name__ == "__main__":
    main()
